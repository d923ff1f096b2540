"""`orchestrator run --resume`: a drag-finishing run stopped after a checkpoint continues to the same result as an
uninterrupted run, on Yade (O.save / O.load between two steps) and LIGGGHTS (restart files).

Yade's resumed run is the uninterrupted one, row for row and bit for bit: at each checkpoint the running script
goes on from the file it saved (O.load), as a resumed run does. (Going on from memory instead, the collider's
bounds and the order of later contacts differed, forces were summed in another order, and the granular bed
amplified that round-off: 1.6e-12 m after the first checkpoint of the tiny bowl, 4.4e-7 m once in CI.)
The loop halts for a checkpoint once its step is complete (O.stopAtIter): halted by O.pause() from an engine,
the script saved the scene while Yade's thread still ran the step's last engines, mid-step or after it as the
threads were scheduled (about one run in four on a loaded machine).
LIGGGHTS restores balls, meshes, the rod's motion and every contact history, but its granular pair style evaluates
the first step after a restart with full-step velocities (read_restart's documentation: granular pair styles do
not restart exactly), so its resumed trajectory leaves the uninterrupted one at the checkpoint: the end state
agrees to a small fraction of a ball radius and the mean force to a few per cent. On both, everything recorded up
to the checkpoint is the uninterrupted run's, byte for byte.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from orchestrator.runh5 import read_run
from paths import TINY_BOWL

SETTINGS = ["--set", "process.duration=0.2", "--set", "output.checkpoint_interval=0.05", "--no-progress"]
ENGINES = [
    pytest.param("liggghts", marks=pytest.mark.liggghts),
    pytest.param("yade", marks=pytest.mark.yade),
]
#: The checkpoint file each engine's script writes.
CHECKPOINT = {"liggghts": "checkpoint.txt", "yade": "checkpoint.json"}
#: How close a resumed run's end state comes to the uninterrupted one's: ball positions (m), mean F_n (relative).
TOLERANCE = {"yade": (0.0, 0.0), "liggghts": (0.01 * 3.27e-3, 0.05)}


def _orchestrator(*args: str, **kwargs) -> subprocess.Popen:
    env = {**os.environ, "OMP_WAIT_POLICY": "PASSIVE"}
    return subprocess.Popen([sys.executable, "-m", "orchestrator", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env, **kwargs)


def _rows(run_dir: Path, engine: str) -> dict[int, list[str]]:
    """Recorded rows by step, as the engine wrote them (text)."""
    if engine == "yade":
        lines = (run_dir / "output" / "series.csv").read_text().splitlines()[1:]
        return {int(line.split(",")[-1]): line.split(",")[:-1] for line in lines}
    lines = (run_dir / "output" / "series.txt").read_text().splitlines()
    return {int(float(line.split()[0])): line.split()[1:] for line in lines if line.strip() and line[0] != "#"}


def _final_positions(run_dir: Path, engine: str) -> np.ndarray:
    if engine == "yade":
        return np.load(run_dir / "output" / "final.npz")["positions"]
    return np.loadtxt(run_dir / "output" / "final.dump", skiprows=9)[:, 2:5]


def _checkpoint_step(path: Path) -> int:
    if path.suffix == ".json":
        return int(json.loads(path.read_text())["step"])
    return int(dict(line.split(" ", 1) for line in path.read_text().splitlines())["step"])


@pytest.mark.parametrize("engine", ENGINES)
def test_a_stopped_run_resumes_to_the_uninterrupted_result(tmp_path, engine):
    whole, stopped = tmp_path / "whole", tmp_path / "stopped"
    settings = ["--engine", engine, *SETTINGS]
    reference = _orchestrator("run", str(TINY_BOWL), "--out", str(whole), *settings)

    run = _orchestrator("run", str(TINY_BOWL), "--out", str(stopped), *settings, start_new_session=True)
    checkpoint = stopped / "output" / CHECKPOINT[engine]
    deadline = time.monotonic() + 600
    while not checkpoint.is_file():
        assert run.poll() is None and time.monotonic() < deadline, run.communicate()
        time.sleep(0.05)
    run.send_signal(signal.SIGTERM)
    _, err = run.communicate(timeout=120)
    assert run.returncode == 143, err
    assert read_run(stopped)["attrs"]["status"] == "terminated"
    step = _checkpoint_step(checkpoint)

    _, err = reference.communicate(timeout=900)
    assert reference.returncode == 0, err
    resumed = _orchestrator("run", "--resume", str(stopped), "--json", "--no-progress")
    out, err = resumed.communicate(timeout=900)
    assert resumed.returncode == 0, err
    summary = json.loads(out)
    a, b = read_run(whole), read_run(stopped)
    assert summary["status"] == "ok" == b["attrs"]["status"]
    assert b["attrs"]["n_steps"] == a["attrs"]["n_steps"] == summary["n_steps"]
    assert b["attrs"]["simulated_time"] == pytest.approx(a["attrs"]["simulated_time"], rel=1e-12)
    assert (stopped / "engine.1.log").is_file()

    # The series continues without a gap or a repeat; up to the checkpoint it is the uninterrupted run's.
    rows_a, rows_b = _rows(whole, engine), _rows(stopped, engine)
    assert sorted(rows_a) == sorted(rows_b)
    assert all(rows_a[s] == rows_b[s] for s in rows_a if s <= step or engine == "yade")
    assert len(a["series"]["time"]) == len(b["series"]["time"])
    np.testing.assert_allclose(b["series"]["time"], a["series"]["time"], rtol=1e-12)

    # Contact starts on the rod (output.impact_window), as the engine tested them: those before the checkpoint are
    # the uninterrupted run's; Yade's restart continues them exactly, LIGGGHTS's only statistically.
    ea, eb = a["events"], b["events"]
    t_checkpoint = a["series"]["time"][sorted(rows_a).index(max(s for s in rows_a if s <= step))]
    early_a, early_b = ea["time"] <= t_checkpoint, eb["time"] <= t_checkpoint
    assert early_a.sum() == early_b.sum() > 0
    np.testing.assert_allclose(eb["engine_speed"][early_b], ea["engine_speed"][early_a], rtol=1e-12)
    if engine == "yade":
        np.testing.assert_array_equal(eb["engine_speed"], ea["engine_speed"])
    else:
        assert abs(len(eb["time"]) - len(ea["time"])) <= 0.5 * len(ea["time"])

    # After it Yade's restart is bitwise, LIGGGHTS's is not (see the module docstring).
    position_tol, force_tol = TOLERANCE[engine]
    assert np.max(np.abs(_final_positions(stopped, engine) - _final_positions(whole, engine))) <= position_tol
    fn_a, fn_b = a["measured"]["attrs"]["fn_mean"], b["measured"]["attrs"]["fn_mean"]
    assert fn_b == pytest.approx(fn_a, rel=force_tol)


def test_resume_refuses_what_it_cannot_continue(tmp_path, capsys):
    from orchestrator.cli import main

    assert main(["run", "--resume", str(tmp_path / "nothing")]) == 2
    assert "not a run directory of orchestrator" in capsys.readouterr().err
    assert main(["run", str(TINY_BOWL), "--resume", str(tmp_path)]) == 2
    assert "CASE cannot go with it" in capsys.readouterr().err
    assert main(["run"]) == 2
    assert "needs a CASE file" in capsys.readouterr().err


def test_rows_cut_off_by_the_stop_are_dropped_before_a_resume(tmp_path):
    """A stopped Yade script leaves its last row cut where the file buffer ended; cut after an integer field it
    ends in digits like a step, and kept it would take the resumed run's first row onto its line."""
    from orchestrator.kinds.drag_finishing.yade import drop_rows_after

    path = tmp_path / "series.csv"
    header = "time,n_contacts,step\n"
    path.write_text(header + "0.1,40,100\n0.2,41,200\n0.3,42,300\n0.4,43")  # cut after the contact count
    drop_rows_after(path, 200)
    assert path.read_text() == header + "0.1,40,100\n0.2,41,200\n"
    path.write_text(header + "0.1,40,100\n0.2,41,2")  # cut inside the step: a prefix below the checkpoint's
    drop_rows_after(path, 200)
    assert path.read_text() == header + "0.1,40,100\n"
