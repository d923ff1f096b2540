"""VTK export from run.h5 (meshio): every file read back and compared with run.h5."""

from __future__ import annotations

import hashlib
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest

from orchestrator.errors import ReadError
from orchestrator.export import export_vtk, normal_force_of
from orchestrator.runh5 import read_run


def _digest(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.fixture
def exported(synthetic_run):
    h5 = synthetic_run / "run.h5"
    before = (_digest(h5), h5.stat().st_mtime_ns)
    paths = export_vtk(synthetic_run)
    return synthetic_run, read_run(synthetic_run), paths, before


def test_writes_the_expected_files_into_run_dir_vtk(exported):
    run_dir, run, paths, _ = exported
    names = sorted(p.name for p in paths)
    assert names == sorted(
        ["particles_0.vtu", "particles_1.vtu", "particles_2.vtu", "particles.pvd",
         "network_0.vtu", "network.pvd", "mesh_bowl.vtu", "mesh_rod.vtu"]
    )
    assert all(p.parent == run_dir / "vtk" and p.is_file() for p in paths)


def test_run_h5_is_unchanged(exported):
    run_dir, _, _, before = exported
    h5 = run_dir / "run.h5"
    assert (_digest(h5), h5.stat().st_mtime_ns) == before


def test_particles_round_trip(exported):
    run_dir, run, _, _ = exported
    for k in ("0", "1", "2"):
        frame = run["frames"][k]
        mesh = meshio.read(run_dir / "vtk" / f"particles_{k}.vtu")
        n = len(frame["positions"])
        assert mesh.points.shape == (n, 3)
        np.testing.assert_allclose(mesh.points, frame["positions"])
        assert [block.type for block in mesh.cells] == ["vertex"]
        assert mesh.cells[0].data.shape == (n, 1)
        np.testing.assert_array_equal(mesh.cells[0].data[:, 0], np.arange(n))
        np.testing.assert_allclose(mesh.point_data["radius"], frame["radii"])
        np.testing.assert_allclose(mesh.point_data["velocity"], frame["velocities"])


def test_particles_pvd_is_a_time_collection_of_the_frames(exported):
    run_dir, run, _, _ = exported
    root = ET.parse(run_dir / "vtk" / "particles.pvd").getroot()
    assert root.get("type") == "Collection"
    datasets = root.findall("./Collection/DataSet")
    assert [d.get("file") for d in datasets] == ["particles_0.vtu", "particles_1.vtu", "particles_2.vtu"]
    times = [float(d.get("timestep")) for d in datasets]
    assert times == [run["frames"][k]["attrs"]["time"] for k in ("0", "1", "2")]
    network = ET.parse(run_dir / "vtk" / "network.pvd").getroot().findall("./Collection/DataSet")
    assert [(d.get("file"), float(d.get("timestep"))) for d in network] == [
        ("network_0.vtu", run["contacts"]["0"]["attrs"]["time"])
    ]


def test_network_round_trip(exported):
    run_dir, run, _, _ = exported
    snap = run["contacts"]["0"]
    n = len(snap["normal_force"])
    mesh = meshio.read(run_dir / "vtk" / "network_0.vtu")
    assert mesh.points.shape == (2 * n, 3)
    assert [block.type for block in mesh.cells] == ["line"]
    lines = mesh.cells[0].data
    assert lines.shape == (n, 2)
    np.testing.assert_allclose(mesh.points[lines[:, 0]], snap["point1"])
    np.testing.assert_allclose(mesh.points[lines[:, 1]], snap["point2"])
    cell = {name: values[0] for name, values in mesh.cell_data.items()}
    np.testing.assert_allclose(cell["normal_force"], snap["normal_force"])
    np.testing.assert_allclose(cell["tangential_force"], np.linalg.norm(snap["tangential_force"], axis=1))
    np.testing.assert_allclose(cell["normal_force_vector"], snap["normal_force_vector"])
    np.testing.assert_allclose(cell["tangential_force_vector"], snap["tangential_force"])
    np.testing.assert_array_equal(cell["body2_role"], snap["body2_role"])
    assert set(np.unique(cell["body2_role"])) == {0, 1, 2}
    np.testing.assert_array_equal(cell["id1"], snap["id1"])
    np.testing.assert_array_equal(cell["id2"], snap["id2"])


def test_meshes_round_trip_with_per_face_fields(exported):
    run_dir, run, _, _ = exported
    for name in ("bowl", "rod"):
        group = run["meshes"][name]
        mesh = meshio.read(run_dir / "vtk" / f"mesh_{name}.vtu")
        np.testing.assert_allclose(mesh.points, group["vertices"])
        assert [block.type for block in mesh.cells] == ["triangle"]
        np.testing.assert_array_equal(mesh.cells[0].data, group["faces"])
    rod = meshio.read(run_dir / "vtk" / "mesh_rod.vtu")
    np.testing.assert_allclose(rod.cell_data["contact_intensity"][0], run["meshes"]["rod"]["contact_intensity"])
    np.testing.assert_array_equal(rod.cell_data["contact_count"][0], run["meshes"]["rod"]["contact_count"])
    assert not meshio.read(run_dir / "vtk" / "mesh_bowl.vtu").cell_data


def test_out_dir_and_the_path_of_run_h5_itself(synthetic_run, tmp_path):
    out = tmp_path / "elsewhere" / "vtk"
    paths = export_vtk(synthetic_run / "run.h5", out)
    assert paths and all(p.parent == out for p in paths)
    assert not (synthetic_run / "vtk").exists()


def test_a_directory_without_run_h5_is_a_clear_read_error(tmp_path):
    with pytest.raises(ReadError, match=r"no run\.h5 in .*orchestrator run"):
        export_vtk(tmp_path)


def test_older_vector_normal_force_still_gives_a_scalar():
    vec = np.array([[0.0, 0.0, -3.0], [4.0, 0.0, 0.0]])
    fn, fn_vec = normal_force_of({"normal_force": vec})
    np.testing.assert_allclose(fn, [3.0, 4.0])
    np.testing.assert_allclose(fn_vec, vec)
