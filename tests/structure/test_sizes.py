"""Small modules and short functions (STYLE.md): no Python module of orchestrator/ over MAX_MODULE_LINES lines and no
function over MAX_FUNCTION_LINES (a nested function counts inside its parent too). The allow-lists below name what is
still too long and is being shrunk elsewhere; the test fails on any new offender and on a listed one that grew, and
warns of a listed one that is short now (then remove its line)."""

from __future__ import annotations

import ast
import warnings
from paths import REPO

PACKAGE = REPO / "orchestrator"
MAX_MODULE_LINES = 400
MAX_FUNCTION_LINES = 80
#: (module, qualified function name) -> its length in lines when listed.
ALLOWED_FUNCTIONS = {
}
#: module -> its length in lines when listed.
ALLOWED_MODULES = {
}


def function_lengths(source: str) -> dict[str, int]:
    """Qualified name (Class.method, outer.inner) -> lines from the def to the function's last line."""
    lengths: dict[str, int] = {}

    def visit(node, prefix):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                name = f"{prefix}{child.name}"
                if not isinstance(child, ast.ClassDef):
                    lengths[name] = child.end_lineno - child.lineno + 1
                visit(child, f"{name}.")
            else:
                visit(child, prefix)

    visit(ast.parse(source), "")
    return lengths


def sizes() -> tuple[dict[str, int], dict[tuple[str, str], int]]:
    """Every module's length and every function's, in lines."""
    modules, functions = {}, {}
    for path in sorted(PACKAGE.rglob("*.py")):
        name = path.relative_to(PACKAGE.parent).as_posix()
        source = path.read_text(encoding="utf-8")
        modules[name] = len(source.splitlines())
        functions.update({(name, function): length for function, length in function_lengths(source).items()})
    return modules, functions


def _check(found: dict, allowed: dict, limit: int, what: str) -> list[str]:
    problems = []
    for key, length in sorted(found.items()):
        if length > limit and key not in allowed:
            problems.append(f"{key}: {length} lines (limit {limit}): split it into named {what}s")
        elif key in allowed and length > allowed[key]:
            problems.append(f"{key}: {length} lines, grew from the {allowed[key]} it is allowed")
    for key in sorted(allowed):
        if found.get(key, 0) <= limit:
            warnings.warn(f"{key} is {found.get(key, 'gone')} lines now: remove it from the allow-list", stacklevel=2)
    return problems


def test_no_module_is_too_long():
    modules, _ = sizes()
    problems = _check(modules, ALLOWED_MODULES, MAX_MODULE_LINES, "module")
    assert not problems, "\n".join(problems)


def test_no_function_is_too_long():
    _, functions = sizes()
    problems = _check(functions, ALLOWED_FUNCTIONS, MAX_FUNCTION_LINES, "function")
    assert not problems, "\n".join(problems)


def test_lengths_are_counted_from_def_to_last_line():
    source = "class A:\n    def f(self):\n        def g():\n            return 1\n        return g()\n\n\ndef h():\n    pass\n"
    assert function_lengths(source) == {"A.f": 4, "A.f.g": 2, "h": 2}
