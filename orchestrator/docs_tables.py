"""Reference tables of the case keys (key, unit, default, meaning), generated from each kind's pydantic case model.

A docs page holds a kind's table between the markers ``<!-- keys:KIND begin -->`` and ``<!-- keys:KIND end -->``.
``python -m orchestrator.docs_tables --write`` regenerates every marked table; ``--check`` (the default) lists the
pages whose table differs from its model and exits 1. The unit of a key is the one its field description states
as a clause of its own ("Young's modulus E, Pa"; "R / dx, -"); a description without one gives no unit.
"""

from __future__ import annotations

import re
import sys
import types
import typing
from dataclasses import dataclass
from pathlib import Path

from pydantic import BaseModel
from pydantic_core import PydanticUndefined

from orchestrator.kinds import get_kind, kind_names

#: The docs folder of the source tree.
DOCS = Path(__file__).resolve().parent.parent / "docs"
#: The opening and closing markers of a kind's table; {kind} is the kind's registered name.
BEGIN, END = "<!-- keys:{kind} begin -->", "<!-- keys:{kind} end -->"
_MARKER = re.compile(r"<!-- keys:([a-z0-9_]+) begin -->")  # kind names are lower case; KIND in prose is no marker

_BASE_UNIT = r"(?:kg|m|mm|s|Pa|N|J|W|K|rad|deg|l|min|Hz|1)(?:\^-?\d)?"
#: A unit as the case models write it: "-" (dimensionless), "m", "m/s", "kg/m^3", "Pa s", "l/min", "1/s", ...
UNIT = re.compile(rf"^(?:-|{_BASE_UNIT}(?:[ /]{_BASE_UNIT})*)(?= of |$)")
_TRAILING_NOTE = re.compile(r"\s*\([^()]*\)\s*$")


@dataclass(frozen=True)
class KeyRow:
    """One row of a key table: the dotted key, its unit, its default as TOML text and what it means."""

    key: str
    unit: str
    default: str
    meaning: str


def _clauses(text: str) -> list[tuple[int, int, str]]:
    """(start, end, the delimiter after it) of the clauses of a text, split at ", ", "; " and ": " outside brackets."""
    out, depth, start = [], 0, 0
    for i, char in enumerate(text):
        depth += (char in "([") - (char in ")]")
        if depth == 0 and char in ",;:" and text[i + 1:i + 2] == " ":
            out.append((start, i, char))
            start = i + 2
    out.append((start, len(text), ""))
    return out


def unit_and_meaning(description: str | None) -> tuple[str, str]:
    """(unit, meaning) of a field description: the first clause that is a unit alone, and the text without it.

    Clauses are separated by ", ", "; " or ": " outside brackets; a clause's trailing "(...)" note does not count,
    and a first clause followed by ": " is a label ("N: the shear wave ..."), not a unit. A unit clause at the end
    is cut from the meaning (its note kept); elsewhere the description stays whole.
    """

    text = " ".join((description or "").split())
    clauses = _clauses(text)
    for i, (start, end, delimiter) in enumerate(clauses):
        clause = text[start:end].strip()
        bare = _TRAILING_NOTE.sub("", clause) if clause.endswith(")") else clause
        match = UNIT.match(bare)
        if not match or (i == 0 and delimiter == ":"):
            continue
        unit = match.group(0)
        note = clause[len(unit):].strip()
        if len(clauses) == 1:
            return unit, note
        if i + 1 == len(clauses) and (not note or note.startswith("(")):
            return unit, (text[:start - 2] + (f" {note}" if note else "")).strip()
        return unit, text
    return "", text


def _unwrap(annotation):
    """annotation without Annotated[...] and without None in a union (X | None -> X)."""
    while typing.get_origin(annotation) is typing.Annotated:
        annotation = typing.get_args(annotation)[0]
    if typing.get_origin(annotation) in (typing.Union, types.UnionType):
        args = [a for a in typing.get_args(annotation) if a is not type(None)]
        if len(args) == 1:
            return _unwrap(args[0])
    return annotation


def _nested(annotation) -> tuple[str, type[BaseModel]] | None:
    """('table' | 'array' | 'map', model) when a field holds a model, an array of them or a name -> model map."""
    inner = _unwrap(annotation)
    if isinstance(inner, type) and issubclass(inner, BaseModel):
        return "table", inner
    origin, args = typing.get_origin(inner), [_unwrap(a) for a in typing.get_args(inner)]
    if origin in (tuple, list) and args and isinstance(args[0], type) and issubclass(args[0], BaseModel):
        return "array", args[0]
    if origin is dict and len(args) == 2 and isinstance(args[1], type) and issubclass(args[1], BaseModel):
        return "map", args[1]
    return None


def _literals(annotation) -> tuple:
    """The allowed values of a Literal field (also inside Optional), else ()."""
    inner = _unwrap(annotation)
    return typing.get_args(inner) if typing.get_origin(inner) is typing.Literal else ()


