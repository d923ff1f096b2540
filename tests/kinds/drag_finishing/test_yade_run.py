"""One real Yade run of the tiny scene (40 balls, 0.1 s of process), asserting physics.

Skipped, with the reason, when Yade is not installed.
"""

import json
import subprocess
import sys

import numpy as np
import pytest

from orchestrator.engines import get_engine

from orchestrator.runh5 import read_run
from orchestrator.kinds import build_scene
from orchestrator.kinds.drag_finishing.scene import bed_weight
from orchestrator.case import load_case
from test_rod_impacts import assert_engine_impacts
from paths import TINY_BOWL


pytestmark = pytest.mark.yade


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("run") / "tiny"
    proc = subprocess.run(
        [sys.executable, "-m", "orchestrator", "run", str(TINY_BOWL), "--out", str(out), "--json", "--no-progress"],
        capture_output=True, text=True, timeout=600,
    )
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout), read_run(out)


def test_summary_json(tiny_run):
    summary, run = tiny_run
    for key in ("status", "engine", "wall_time_s", "n_particles", "n_steps", "run_dir", "measured"):
        assert key in summary
    assert summary["status"] == "ok" and summary["engine"] == "yade" and summary["n_particles"] == 120
    assert summary["n_steps"] == run["attrs"]["n_steps"] > 1000
    assert run["attrs"]["engine_version"] == get_engine("yade").version() != "unknown"


def test_bowl_carries_the_bed_weight_at_rest(tiny_run, tiny_bowl_scene):
    """At rest (end of settling, before the rod touches) the bowl carries the whole bed: sum F_z = -m g within 1 %."""
    _, run = tiny_run
    series = run["series"]
    last_settle = np.flatnonzero(series["phase"] == 0)[-1]
    assert run["attrs"]["settled"]
    weight = bed_weight(tiny_bowl_scene)
    assert series["bowl_force"][last_settle, 2] == pytest.approx(-weight, rel=0.01)
    assert abs(series["bowl_force"][last_settle, 0]) < 0.01 * weight


def test_rod_reaches_submersion_depth_and_moves(tiny_run, tiny_bowl):
    _, run = tiny_run
    case = tiny_bowl
    series = run["series"]
    process = series["phase"] == 3
    tip = series["rod_tip_z"][process]
    bed = run["attrs"]["bed_height"]
    # the tip sits d_s below the settled surface (to within one insertion step of travel)
    assert tip[0] == pytest.approx(bed - case.workpiece.submersion_depth, abs=case.workpiece.insertion_speed * 2e-3)
    assert np.ptp(tip) < 1e-9  # no vertical motion while dragging
    wf = series["workpiece_force"][process]
    assert np.all(np.isfinite(wf))
    # the media resist the motion: the mean force along the rod's velocity is negative
    assert run["measured"]["attrs"]["fn_mean"] < 0


def test_network_and_intensity(tiny_run):
    _, run = tiny_run
    net = run["contacts"]["0"]
    assert net["attrs"]["process_time"] == pytest.approx(0.05, abs=2e-3)
    assert len(net["normal_force"]) > 20 and np.all(net["normal_force"] >= 0)
    rod = run["meshes"]["rod"]
    assert rod["contact_intensity"].shape == (len(rod["faces"]),) and rod["contact_intensity"].max() > 0


def test_contact_starts_on_the_rod(tiny_run):
    assert_engine_impacts(tiny_run[1])


def test_timeout_keeps_status_and_partial_data(tmp_path):
    out = tmp_path / "slow"
    proc = subprocess.run(
        [sys.executable, "-m", "orchestrator", "run", str(TINY_BOWL), "--out", str(out), "--timeout", "6",
         "--set", "process.duration=100", "--no-progress"],
        capture_output=True, text=True, timeout=300,
    )
    assert proc.returncode != 0
    assert "Traceback" not in proc.stderr and "--timeout" in proc.stderr
    run = read_run(out)
    assert run["attrs"]["status"] == "timeout"
    assert len(run["series"]["time"]) > 5  # what was measured before the stop is kept
    from orchestrator.kinds.drag_finishing.yade import read_series_csv

    recorded = read_series_csv(out / "output" / "series.csv")
    assert run["attrs"]["n_steps"] == int(recorded["step"][-1]) > 1000  # the last recorded step
    assert "engine.log" in {p.name for p in out.iterdir()}


def test_soft_settling_then_stiffening_keeps_the_bed_at_rest(tmp_path):
    """Settle at E/1000, stiffen x100 to E/10 over 0.02 s with damping: afterwards the bowl and the
    rod still carry the bed's weight within 1 %, the bed is at rest, and the process runs at E/10's step."""
    out = tmp_path / "stiffened"
    proc = subprocess.run(
        [sys.executable, "-m", "orchestrator", "run", str(TINY_BOWL), "--out", str(out), "--json", "--no-progress",
         "--set", "numerics.stiffness_scale=0.1", "--set", "settling.stiffness_scale=0.001",
         "--set", "process.duration=0.05", "--set", "output.network_times=[0.05]"],
        capture_output=True, text=True, timeout=600,
    )
    assert proc.returncode == 0, proc.stderr
    run = read_run(out)
    model = load_case(TINY_BOWL, overrides=["numerics.stiffness_scale=0.1"]).model
    scene = build_scene(model)
    assert run["attrs"]["dt"] == pytest.approx(scene.timestep, rel=1e-12)  # the process step: E/10's
    log = (out / "engine.log").read_text()
    assert "STIFFEN x100 over 0.02 s" in log and "STIFFENED" in log
    series = run["series"]
    before_process = np.flatnonzero(series["phase"] == 2)[-1]
    weight = bed_weight(scene)
    carried = -(series["bowl_force"][before_process, 2] + series["rod_force"][before_process, 2])
    assert carried == pytest.approx(weight, rel=0.01)
    # at rest: kinetic energy below 1e-3 m g R (mean ball speed below about 8 mm/s)
    assert series["kinetic_energy"][before_process] < 1e-3 * weight * model.media.radius
    assert np.all(run["contacts"]["0"]["normal_force"] >= 0)


def test_remeasure_reproduces_the_stored_quantities(tiny_run):
    """A stored run re-analysed (what a study does when it reuses a run) gives the values written at run time."""
    from orchestrator.measure import remeasure

    _, run = tiny_run
    stored = run["measured"]["attrs"]
    fresh = remeasure(run)
    assert stored and set(stored) <= set(fresh)
    for key, value in stored.items():
        assert fresh[key] == pytest.approx(value, rel=1e-12, nan_ok=True), key
