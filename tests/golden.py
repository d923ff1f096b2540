"""Golden-file comparison that does not depend on the last bits of a float.

A rendered deck holds numbers computed through numpy (and so through whatever
BLAS kernel the CPU picks: OPENBLAS_CORETYPE changes the last digits of a
damping constant). ``assert_matches_golden`` splits both texts into text and
numbers: the text must be equal character for character, the numbers equal
within a relative tolerance (default 1e-9, with an absolute floor of 1e-300
so that a computed zero matches a stored one). On a mismatch it names the
first differing line and both values.

Regenerate a golden file after an intended change with UPDATE_GOLDEN=1.
"""

from __future__ import annotations

import math
import os
import re
from pathlib import Path

#: Relative tolerance of a number in a golden file, -.
REL = 1e-9
#: Absolute tolerance (numbers that are zero up to rounding), in the number's unit.
ABS = 1e-300

# A decimal number not glued to an identifier or another number's digits (plane0, c_pairs, %.17g, 2023.02a stay
# text); a minus right before it belongs to it unless it follows a letter or digit (x-1: text "x-", number 1).
NUMBER = re.compile(r"(?<![\w.])-?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?(?![\w.])")


def tokens(line: str) -> list[str | float]:
    """A line as alternating text (str) and number (float) tokens; text between numbers kept verbatim."""
    out: list[str | float] = []
    position = 0
    for match in NUMBER.finditer(line):
        out.append(line[position:match.start()])
        out.append(float(match.group()))
        position = match.end()
    out.append(line[position:])
    return out


def first_difference(expected: str, actual: str, rel: float = REL, abs_tol: float = ABS) -> str | None:
    """None if the texts match (text exactly, numbers within rel/abs_tol), else where and how they differ."""
    want, got = expected.splitlines(), actual.splitlines()
    for number, (line_want, line_got) in enumerate(zip(want, got), start=1):
        a, b = tokens(line_want), tokens(line_got)
        if len(a) != len(b):
            return f"line {number}: expected {line_want!r}, got {line_got!r}"
        for x, y in zip(a, b):
            if isinstance(x, str) != isinstance(y, str):
                return f"line {number}: expected {line_want!r}, got {line_got!r}"
            if isinstance(x, str):
                if x != y:
                    return f"line {number}: text {x!r} expected, got {y!r} (line {line_got!r})"
            elif not math.isclose(x, y, rel_tol=rel, abs_tol=abs_tol):
                return (f"line {number}: number {x!r} expected, got {y!r} (relative difference "
                        f"{abs(x - y) / max(abs(x), abs(y)):.3g} > {rel:g}); line {line_got!r}")
    if len(want) != len(got):
        number = min(len(want), len(got)) + 1
        extra = want[number - 1] if len(want) > len(got) else got[number - 1]
        return (f"line {number}: expected {len(want)} lines, got {len(got)}; first unmatched line {extra!r}")
    if expected.endswith("\n") != actual.endswith("\n"):
        return "the texts differ in the final newline"
    return None


def assert_matches_golden(rendered: str, path: Path, rel: float = REL, abs_tol: float = ABS) -> None:
    """Assert rendered matches the golden file at path (text exact, numbers within rel); UPDATE_GOLDEN=1 rewrites it."""
    path = Path(path)
    if os.environ.get("UPDATE_GOLDEN"):
        path.write_text(rendered)
    difference = first_difference(path.read_text(), rendered, rel, abs_tol)
    assert difference is None, f"{path.name} differs from the rendered text: {difference}"
