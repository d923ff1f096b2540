"""The LIGGGHTS output readers on small stored outputs of real runs (tests/data/liggghts_*); no engine needed.

liggghts_impact_output: Chung & Ooi's test 1 (two glass spheres, pair contacts) and test 3 at e_n = 0.2 (one
sphere on two coincident wall copies); liggghts_tiny_output: tests/data/tiny_bowl.toml (its last four rod
dumps kept of 222, the log's last lines).
"""

import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from orchestrator.kinds import measure
from orchestrator.kinds.impact.analysis import evaluate_checks
from orchestrator.engines.liggghts_files import read_dump
from orchestrator.kinds.drag_finishing.liggghts_output import read_drag_output, read_vtk_cells
from orchestrator.kinds.impact.liggghts_output import read_impact_output
from orchestrator.case import load_case
from orchestrator.kinds import build_scene
from orchestrator.kinds.drag_finishing.scene import bed_weight
from paths import VERIFICATION, DATA

IMPACTS = DATA / "liggghts_impact_output"


def _workdir(stored: Path, tmp_path: Path) -> Path:
    """A run directory as the runner leaves it: output/ and engine.log."""
    (tmp_path / "output").mkdir()
    for path in stored.iterdir():
        shutil.copy(path, tmp_path / ("engine.log" if path.name == "engine.log" else f"output/{path.name}"))
    return tmp_path


def _impact(name, tmp_path):
    loaded = load_case(VERIFICATION / f"{name}.toml")
    scene = build_scene(loaded.model)
    return loaded.model, scene, read_impact_output(scene, _workdir(IMPACTS / name, tmp_path))


def test_two_spheres_one_event_with_hertz_peak(tmp_path):
    case, scene, result = _impact("chung_ooi_test1_sphere_sphere", tmp_path)
    assert result.status == "ok" and result.attrs["n_steps"] == math.ceil(scene.duration / scene.timestep) == 93
    events = {name: item.values for name, item in result.events.items()}
    assert events["sphere"].tolist() == [0] and events["other_kind"].tolist() == [0] and events["other"].tolist() == [1]
    # the peak is the largest normal force any dumped step shows (rows: force on atom id1, normal part)
    raw = max(np.linalg.norm(rows[:, 18:21], axis=1).max(initial=0.0)
              for _, _, rows in read_dump(tmp_path / "output" / "pairs.dump"))
    assert events["peak_normal_force"][0] == raw
    for check in evaluate_checks(case, measure(case, result)):
        assert check.rel_error < 1e-3, check  # Hertz's force, overlap, duration; elastic rebound
    energy = result.series["kinetic_energy"].values + result.series["potential_energy"].values
    assert energy[-1] == pytest.approx(energy[0], rel=1e-3)  # elastic: all kinetic energy comes back
    assert result.series["positions"].values.shape == (len(result.time), 2, 3)


def test_wall_copies_are_merged_into_one_contact(tmp_path):
    case, scene, result = _impact("chung_ooi_test3_restitution_020", tmp_path)
    assert result.status == "ok"
    snapshots = read_dump(tmp_path / "output" / "walls.dump")
    in_contact = [rows for _, _, rows in snapshots if len(rows)]
    assert in_contact and all(len(rows) == 2 for rows in in_contact)  # two copies of the wall, one sphere
    assert all(np.array_equal(rows[0, 21], rows[1, 21]) for rows in in_contact)  # same overlap on both
    events = {name: item.values for name, item in result.events.items()}
    assert len(events["start_time"]) == 1 and events["other_kind"][0] == 1
    peak = max(np.linalg.norm(rows[:, 18:21], axis=1).sum() for rows in in_contact)
    assert events["peak_normal_force"][0] == pytest.approx(peak, rel=1e-14)
    measured = measure(case, result)
    assert measured["restitution"] == pytest.approx(0.2, rel=0.01)
    # the sphere pushes the plane down with the summed contact force
    wall_z = result.series["wall_force"].values[:, 2]
    normal = result.series["normal_force"].values
    assert np.all(wall_z <= 1e-9) and np.allclose(-wall_z, normal, rtol=1e-9, atol=1e-9)
    assert normal.max() > 0.5 * events["peak_normal_force"][0]


def test_a_run_without_final_status_is_failed_and_keeps_its_data(tmp_path):
    _, scene, _ = _impact("chung_ooi_test1_sphere_sphere", tmp_path)
    (tmp_path / "output" / "status.txt").unlink()
    result = read_impact_output(scene, tmp_path)
    assert result.status == "failed" and "no final status" in result.message
    assert len(result.time) > 10 and len(result.events["start_time"].values) == 1


# ---- drag finishing ----
@pytest.fixture(scope="module")
def tiny(tmp_path_factory, tiny_bowl, tiny_bowl_scene):
    case, scene = tiny_bowl, tiny_bowl_scene
    workdir = _workdir(DATA / "liggghts_tiny_output", tmp_path_factory.mktemp("tiny"))
    return case, scene, workdir, read_drag_output(scene, workdir)


