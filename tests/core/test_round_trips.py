"""Round trips of every writer we own whose output we (or a library) read back, as meshio tests its formats: a few
canonical inputs, written, read back, compared number for number, and the input left unmutated."""

from __future__ import annotations

import copy

import h5py
import numpy as np
import pytest
import trimesh

from orchestrator.case import load_case
from orchestrator.engines.base import Result, Series
from orchestrator.engines.liggghts_files import write_data_file, write_stl_ascii
from orchestrator.kinds import build_scene
from orchestrator.kinds.sph_flow.sph import write_particles
from orchestrator.runh5 import read_run, write_run
from paths import CASES as SHIPPED_CASES, VERIFICATION, DATA, TINY_BOWL

CASES = [TINY_BOWL, VERIFICATION / "chung_ooi_test2_sphere_plane.toml", VERIFICATION / "sph_poiseuille_morris1997.toml",
         DATA / "sph_channel_3d.toml"]
#: Every shipped case (studies are not cases): each must read back from the resolved TOML that run.h5 stores.
SHIPPED = sorted(p for p in SHIPPED_CASES.rglob("*.toml") if "studies" not in p.parts)
RNG = np.random.default_rng(11)


def _meshes():
    """A tetrahedron, a box and a rod-like cylinder (m), with coordinates that need every digit."""
    tetra = trimesh.Trimesh(vertices=[[0, 0, 0], [1e-3, 0, 0], [0, 1e-3, 0], [0, 0, 1e-3]],
                            faces=[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], process=False)
    box = trimesh.creation.box(extents=(0.042, 0.03, 0.07))
    box.apply_translation([1 / 3, -2 / 7, 0.1])
    rod = trimesh.creation.cylinder(radius=0.005, height=0.1, sections=24)
    return {"tetra": tetra, "box": box, "rod": rod}


@pytest.mark.parametrize("name", sorted(_meshes()))
def test_ascii_stl_round_trip(name, tmp_path):
    mesh = _meshes()[name]
    before = mesh.vertices.copy(), mesh.faces.copy()
    write_stl_ascii(tmp_path / "m.stl", mesh.vertices, mesh.faces, name)
    back = trimesh.load(tmp_path / "m.stl", process=False)
    corners, back_corners = mesh.vertices[mesh.faces], back.vertices[back.faces]
    assert np.array_equal(back_corners, corners)  # %r of every coordinate: bit for bit
    assert np.array_equal(mesh.vertices, before[0]) and np.array_equal(mesh.faces, before[1])


@pytest.mark.parametrize("with_velocities", [False, True])
def test_liggghts_data_file_round_trip(with_velocities, tmp_path):
    n = 17
    positions, radii = RNG.uniform(-0.05, 0.05, (n, 3)), RNG.uniform(1e-3, 4e-3, n)
    types, densities = RNG.integers(1, 4, n), RNG.uniform(1000, 8000, n)
    velocities = RNG.normal(size=(n, 3)) if with_velocities else None
    spins = RNG.normal(size=(n, 3)) if with_velocities else None
    box = np.array([[-0.1, 0.1], [-0.1, 0.1], [-0.05, 0.2]])
    inputs = copy.deepcopy((positions, radii, types, densities, velocities, spins))
    write_data_file(tmp_path / "d.data", box, 3, types, radii, densities, positions, velocities, spins)
    lines = (tmp_path / "d.data").read_text().splitlines()
    bounds = np.array([line.split()[:2] for line in lines if line.endswith(("lo xhi", "lo yhi", "lo zhi"))],
                      dtype=float)  # plain numbers: numpy 2's repr of a scalar ('np.float64(...)') is not one
    assert np.array_equal(bounds, box)
    start = lines.index("Atoms") + 2
    atoms = np.array([line.split() for line in lines[start:start + n]], dtype=float)
    assert np.array_equal(atoms[:, 0], np.arange(1, n + 1)) and np.array_equal(atoms[:, 1], types)
    assert np.array_equal(atoms[:, 2], 2 * radii) and np.array_equal(atoms[:, 3], densities)
    assert np.array_equal(atoms[:, 4:7], positions)
    if with_velocities:
        start = lines.index("Velocities") + 2
        rows = np.array([line.split() for line in lines[start:start + n]], dtype=float)
        assert np.array_equal(rows[:, 1:4], velocities) and np.array_equal(rows[:, 4:7], spins)
    else:
        assert "Velocities" not in lines
    for a, b in zip(inputs, (positions, radii, types, densities, velocities, spins)):
        assert (a is None and b is None) or np.array_equal(a, b)


