"""Hard cases (cases/hard/): a time step above the stable limit, very stiff
contacts at high speed, a dense polydisperse pile. A run either ends "ok"
with the right answer or "unstable" with the cause and the fix, never with
silent garbage or a crash; on the reference DEM and on Yade alike."""

from __future__ import annotations

import subprocess
import sys

import pytest

from orchestrator.kinds.impact.analysis import evaluate_checks
from orchestrator.case import load_case
from orchestrator.errors import EngineUnstable
from orchestrator.run import run_case
from orchestrator.runh5 import read_run
from paths import CASES

HARD = CASES / "hard"
ENGINES = [
    "reference",
    pytest.param("yade", marks=[pytest.mark.yade, pytest.mark.yade]),
]


@pytest.mark.parametrize("engine", ENGINES)
def test_a_time_step_above_the_limit_ends_unstable_with_cause_and_fix(tmp_path, engine):
    out = tmp_path / "run"
    proc = subprocess.run([sys.executable, "-m", "orchestrator", "run", str(HARD / "timestep_above_limit.toml"),
                           "--engine", engine, "--out", str(out), "--no-progress"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 7 and proc.stderr.startswith("error:") and "Traceback" not in proc.stderr
    for words in ("numerically unstable", "energy grew", "likely cause: numerics.timestep = 2e-05 s",
                  "1.55 times the critical step", "in 1.88 steps", "fix: remove numerics.timestep"):
        assert words in proc.stderr, words
    run = read_run(out)
    assert run["attrs"]["status"] == "unstable" and "likely cause" in run["attrs"]["message"]
    assert len(run["series"]["time"]) >= 2  # what was recorded before the stop is kept


@pytest.mark.parametrize("engine", ENGINES)
def test_steel_on_steel_at_200_m_per_s_is_resolved_at_the_default_step(tmp_path, engine):
    loaded = load_case(HARD / "steel_on_steel_fast.toml")
    summary = run_case(loaded, engine=engine, out_dir=tmp_path / "run", progress=False)
    assert summary.status == "ok"
    rows = evaluate_checks(loaded.model, summary.measured)
    assert rows and all(row.passed for row in rows), rows
    # measured: peak force 3.2e-4 above Hertz, duration 2.8e-4 below, on both engines
    assert max(row.rel_error for row in rows) < 2e-3


@pytest.mark.parametrize("engine", ENGINES)
def test_dense_pile_settles_at_the_default_step_and_blows_up_at_four_times_the_limit(tmp_path, engine):
    summary = run_case(load_case(HARD / "dense_pile.toml"), engine=engine, out_dir=tmp_path / "ok", progress=False)
    assert summary.status == "ok" and summary.n_particles == 91
    assert "n_contacts" not in summary.measured  # a pile's contacts are not impacts: no events on any engine
    run = read_run(tmp_path / "ok")
    assert run["series"]["n_contacts"].max() >= 50  # measured 61 (reference) and 67 (Yade) at once
    energy = run["series"]["kinetic_energy"] + run["series"]["potential_energy"]
    assert energy[-1] < energy[0]  # it loses energy, as it must
    with pytest.raises(EngineUnstable) as info:
        run_case(load_case(HARD / "dense_pile.toml", overrides=["numerics.timestep=4.4e-4"]), engine=engine,
                 out_dir=tmp_path / "unstable", progress=False)
    message = str(info.value)
    assert "4.01 times the critical step" in message and "fix: remove numerics.timestep" in message
    assert info.value.summary.status == "unstable"
    assert read_run(tmp_path / "unstable")["attrs"]["status"] == "unstable"
