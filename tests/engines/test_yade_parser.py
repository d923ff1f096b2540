"""The Yade output parser on a small stored output (tests/data/yade_tiny_output,
from a real Yade run of tests/data/tiny_bowl.toml); no engine needed."""

import shutil

import numpy as np
import pytest

from orchestrator.kinds import measure
from orchestrator.kinds.drag_finishing.yade import read_drag_finishing_output, read_series_csv
from paths import DATA

STORED = DATA / "yade_tiny_output"


@pytest.fixture(scope="module")
def case(tiny_bowl):
    return tiny_bowl


@pytest.fixture(scope="module")
def scene(tiny_bowl_scene):
    return tiny_bowl_scene


@pytest.fixture
def workdir(tmp_path):
    shutil.copytree(STORED, tmp_path / "output")
    return tmp_path


def test_series_and_workpiece_frame(scene, workdir):
    result = read_drag_finishing_output(scene, workdir)
    assert result.status == "ok"
    cols = read_series_csv(STORED / "series.csv")
    n = len(cols["time"])
    assert result.time.shape == (n,) and np.all(np.diff(result.time) > 0)
    wf = result.series["workpiece_force"].values
    assert wf.shape == (n, 3)
    phase = result.series["phase"].values
    assert set(np.unique(phase)) == {0, 1, 2, 3}
    # NaN outside the process, finite inside
    assert np.all(np.isnan(wf[phase != 3])) and np.all(np.isfinite(wf[phase == 3]))
    # the workpiece frame is a rotation of the global force about z: the horizontal magnitude is kept
    rod = result.series["rod_force"].values
    sel = phase == 3
    np.testing.assert_allclose(np.hypot(wf[sel, 0], wf[sel, 1]), np.hypot(rod[sel, 0], rod[sel, 1]), rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(wf[sel, 2], rod[sel, 2])
    # and at the first process sample (rod at angle ~0, moving along +y) normal ~ +y, radial ~ +x
    i = np.flatnonzero(sel)[0]
    theta = 0.01 / 0.005 * (result.time[i] - result.attrs["process_start_time"])
    assert wf[i, 0] == pytest.approx(-np.sin(theta) * rod[i, 0] + np.cos(theta) * rod[i, 1], rel=1e-6, abs=1e-12)


def test_measured_quantities_match_independent_reduction(case, scene, workdir):
    result = read_drag_finishing_output(scene, workdir)
    measured = measure(case, result)
    cols = read_series_csv(STORED / "series.csv")
    t_p = cols["time"] - result.attrs["process_start_time"]
    keep = (cols["phase"] == 3) & (t_p >= case.analysis.transient_time)
    assert measured["n_samples"] == keep.sum() > 10
    assert measured["fn_mean"] == pytest.approx(cols["wf_normal"][keep].mean(), rel=1e-12)
    assert measured["fn_std"] == pytest.approx(cols["wf_normal"][keep].std(ddof=1), rel=1e-12)
    assert measured["ft_mean"] == pytest.approx(cols["wf_tangential"][keep].mean(), rel=1e-12)
    assert 0.0 < measured["bed_height"] < case.bowl.height


def test_network_and_rod_mesh(scene, workdir):
    result = read_drag_finishing_output(scene, workdir)
    assert len(result.contacts) == 1
    time_s, net = result.contacts[0]
    assert net["process_time"] == pytest.approx(0.05, abs=2e-3)
    m = len(net["id1"])
    assert m > 20 and net["normal_force"].shape == (m,) and net["tangential_force"].shape == (m, 3)
    assert np.all(net["normal_force"] >= 0.0)
    np.testing.assert_allclose(net["branch"], net["point2"] - net["point1"])
    # ball-ball branch vectors are about one diameter long (overlaps are tiny with these soft contacts)
    balls = net["body2_role"] == 0
    lengths = np.linalg.norm(net["branch"][balls], axis=1)
    assert np.all(lengths < 2 * 3.57e-3) and np.all(lengths > 2 * 2.9e-3)
    rod = result.meshes["rod"]
    assert rod["contact_intensity"].shape == (len(rod["faces"]),)
    assert np.all(rod["contact_intensity"] >= 0) and rod["contact_intensity"].max() > 0


def test_partial_output_is_read_as_failed(scene, workdir):
    (workdir / "output" / "status.json").unlink()
    (workdir / "output" / "final.npz").unlink()
    text = (workdir / "output" / "series.csv").read_text()
    (workdir / "output" / "series.csv").write_text(text[: len(text) // 2])  # cut mid-line, as a killed engine leaves it
    result = read_drag_finishing_output(scene, workdir)
    assert result.status == "failed" and "no status" in result.message
    assert len(result.time) > 10 and np.all(np.isfinite(result.time))
    assert "contact_intensity" not in result.meshes["rod"]
