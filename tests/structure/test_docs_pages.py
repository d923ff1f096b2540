"""The docs read as a manual: key tables generated from the case models, a README a newcomer can scan, pages of
bounded length, no history (dates, issue numbers, seed labels) in code, cases or docs, and an SPH deck reference
that lists exactly the keys the engine's parser reads."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from orchestrator import docs_tables
from orchestrator.kinds import get_kind, kind_names
from paths import REPO

DOCS = REPO / "docs"
README = REPO / "README.md"
SPH_README = REPO / "engines" / "sph" / "README.md"
SPH_SOURCES = REPO / "engines" / "sph" / "src"

#: Longest README, lines; longest cell of its results table, characters; longest docs page, lines.
README_LINES, RESULT_CELL, PAGE_LINES = 150, 200, 400
#: Trees where no history may stand, and what history looks like (the same as grep "issue [0-9]\|seed 00\|2026-").
HISTORY_TREES = ("orchestrator", "engines", "cases", "docs", "README.md")
HISTORY = re.compile(r"issue [0-9]|seed 00|2026-")
#: Folders that hold build products or caches, not sources.
SKIPPED_FOLDERS = {"build", "__pycache__", ".pytest_cache", "node_modules"}


def _pages_with_tables() -> dict[str, list[Path]]:
    pages: dict[str, list[Path]] = {}
    for page in sorted(DOCS.glob("*.md")):
        for kind in docs_tables.marked_kinds(page.read_text()):
            pages.setdefault(kind, []).append(page)
    return pages


@pytest.mark.parametrize("kind", kind_names())
def test_a_kind_page_holds_the_table_of_its_model(kind):
    pages = _pages_with_tables().get(kind, [])
    assert pages, f"no docs page holds <!-- keys:{kind} begin -->: every kind has a page with its key table"
    for page in pages:
        text = page.read_text()
        assert docs_tables.with_table(text, kind, docs_tables.kind_table(kind)) == text, (
            f"{page.name}: the key table of {kind} differs from its case model; run "
            "python -m orchestrator.docs_tables --write")


def test_every_table_marker_names_a_registered_kind():
    unknown = sorted(set(_pages_with_tables()) - set(kind_names()))
    assert not unknown, f"docs pages hold key tables of kinds that are not registered: {unknown}"
    assert docs_tables.stale_tables() == []


def test_the_table_lists_every_key_with_its_unit_and_default():
    rows = {row.key: row for row in docs_tables.key_rows(get_kind("impact").case_model.load())}
    assert rows["simulation.duration"].unit == "s" and rows["simulation.duration"].default == "required"
    assert rows["spheres[].velocity"].unit == "m/s" and rows["spheres[].velocity"].default == "`[0.0, 0.0, 0.0]`"
    assert rows["materials.<name>.young_modulus"].meaning == "Young's modulus E"
    assert rows["plane"].default == "none" and rows["plane"].meaning.startswith("table: ")
    assert "`\"exact\"`" in rows["model.damping"].meaning


@pytest.mark.parametrize("kind", ["ejector_drill", "ejector_feed"])
def test_every_drill_key_has_a_unit_and_a_meaning(kind):
    rows = [row for row in docs_tables.key_rows(get_kind(kind).case_model.load()) if row.key.startswith("drill.")]
    assert len(rows) == 35
    assert [row.key for row in rows if not (row.unit and row.meaning)] == []
    units = {row.key: row.unit for row in rows}
    assert (units["drill.rho"], units["drill.mu"], units["drill.front_area"]) == ("kg/m^3", "Pa s", "m^2")
    assert (units["drill.n_holes"], units["drill.nozzle_angle_deg"], units["drill.d_bore"]) == ("-", "deg", "m")


@pytest.mark.parametrize("description, unit, meaning", [
    ("m", "m", ""),
    ("Young's modulus E, Pa", "Pa", "Young's modulus E"),
    ("time step as a fraction of the critical step, - (0.05: >= 40 steps per contact)", "-",
     "time step as a fraction of the critical step (0.05: >= 40 steps per contact)"),
    ("N: the shear wave crosses the sample within 1/N of the period; sets the density, -", "-",
     "N: the shear wave crosses the sample within 1/N of the period; sets the density"),
    ("delta_b, m: std (normal) or half-width (uniform)", "m", "delta_b, m: std (normal) or half-width (uniform)"),
    ("mode viscosity eta_i, Pa s (G_i = eta_i / lambda_i)", "Pa s", "mode viscosity eta_i (G_i = eta_i / lambda_i)"),
    ("adaptive step: dt <= cfl h / (c0 + |v|max), - (default 0.25)", "-",
     "adaptive step: dt <= cfl h / (c0 + |v|max) (default 0.25)"),
    ("seed of every random draw (particle cloud)", "", "seed of every random draw (particle cloud)"),
    (None, "", ""),
])
def test_units_come_from_the_description(description, unit, meaning):
    assert docs_tables.unit_and_meaning(description) == (unit, meaning)


def test_write_regenerates_a_stale_table(tmp_path):
    kind = kind_names()[0]
    begin, end = docs_tables.BEGIN.format(kind=kind), docs_tables.END.format(kind=kind)
    page = tmp_path / "page.md"
    page.write_text(f"# A page\n\n{begin}\n| old | table |\n{end}\n\nafter\n")
    assert docs_tables.stale_tables(tmp_path) == [f"page.md: {kind}"]
    assert docs_tables.write_tables(tmp_path) == [page]
    assert docs_tables.stale_tables(tmp_path) == []
    assert page.read_text().endswith(f"{end}\n\nafter\n")


def _results_rows() -> list[list[str]]:
    text = README.read_text()
    section = text.split("\n## Results", 1)[1].split("\n## ", 1)[0]
    rows = [line for line in section.splitlines() if line.startswith("|")]
    return [[cell.strip() for cell in re.split(r"(?<!\\)\|", row)[1:-1]] for row in rows[2:]]


def test_the_readme_is_short_and_its_results_table_scannable():
    lines = README.read_text().splitlines()
    assert len(lines) <= README_LINES, f"README.md has {len(lines)} lines; allowed: {README_LINES}"
    rows = _results_rows()
    assert len(rows) >= 5
    for row in rows:
        assert all(len(cell) <= RESULT_CELL for cell in row), f"a results cell over {RESULT_CELL} characters: {row}"
        links = re.findall(r"\]\((docs/[^)#]+)", " ".join(row))
        assert links, f"a results row without a link to its docs page: {row}"
        assert all((REPO / link).is_file() for link in links), links


def test_docs_pages_are_short():
    long = {page.name: n for page in DOCS.glob("*.md") if (n := len(page.read_text().splitlines())) > PAGE_LINES}
    assert not long, f"docs pages over {PAGE_LINES} lines: {long}"


def _text_files(tree: Path):
    paths = [tree] if tree.is_file() else sorted(tree.rglob("*"))
    for path in paths:
        if not path.is_file() or SKIPPED_FOLDERS & set(path.relative_to(REPO).parts):
            continue
        data = path.read_bytes()
        if b"\0" in data[:8192]:
            continue
        try:
            yield path, data.decode()
        except UnicodeDecodeError:
            continue


def test_no_history_in_code_cases_or_docs():
    found = [f"{path.relative_to(REPO)}:{n}: {line.strip()[:100]}"
             for tree in HISTORY_TREES for path, text in _text_files(REPO / tree)
             for n, line in enumerate(text.splitlines(), 1) if HISTORY.search(line)]
    assert not found, "dates, issue numbers or seed labels (cite papers by author and year):\n" + "\n".join(found)


def _parser_keys() -> tuple[set[str], set[str]]:
    """(every key name the deck parser accepts, the top-level ones), from the engine's C++ source: the key lists
    of check_keys calls, the allowed lists of the material parser and each material model's keys()."""
    source = "\n".join(p.read_text() for p in sorted(SPH_SOURCES.rglob("*")) if p.suffix in (".cpp", ".h"))
    literal_list = r'\{\s*("[A-Za-z0-9_]+"(?:\s*,\s*"[A-Za-z0-9_]+")*)\s*\}'
    lists = re.findall(r"check_keys\([^;{]*?" + literal_list, source)
    lists += re.findall(r"std::vector<std::string> allowed = " + literal_list, source)
    lists += re.findall(r"keys\(\)\s*\{\s*return " + literal_list, source)
    lists += re.findall(r"\.objects\([^;{]*?" + literal_list, source)
    top = re.findall(r'check_keys\(\s*j\s*,\s*""\s*,\s*' + literal_list, source)
    names = lambda found: {name for group in found for name in re.findall(r'"([A-Za-z0-9_]+)"', group)}  # noqa: E731
    return names(lists), names(top)


