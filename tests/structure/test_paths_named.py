"""Every path and module the project names exists: in the docs (*.md), the templates' comments (their provenance
lines) and the docstrings of orchestrator/ and tests/.

Checked: repository paths (orchestrator/..., engines/..., cases/..., docs/..., tests/..., templates/..., and paths
inside the package written without orchestrator/: kinds/..., reference/..., dem/...), where <name> is a placeholder
and * a glob, a path may end in a module's attribute (kinds/impact/theory.QUANTITIES), and a module may be written
without .py; and dotted names orchestrator.x.y, which must resolve to a module, then to names it defines (a class's
methods too). What is still broken is listed in KNOWN_BROKEN with the reason, to be cleared; the test fails on
anything new, and warns of a listed reference that resolves now.
"""

from __future__ import annotations

import ast
import glob
import re
import warnings
from functools import lru_cache
from pathlib import Path
from paths import REPO

PACKAGE = REPO / "orchestrator"
#: First folders of a path from the repository's root, and of a path inside the package written without it.
ROOT_FOLDERS = ("orchestrator", "engines", "cases", "docs", "tests", "templates")
PACKAGE_FOLDERS = ("kinds", "reference", "dem", "drill", "workflows", "study", "cli", "case", "scene")
PATH = re.compile(r"(?<![\w./~$-])((?:%s)/[\w.*/<>{},-]*[\w*/>}])" % "|".join(ROOT_FOLDERS + PACKAGE_FOLDERS))
DOTTED = re.compile(r"(?<![\w.])orchestrator(?:\.\w+)+")
#: Paths the build makes (not in a checkout).
BUILT = ("engines/sph/build",)
#: Folders outside orchestrator/ that the wheel ships inside it (pyproject.toml's package-dir).
MAPPED = {"orchestrator.templates": "templates", "orchestrator.verification_cases": "cases/verification"}
#: Dotted names that stand for any module in a docstring's example.
PLACEHOLDERS = {"orchestrator.a.b", "orchestrator.x.y"}
#: (file, reference) -> why it is still broken. Empty: every reference resolves. A reference that another piece of
#: work will fix may stand here for a while, with the reason; clear its line when it resolves.
KNOWN_BROKEN: dict[tuple[str, str], str] = {}


def named_texts():
    """(file relative to the root, text) of every place checked: whole docs, templates' comments, docstrings."""
    docs = [*REPO.glob("*.md"), *REPO.glob("docs/**/*.md"), *REPO.glob("engines/**/*.md")]
    for path in sorted(p for p in docs if not {"build", "_deps"} & set(p.parts)):
        yield path.relative_to(REPO).as_posix(), path.read_text(encoding="utf-8")
    for path in sorted([*PACKAGE.glob("**/*.j2"), *REPO.glob("templates/**/*.j2")]):
        text = path.read_text(encoding="utf-8")
        comments = [line for line in text.splitlines() if line.lstrip().startswith("#")]
        comments += re.findall(r"\{#.*?#\}", text, re.S)
        yield path.relative_to(REPO).as_posix(), "\n".join(comments)
    for path in sorted([*PACKAGE.rglob("*.py"), *REPO.glob("tests/**/*.py")]):
        if "__pycache__" in path.parts:
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        nodes = (n for n in ast.walk(tree) if isinstance(n, (ast.Module, ast.ClassDef, ast.FunctionDef,
                                                               ast.AsyncFunctionDef)))
        yield path.relative_to(REPO).as_posix(), "\n".join(filter(None, map(ast.get_docstring, nodes)))


@lru_cache(maxsize=None)
def defined_names(module: Path) -> dict[str, set[str]]:
    """Top-level names a module defines or imports -> the names defined in its body (a class's methods)."""
    names: dict[str, set[str]] = {}
    for node in ast.parse(module.read_text(encoding="utf-8")).body:
        inner = {getattr(n, "name", None) for n in getattr(node, "body", [])} - {None}
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names[node.name] = inner
        elif isinstance(node, (ast.Assign, ast.AnnAssign)):
            for target in node.targets if isinstance(node, ast.Assign) else [node.target]:
                for name in ast.walk(target):
                    if isinstance(name, ast.Name):
                        names[name.id] = set()
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            names.update({(alias.asname or alias.name).split(".")[0]: set() for alias in node.names})
    return names


