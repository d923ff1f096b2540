"""The generic layers name no kind (pytest's core and its plug-ins are the model): run.py, runh5.py, workflows/,
study/, cli/, case/ and scene/ loop over the kinds the registry holds and the capabilities they declare
(kinds.base.Kind); none of their modules imports orchestrator.kinds.<kind>, holds a string equal to a registered
kind's name, or compares a kind with a literal (kind == "..."). Checked on the modules' syntax trees (ast)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from orchestrator.kinds import kind_names
from paths import REPO

PACKAGE = REPO / "orchestrator"
GENERIC = ["run.py", "runh5.py", "workflows", "study", "cli", "case", "scene"]
#: Modules that still name a kind, with the reason; clear a line when its module is generic.
KNOWN: dict[str, str] = {}


def generic_modules() -> list[Path]:
    """Every module file of the generic layers."""
    files = []
    for name in GENERIC:
        path = PACKAGE / name
        files += sorted(path.rglob("*.py")) if path.is_dir() else [path]
    return files


def kind_mentions(path: Path, kinds: set[str]) -> list[str]:
    """Where the module names a kind: an import of orchestrator.kinds.<kind>, a string constant equal to a kind's
    name (docstrings and f-string text aside: they are prose), or a comparison of a name called kind with a
    string literal."""
    tree = ast.parse(path.read_text(), str(path))
    prose = {id(node.body[0].value) for node in ast.walk(tree)
             if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body
             and isinstance(node.body[0], ast.Expr) and isinstance(node.body[0].value, ast.Constant)}
    found = []
    for node in ast.walk(tree):
        modules = []
        if isinstance(node, ast.Import):
            modules = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module:
            modules = [node.module] + [f"{node.module}.{alias.name}" for alias in node.names]
        for module in modules:
            parts = module.split(".")
            if parts[:2] == ["orchestrator", "kinds"] and len(parts) > 2 and parts[2] in kinds:
                found.append(f"line {node.lineno}: imports {module}")
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in prose \
                and node.value in kinds:
            found.append(f"line {node.lineno}: the string {node.value!r}")
        if isinstance(node, ast.Compare):
            sides = [node.left, *node.comparators]
            named = any(isinstance(s, ast.Name) and "kind" in s.id or isinstance(s, ast.Attribute) and "kind" in s.attr
                        for s in sides)
            literal = any(isinstance(s, ast.Constant) and isinstance(s.value, str) for s in sides)
            if named and literal:
                found.append(f"line {node.lineno}: compares a kind with a literal")
    return found


def test_generic_layers_name_no_kind():
    kinds = set(kind_names())
    problems = []
    for path in generic_modules():
        relative = path.relative_to(PACKAGE).as_posix()
        mentions = kind_mentions(path, kinds)
        if mentions and relative not in KNOWN:
            problems += [f"orchestrator/{relative}: {m}" for m in mentions]
        if not mentions and relative in KNOWN:
            problems.append(f"orchestrator/{relative} names no kind any more: clear its line in KNOWN")
    assert not problems, "generic code that names a kind:\n" + "\n".join(problems)


@pytest.mark.parametrize("source, words", [
    ("from orchestrator.kinds.impact.theory import QUANTITIES\n", "imports orchestrator.kinds.impact.theory"),
    ("import orchestrator.kinds.impact\n", "imports orchestrator.kinds.impact"),
    ("def f(case):\n    return case.case.kind == 'drag_finishing'\n", "the string 'drag_finishing'"),
    ("def f(kind):\n    return kind != 'toy'\n", "compares a kind with a literal"),
    ("ENGINES = {'sph_flow': 'sph'}\n", "the string 'sph_flow'"),
])
def test_the_checker_finds_a_kind(tmp_path, source, words):
    """The checker itself: each way of naming a kind is found; a docstring that mentions one is prose."""
    path = tmp_path / "probe.py"
    path.write_text('"""A docstring may say impact."""\n' + source)
    assert any(words in m for m in kind_mentions(path, {"impact", "drag_finishing", "sph_flow"}))
    path.write_text('"""impact"""\nX = 1\n')
    assert kind_mentions(path, {"impact"}) == []