def _readme_deck_keys() -> list[str]:
    text = SPH_README.read_text()
    section = text.split("\n## Deck reference", 1)[1].split("\n## ", 1)[0]
    keys = []
    for line in section.splitlines():
        if line.startswith("| `"):
            keys += re.findall(r"`([A-Za-z0-9_.\[\]]+)`", line.split("|")[1])
    return keys


def test_the_sph_readme_lists_every_deck_key_the_parser_reads():
    keys, top = _parser_keys()
    assert "dimension" in top and "t_end" in top and "lambda" in keys, "the parser's key lists were not found"
    listed = _readme_deck_keys()
    leaves = {re.split(r"[.\]]", key)[-1] for key in listed}
    assert leaves == keys, (f"deck keys the parser reads but engines/sph/README.md does not list: {sorted(keys - leaves)}; "
                            f"listed but not read: {sorted(leaves - keys)}")
    assert {key for key in listed if not re.search(r"[.\[]", key)} == top


def test_the_sph_readme_names_only_files_that_exist():
    text = SPH_README.read_text()
    named = set(re.findall(r"`((?:src|tests|bench)/[A-Za-z0-9_./*-]+)`", text))
    missing = [name for name in sorted(named) if not list(SPH_README.parent.glob(name)) and not list(REPO.glob(name))]
    assert not missing, f"engines/sph/README.md names files that do not exist: {missing}"
    assert "DESIGN.md" not in text