def attributes_exist(module: Path, attributes: list[str]) -> bool:
    """The attribute chain is defined in the module (the first name, and a class's member after it)."""
    if not attributes:
        return True
    names = defined_names(module)
    if attributes[0] not in names:
        return False
    return len(attributes) < 2 or not names[attributes[0]] or attributes[1] in names[attributes[0]]


def module_exists(dotted: str) -> bool:
    """orchestrator.x.y[.attribute...]: the longest module prefix exists and defines the rest."""
    parts = dotted.split(".")
    for mapped, folder in MAPPED.items():
        if dotted == mapped or dotted.startswith(mapped + "."):
            return (REPO / folder).is_dir()
    for k in range(len(parts), 1, -1):
        base = REPO.joinpath(*parts[:k])
        for module in (base.with_suffix(".py"), base / "__init__.py"):
            if module.is_file():
                return attributes_exist(module, parts[k:])
    return False


def _expanded(reference: str) -> list[str]:
    """The reference as glob patterns: <placeholder> -> *, {a,b} -> a and b."""
    pattern = re.sub(r"<[^>]*>", "*", reference.rstrip("/"))
    match = re.search(r"\{([^{}]*)\}", pattern)
    if not match:
        return [pattern]
    return [p for choice in match.group(1).split(",")
            for p in _expanded(pattern[:match.start()] + choice + pattern[match.end():])]


def path_exists(reference: str, named_in: Path = REPO) -> bool:
    """A path exists: from the repository's root, from orchestrator/, from a kind's folder or from the folder of the
    file that names it (named_in); as written, as a module without .py, or as a module followed by attributes
    (a/b.Name). Every alternative of {a,b} must exist."""
    if reference.startswith(BUILT):
        return True
    bases = (REPO, PACKAGE, PACKAGE / "kinds" / "*", named_in.parent)
    return all(any(_exists(base, pattern) for base in bases) for pattern in _expanded(reference))


def _exists(base: Path, pattern: str) -> bool:
    if glob.glob(str(base / pattern)) or glob.glob(str(base / pattern) + ".py"):
        return True
    folder, _, last = pattern.rpartition("/")
    module, _, attributes = last.partition(".")
    return bool(attributes) and any(attributes_exist(Path(found), attributes.split("."))
                                    for found in glob.glob(str(base / folder / f"{module}.py")))


def broken_references() -> set[tuple[str, str]]:
    """(file, reference) for every named path or module that does not exist."""
    broken = set()
    for name, text in named_texts():
        broken |= {(name, m.group(1)) for m in PATH.finditer(text) if not path_exists(m.group(1), REPO / name)}
        broken |= {(name, m.group(0)) for m in DOTTED.finditer(text)
                   if m.group(0) not in PLACEHOLDERS and not module_exists(m.group(0))}
    return broken


def test_every_named_path_and_module_exists():
    broken = broken_references()
    new = sorted(broken - set(KNOWN_BROKEN))
    assert not new, "named but missing (fix the reference):\n" + "\n".join(f"{f}: {ref}" for f, ref in new)
    for file, reference in sorted(set(KNOWN_BROKEN) - broken):
        warnings.warn(f"{file}: {reference} resolves now: remove it from KNOWN_BROKEN", stacklevel=1)


def test_the_resolver_tells_real_from_missing():
    assert path_exists("orchestrator/kinds/<kind>/templates/*.j2") and path_exists("kinds/impact/theory.py")
    assert path_exists("orchestrator/dem/liggghts_law.py") and not path_exists("orchestrator/backends/liggghts.py")
    assert path_exists("orchestrator/kinds/{impact,drag_finishing}/case.py")
    assert path_exists("templates/yade.py.j2", PACKAGE / "kinds" / "impact" / "yade.py")
    assert not path_exists("orchestrator/kinds/{impact,nothing}/case.py")
    assert path_exists("reference/dem_forces.EVENT_FIELDS") and not path_exists("reference/dem_forces.NOTHING")
    assert module_exists("orchestrator.reference.dem_forces.EVENT_FIELDS")
    assert module_exists("orchestrator.reference.dem_forces.ContactLaw.events")
    assert not module_exists("orchestrator.kinds.impact.analysis.EVENT_FIELDS")
    assert not module_exists("orchestrator.analysis.impact") and module_exists("orchestrator.verification_cases")