def test_status_phases_and_the_bed_weight(tiny):
    case, scene, _, result = tiny
    assert result.status == "ok" and result.attrs["last_phase"] == "process" and result.attrs["settled"]
    assert result.attrs["n_steps"] == 32220 and result.attrs["dt"] == pytest.approx(scene.timestep)
    phase = result.series["phase"].values
    assert phase[0] == 0 and phase[-1] == 3 and np.all(np.diff(phase) >= 0) and np.all(np.diff(result.time) > 0)
    last_settle = np.flatnonzero(phase == 0)[-1]
    assert result.series["bowl_force"].values[last_settle, 2] == pytest.approx(-bed_weight(scene), rel=0.01)
    process = phase == 3
    tip = result.series["rod_tip_z"].values[process]
    assert np.ptp(tip) == 0 and tip[0] == pytest.approx(result.attrs["bed_height"] - case.workpiece.submersion_depth,
                                                         abs=case.workpiece.insertion_speed * scene.timestep)


def test_workpiece_frame(tiny):
    case, _, _, result = tiny
    phase = result.series["phase"].values
    wf = result.series["workpiece_force"].values
    rod = result.series["rod_force"].values
    assert np.all(np.isnan(wf[phase < 3])) and np.all(np.isfinite(wf[phase == 3]))
    k = np.flatnonzero(phase == 3)[-1]
    theta = case.angular_velocity * (result.time[k] - result.attrs["process_start_time"])
    velocity_direction = np.array([-math.sin(theta), math.cos(theta)])
    assert wf[k, 0] == pytest.approx(rod[k, :2] @ velocity_direction, rel=1e-12)
    assert np.hypot(wf[k, 0], wf[k, 1]) == pytest.approx(np.hypot(*rod[k, :2]), rel=1e-12)
    assert wf[k, 2] == rod[k, 2]
    assert measure(case, result)["fn_mean"] < 0  # the media resist the motion


def test_network_and_frames(tiny):
    _, scene, workdir, result = tiny
    (time, net), = result.contacts
    assert net["process_time"] == pytest.approx(0.05, abs=scene.timestep)
    walls = read_dump(workdir / "output" / "network_0_walls.dump")[-1][2]
    pairs = read_dump(workdir / "output" / "network_0_pairs.dump")[-1][2]
    assert len(net["id1"]) == len(walls) + len(pairs) > 100
    assert np.all(net["normal_force"] >= -1e-12)  # limitForce: no pulling contact
    n_bowl = len(scene.meshes["bowl"].mesh.faces)
    rod = net["body2_role"] == 2
    assert rod.sum() == (walls[:, 6] == 1).sum() > 0 and np.all(net["id2"][rod] >= scene.n_particles + n_bowl)
    balls = net["body2_role"] == 0
    assert np.all(net["id2"][balls] < scene.n_particles) and np.all(net["id1"] < scene.n_particles)
    # the branch of a ball-ball contact is about the sum of the radii
    gap = np.linalg.norm(net["branch"][balls], axis=1) - scene.radii[net["id1"][balls]] - scene.radii[net["id2"][balls]]
    assert np.all(gap <= 0) and np.all(gap > -0.01 * scene.radii.min())
    times = [t for t, _ in result.frames]
    assert times == sorted(times) and len(times) == 3 and times[1] == pytest.approx(time)
    assert all(frame["positions"].shape == (scene.n_particles, 3) for _, frame in result.frames)


def test_rod_mesh_moved_and_intensity(tiny):
    case, scene, workdir, result = tiny
    rod = result.meshes["rod"]
    start = np.asarray(scene.meshes["rod"].mesh.vertices)
    # the rod's end position: lowered to its tip height, then turned about the bowl axis for the process time
    theta = case.angular_velocity * (result.attrs["simulated_time"] - result.attrs["process_start_time"])
    turn = np.array([[math.cos(theta), -math.sin(theta), 0], [math.sin(theta), math.cos(theta), 0], [0, 0, 1]])
    lowered = start + [0.0, 0.0, result.series["rod_tip_z"].values[-1] - start[:, 2].min()]
    np.testing.assert_allclose(rod["vertices"], lowered @ turn.T, atol=1e-6)
    files = sorted((workdir / "output").glob("rod_[0-9]*.vtk"))
    interval = round(case.output.record_interval / scene.timestep) * scene.timestep  # whole steps, as Yade's
    expected = np.zeros(len(rod["faces"]))
    for path in files:
        cells = read_vtk_cells(path)
        expected[cells["meshid"].astype(int)] += cells["area"] * np.hypot(
            cells["normal_stress_average"], cells["shear_stress_average"]) * interval
    np.testing.assert_allclose(rod["contact_intensity"], expected, rtol=1e-3)
    assert rod["contact_intensity"].max() > 0 and rod["contact_count"].max() <= len(files)