def _result() -> Result:
    time = np.linspace(0.0, 1.0, 11)
    result = Result(status="ok", message="", attrs={"n_steps": 1000, "dt": 1e-3, "note": "tiny"}, time=time)
    result.series = {"force": Series(RNG.normal(size=(11, 3)), "N", "force on the rod"),
                     "phase": Series(np.arange(11, dtype=np.int8) % 4, "-", "phase code")}
    result.frames = [(0.5, {"positions": RNG.normal(size=(5, 3)), "radii": np.full(5, 2e-3)})]
    result.contacts = [(0.7, {"id1": np.arange(4), "id2": np.arange(4) + 1, "normal_force": RNG.uniform(0, 1, 4)})]
    result.measured = {"fn_mean": -1.9, "fn_std": 0.4}
    return result


def test_run_h5_round_trip(tmp_path):
    result = _result()
    before = copy.deepcopy(result)
    write_run(tmp_path / "run.h5", result, {"engine": "yade", "wall_time_s": 1.5}, "[case]\nname='x'\n", {"a": 1},
              "last line")
    run = read_run(tmp_path)
    assert run["attrs"]["engine"] == "yade" and run["attrs"]["n_steps"] == 1000 and run["attrs"]["status"] == "ok"
    assert np.array_equal(run["series"]["time"], result.time)
    for name, series in result.series.items():
        assert np.array_equal(run["series"][name], series.values)
        assert run["series"][name].dtype == series.values.dtype
    frame = next(v for k, v in run["frames"].items() if k != "attrs")
    assert frame["attrs"]["time"] == 0.5 and np.array_equal(frame["positions"], result.frames[0][1]["positions"])
    snapshot = next(v for k, v in run["contacts"].items() if k != "attrs")
    assert np.array_equal(snapshot["normal_force"], result.contacts[0][1]["normal_force"])
    assert run["measured"]["attrs"] == pytest.approx(result.measured)
    assert np.array_equal(result.series["force"].values, before.series["force"].values) and result.measured == \
        before.measured


@pytest.mark.parametrize("path", CASES + SHIPPED, ids=lambda p: p.stem)
def test_case_round_trip_through_its_resolved_toml(path, tmp_path):
    """A case, written back as the resolved TOML stored in run.h5, loads to the same parameters (same hash)."""
    loaded = load_case(path)
    copy_path = tmp_path / path.name
    copy_path.write_text(loaded.toml_text)
    for extra in (path.parent.glob("*.stl")):  # mesh files the case names relative to itself
        (tmp_path / extra.name).write_bytes(extra.read_bytes())
    again = load_case(copy_path)
    assert again.hash == loaded.hash and again.model == loaded.model


@pytest.mark.parametrize("path", [p for p in CASES if p.stem.startswith("sph_")], ids=lambda p: p.stem)
def test_sph_particle_file_round_trip(path, tmp_path):
    scene = build_scene(load_case(path).model)
    before = scene.positions.copy()
    write_particles(scene, tmp_path / "particles.h5")
    with h5py.File(tmp_path / "particles.h5") as h5:
        for name, expected in (("positions", scene.positions), ("velocities", scene.velocities),
                               ("masses", scene.masses), ("densities", scene.densities), ("kind", scene.kind)):
            assert np.array_equal(h5[name][()], np.asarray(expected)), name
        assert h5["kind"].dtype == np.int8 and h5["positions"].dtype == np.float64
    assert np.array_equal(scene.positions, before)
