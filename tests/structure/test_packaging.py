"""The wheel holds every package of orchestrator/ and every data file its kinds read (templates above all), found by
pattern: a new kind folder needs no edit in pyproject.toml or setup.py. Built from a copy of the tree with the venv's
own setuptools (no network, no build isolation); about 4 s."""

from __future__ import annotations

import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from orchestrator.kinds import get_kind, kind_names
from paths import REPO

PACKAGE = REPO / "orchestrator"
#: What the build reads: the package, the folders it maps into the package, and the project files.
BUILD_INPUTS = ("pyproject.toml", "setup.py", "README.md", "orchestrator", "templates", "cases/verification")
#: Folders outside orchestrator/ that ship inside it (package-dir in pyproject.toml): source -> place in the wheel.
MAPPED = {"templates": "orchestrator/templates", "cases/verification": "orchestrator/verification_cases"}
IGNORED = shutil.ignore_patterns("__pycache__", "*.pyc", "*.egg-info")


def tree_files(folder: Path) -> list[Path]:
    """Every file below folder, without caches."""
    return sorted(p for p in folder.rglob("*") if p.is_file() and "__pycache__" not in p.parts
                  and p.suffix != ".pyc")


@pytest.fixture(scope="module")
def wheel_names(tmp_path_factory) -> set[str]:
    """The file names inside a wheel built from a copy of the tree."""
    source = tmp_path_factory.mktemp("tree")
    for name in BUILD_INPUTS:
        if (REPO / name).is_dir():
            shutil.copytree(REPO / name, source / name, ignore=IGNORED)
        else:
            shutil.copy2(REPO / name, source / name)
    dist = tmp_path_factory.mktemp("dist")
    done = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "--no-index",
                           "-q", "-w", str(dist), str(source)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, (f"pip wheel failed (setuptools < 70.1 needs the wheel package: pip install -e "
                                  f"'.[dev]'):\n{done.stderr[-3000:]}")
    (wheel,) = dist.glob("orchestrator-*.whl")
    with zipfile.ZipFile(wheel) as archive:
        return set(archive.namelist())


def test_every_module_and_package_of_the_tree_is_in_the_wheel(wheel_names):
    modules = [p.relative_to(REPO).as_posix() for p in tree_files(PACKAGE) if p.suffix == ".py"]
    assert len(modules) > 100
    missing = [name for name in modules if name not in wheel_names]
    assert not missing, f"modules missing from the wheel (package discovery in setup.py): {missing}"
    packages = {p.parent.relative_to(REPO).as_posix() for p in PACKAGE.rglob("__init__.py")}
    assert {"orchestrator/dem", "orchestrator/kinds/impact", "orchestrator/kinds/drag_finishing"} <= packages


def test_every_data_file_of_the_tree_is_in_the_wheel(wheel_names):
    """Every file under orchestrator/ that is not Python (kind templates, data), and the mapped folders' files."""
    expected = [p.relative_to(REPO).as_posix() for p in tree_files(PACKAGE) if p.suffix != ".py"]
    assert any(name.endswith(".j2") for name in expected)
    for source, target in MAPPED.items():
        expected += [f"{target}/{p.relative_to(REPO / source).as_posix()}" for p in tree_files(REPO / source)
                     if p.suffix in (".j2", ".toml")]
    assert "orchestrator/verification_cases/uhlmann2015_sphere_drop.toml" in expected
    missing = [name for name in expected if name not in wheel_names]
    assert not missing, f"data files missing from the wheel (package-data in pyproject.toml): {missing}"


def test_every_kind_template_is_in_the_wheel(wheel_names):
    """The templates each kind's adapters render, asked of the kinds themselves."""
    templates = {}
    for name in kind_names():
        kind = get_kind(name)
        for engine in kind.engines():
            for template in kind.adapter(engine).templates:
                templates[f"{name}/{engine}"] = Path(template).resolve().relative_to(REPO).as_posix()
    assert {"impact/yade", "impact/liggghts", "drag_finishing/yade", "sph_flow/sph"} <= set(templates)
    missing = {adapter: path for adapter, path in templates.items() if path not in wheel_names}
    assert not missing, f"kind templates missing from the wheel: {missing}"