def toml_text(value) -> str:
    """A default value as it is written in a case file (TOML)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, (tuple, list)):
        return "[" + ", ".join(toml_text(v) for v in value) + "]"
    if isinstance(value, (str, Path)):
        return f'"{value}"'
    return str(value)


def _default(field) -> str:
    """The default column: 'required', 'none', or the default's TOML text in backticks."""
    if field.is_required():
        return "required"
    value = field.get_default(call_default_factory=True)
    if value is None or value is PydanticUndefined:
        return "none"
    return f"`{toml_text(value)}`"


def _summary(model: type[BaseModel]) -> str:
    """The first paragraph of a model's docstring, on one line."""
    doc = (model.__doc__ or "").strip()
    return " ".join(doc.split("\n\n")[0].split())


def _table_row(key: str, field, shape: str, model: type[BaseModel]) -> KeyRow:
    """The row of a field that holds a table, an array of tables or a map of tables."""
    required = field.is_required()
    default = "required" if required else ("none" if field.get_default(call_default_factory=True) is None else "")
    what = {"table": "table", "array": f"array of tables [[{key}]]",
            "map": "tables by name"}[shape]
    meaning = field.description or _summary(model)
    return KeyRow(key, "", default, f"{what}: {meaning}" if meaning else what)


def key_rows(model: type[BaseModel], prefix: str = "") -> list[KeyRow]:
    """Every key of a case model, depth first in the model's field order: tables and the keys inside them.

    Keys inside an array of tables read `name[].key`, inside a map of tables `name.<name>.key`.
    """

    rows = []
    for name, field in model.model_fields.items():
        key = prefix + name
        nested = _nested(field.annotation)
        if nested is not None:
            shape, inner = nested
            rows.append(_table_row(key, field, shape, inner))
            below = {"table": f"{key}.", "array": f"{key}[].", "map": f"{key}.<name>."}[shape]
            rows.extend(key_rows(inner, below))
            continue
        unit, meaning = unit_and_meaning(field.description)
        allowed = _literals(field.annotation)
        if allowed:
            listed = ", ".join(f"`{toml_text(v)}`" for v in allowed)
            meaning = f"{meaning} (one of {listed})" if meaning else f"one of {listed}"
        rows.append(KeyRow(key, unit, _default(field), meaning))
    return rows


def _cell(text: str) -> str:
    """Text safe inside a markdown table cell."""
    return " ".join(text.split()).replace("|", "\\|")


def key_table(model: type[BaseModel]) -> str:
    """The markdown table (key, unit, default, meaning) of a case model, one row per key."""
    lines = ["| key | unit | default | meaning |", "|---|---|---|---|"]
    for row in key_rows(model):
        lines.append(f"| `{row.key}` | {_cell(row.unit)} | {_cell(row.default)} | {_cell(row.meaning)} |")
    return "\n".join(lines) + "\n"


def kind_table(kind: str) -> str:
    """The key table of a registered kind's case model."""
    return key_table(get_kind(kind).case_model.load())


def marked_kinds(text: str) -> list[str]:
    """The kinds whose table markers a page holds, in order."""
    return _MARKER.findall(text)


def with_table(text: str, kind: str, table: str) -> str:
    """The page text with the kind's marked table replaced by `table` (ValueError when a marker is missing)."""
    begin, end = BEGIN.format(kind=kind), END.format(kind=kind)
    start, stop = text.find(begin), text.find(end)
    if start < 0 or stop < start:
        raise ValueError(f"the page has no {begin} ... {end} pair")
    return text[:start + len(begin)] + "\n" + table + text[stop:]


def stale_tables(docs: Path = DOCS) -> list[str]:
    """'page: kind' for every marked table that differs from its model or names a kind that is not registered."""
    known, stale = set(kind_names()), []
    for page in sorted(docs.glob("*.md")):
        text = page.read_text()
        for kind in marked_kinds(text):
            if kind not in known:
                stale.append(f"{page.name}: {kind} (no such kind; registered: {', '.join(sorted(known))})")
            elif with_table(text, kind, kind_table(kind)) != text:
                stale.append(f"{page.name}: {kind}")
    return stale


def write_tables(docs: Path = DOCS) -> list[Path]:
    """Regenerate every marked table of the registered kinds in docs/*.md; returns the pages changed."""
    known, changed = set(kind_names()), []
    for page in sorted(docs.glob("*.md")):
        text = page.read_text()
        new = text
        for kind in marked_kinds(text):
            if kind in known:
                new = with_table(new, kind, kind_table(kind))
        if new != text:
            page.write_text(new)
            changed.append(page)
    return changed


def main(argv: list[str] | None = None) -> int:
    """`--write` regenerates the tables, `--check` (the default) lists stale ones; exit code 0, 1 stale, 2 usage."""
    args = sys.argv[1:] if argv is None else argv
    if args not in ([], ["--check"], ["--write"]):
        print("error: usage: python -m orchestrator.docs_tables [--check | --write]", file=sys.stderr)
        return 2
    if args == ["--write"]:
        for page in write_tables():
            print(f"wrote {page.relative_to(DOCS.parent)}")
        return 0
    stale = stale_tables()
    for line in stale:
        print(f"stale key table: {line}")
    if stale:
        print("error: key tables differ from the case models; run python -m orchestrator.docs_tables --write",
              file=sys.stderr)
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main())
