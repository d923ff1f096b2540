"""The smd/tlsph card of a LAMMPS MACHDYN deck read back as numbers (the solid kinds' deck tests)."""

import re


def pair_coeff_blocks(deck: str) -> dict[str, list[float]]:
    """The type-1 pair_coeff card's keyword blocks as numbers, e.g. {'*COMMON': [rho0, E, ...], '*EOS_SHOCK': [...]}
    (with or without the hybrid style's 'smd/tlsph' word)."""
    text = re.search(r"^pair_coeff\s+1 1 (?:smd/tlsph )?(.*?\*END)", deck.replace("&\n", " "),
                     re.MULTILINE | re.DOTALL).group(1)
    blocks, key = {}, None
    for word in text.split():
        if word.startswith("*"):
            key = word
            blocks[key] = []
        else:
            blocks[key].append(float(word))
    return blocks
