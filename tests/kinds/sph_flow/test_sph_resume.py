"""`orchestrator run --resume` on sph runs (kinds/sph_flow/resume.py): a stopped run continues from its last frame.

The engine-run test ends a pipe flow (velocity inlet, held-pressure outlet, walls with wall points) at a time off
the output grid, runs it on (`--until`) and compares it with the uninterrupted run: everything before the stop is that run's,
and after it the kinetic energy agrees to 1e-4 of its largest value (measured on 2026-11-27: 2e-7; the resumed
run recomputes its first rates from the frame and sums in another order, so it is close, not bitwise).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import h5py
import numpy as np
import pytest

from orchestrator.engines.base import Result, Series
from orchestrator.errors import OrchestratorError
from orchestrator.kinds.sph_flow.resume import (RESUME_DECK, RESUME_PARTICLES, merge_parts, part_files,
                                                write_resume_input)
from orchestrator.runh5 import read_run
from paths import VERIFICATION

PIPE = VERIFICATION / "sph_pipe_hagen_poiseuille.toml"
STOP = 0.4623  # s: off the 0.05 s output grid, as a timeout's stop is


def _run(*args) -> int:
    from orchestrator.cli import main

    return main(["run", *args, "--no-progress"])


@pytest.mark.sph
def test_a_finished_sph_run_runs_on_to_the_uninterrupted_result(tmp_path, capsys):
    whole, stopped = tmp_path / "whole", tmp_path / "stopped"
    common = [str(PIPE), "--set", "numerics.threads=1"]
    assert _run(*common, "--set", "simulation.duration=1.0", "--out", str(whole)) == 0
    assert _run(*common, "--set", f"simulation.duration={STOP}", "--out", str(stopped)) == 0
    # The finished run runs on to 1 s from its last frame (at STOP), as a run stopped there by a timeout would.
    assert _run("--resume", str(stopped), "--until", "1.0") == 0
    assert (stopped / "out.1.h5").is_file() and (stopped / RESUME_DECK).is_file()
    assert re.search(r"^duration = 1\.0$", (stopped / "case.toml").read_text(), re.M)
    a, b = read_run(whole), read_run(stopped)
    assert b["attrs"]["status"] == "ok"
    assert b["attrs"]["simulated_time"] == pytest.approx(1.0, rel=1e-12)
    assert abs(int(b["attrs"]["n_steps"]) - int(a["attrs"]["n_steps"])) <= 2
    ta, tb = a["series"]["time"], b["series"]["time"]
    # B's rows: A's grid up to the stop, the stop, then A's grid again (no repeat at the stop).
    assert np.all(np.diff(tb) > 0)
    np.testing.assert_allclose(np.sort(np.r_[ta, STOP]), tb, rtol=1e-9)
    rows = np.searchsorted(tb, ta - 1e-12)
    ke_a, ke_b = a["series"]["kinetic_energy"], b["series"]["kinetic_energy"][rows]
    before = ta <= STOP
    np.testing.assert_allclose(ke_b[before], ke_a[before], rtol=1e-12)
    assert np.max(np.abs(ke_b - ke_a)) < 1e-4 * np.max(np.abs(ke_a))
    capsys.readouterr()
    assert _run("--resume", str(stopped)) == 2
    assert "the run finished" in capsys.readouterr().err


def _part(times, values, t_start=None, steps=10, dt=1e-3, wall=2.0, frames=(), status="ok", **attrs):
    result = Result(status=status, time=np.asarray(times, float),
                    series={"q": Series(np.asarray(values, float), "m3/s")},
                    frames=[(t, {"ids": np.arange(2)}) for t in frames],
                    attrs={"n_steps": steps, "dt": dt, "engine_wall_time_s": wall, "particle_steps_per_s": 100.0,
                           **attrs})
    return result, ({} if t_start is None else {"t_start": t_start})


def test_merge_parts_joins_at_each_start_and_sums_the_cost():
    first = _part([0.0, 0.1, 0.2, 0.25], [0, 1, 2, 3], steps=30, dt=1e-3, wall=3.0, frames=[0.0, 0.2, 0.25],
                  status="failed")
    second = _part([0.25, 0.3, 0.4], [0, 4, 5], t_start=0.25, steps=10, dt=2e-3, wall=1.0, frames=[0.25, 0.4],
                   last_good_frame=1, status="unstable")
    merged = merge_parts([first, second])
    np.testing.assert_array_equal(merged.time, [0.0, 0.1, 0.2, 0.25, 0.3, 0.4])
    np.testing.assert_array_equal(merged.series["q"].values, [0, 1, 2, 3, 4, 5])
    assert [t for t, _ in merged.frames] == [0.0, 0.2, 0.25, 0.4]
    assert merged.attrs["last_good_frame"] == 3  # the second part's frame 1 (0.4 s)
    assert merged.attrs["n_steps"] == 40 and merged.attrs["engine_wall_time_s"] == 4.0
    assert merged.attrs["dt"] == pytest.approx((30 * 1e-3 + 10 * 2e-3) / 40)
    assert merged.status == "unstable" and merged.attrs["engine_parts"] == 2


def test_merge_parts_keeps_the_data_when_the_last_part_wrote_nothing():
    first = _part([0.0, 0.1], [0, 1], frames=[0.0, 0.1], status="failed")
    broken = (Result(status="failed", message="the engine wrote no out.h5"), {})
    merged = merge_parts([first, broken])
    assert len(merged.time) == 2 and len(merged.frames) == 2
    assert merged.status == "failed" and "no out.h5" in merged.message


def test_part_files_are_in_run_order(tmp_path):
    for name in ("out.h5", "out.2.h5", "out.10.h5", "out.1.h5", "out.x.h5"):
        (tmp_path / name).write_bytes(b"")
    assert [p.name for p in part_files(tmp_path)] == ["out.1.h5", "out.2.h5", "out.10.h5", "out.h5"]


def _stopped_run(tmp_path: Path, status="terminated", materials=None) -> Path:
    """A run directory as the engine leaves it: deck.json, particles.h5 (2 boundary rows, 1 fluid) and out.h5 whose
    last frame also holds a particle an inlet made (id 7) and an outlet particle."""
    deck = {"dimension": 2, "dx": 0.1, "rho0": 1000.0, "t_end": 1.0, "particles_file": "particles.h5",
            "inlets": [{"name": "in", "velocity": 1.0}]}
    if materials:
        deck["materials"] = materials
        deck["inlets"][0]["material"] = materials[1]["name"]
    (tmp_path / "deck.json").write_text(json.dumps(deck))
    with h5py.File(tmp_path / "particles.h5", "w") as h5:
        h5["masses"] = [1.0, 2.0, 3.0]
        h5["wall_point"] = [[0.0, 0.5], [1.0, 0.5], [np.nan, np.nan]]
        h5["densities"] = [1000.0, 1000.0, 999.0]
        if materials:
            h5["material"] = np.array([0, 0, 0], dtype=np.int32)
    with h5py.File(tmp_path / "out.h5", "w") as h5:
        h5.attrs["status"] = status
        h5.attrs["message"] = "unstable at t = 0.3 s" if status == "unstable" else ""
        for k, t in enumerate((0.0, 0.3)):
            g = h5.create_group(f"frames/{k}")
            g.attrs["time"], g.attrs["step"] = t, 100 * k
            g["ids"] = np.array([0, 1, 2, 7], dtype=np.int64)
            g["kind"] = np.array([1, 1, 0, 3], dtype=np.int8)
            g["positions"] = np.arange(8.0).reshape(4, 2) + t
            g["velocities"] = np.ones((4, 2))
            g["densities"] = np.array([-305.0, 1001.0, 1001.0, 1001.0])  # an old engine's drifted wall density
            g["pressures"] = np.zeros(4)
        del h5["frames/1/pressures"]  # a frame cut off while it was written: the one before is the last whole one
        g = h5.create_group("frames/2")
        g.attrs["time"] = 0.4
    return tmp_path


def test_resume_input_writes_the_last_whole_frame_with_masses_and_wall_points(tmp_path):
    run = _stopped_run(tmp_path)
    assert write_resume_input(run) == RESUME_DECK
    assert (run / "out.1.h5").is_file() and not (run / "out.h5").exists()
    deck = json.loads((run / RESUME_DECK).read_text())
    assert deck["t_start"] == 0.0 and deck["step_start"] == 0 and deck["particles_file"] == RESUME_PARTICLES
    with h5py.File(run / RESUME_PARTICLES, "r") as h5:
        np.testing.assert_array_equal(h5["ids"][()], [0, 1, 2, 7])
        np.testing.assert_array_equal(h5["kind"][()], [1, 1, 0, 3])
        # the walls' densities are their input's (eq. WP3 recomputes them), the fluid's and the buffer's the frame's
        np.testing.assert_array_equal(h5["densities"][()], [1000.0, 1000.0, 1001.0, 1001.0])
        np.testing.assert_allclose(h5["masses"][()], [1.0, 2.0, 3.0, 1000.0 * 0.1 ** 2])
        np.testing.assert_array_equal(h5["wall_point"][()][:2], [[0.0, 0.5], [1.0, 0.5]])
        assert np.isnan(h5["wall_point"][()][2:]).all()
        assert "material" not in h5


def test_resume_input_gives_inlet_particles_the_inlets_material(tmp_path):
    materials = [{"name": "water", "rho0": 1000.0}, {"name": "paste", "rho0": 1500.0}]
    run = _stopped_run(tmp_path, materials=materials)
    write_resume_input(run)
    with h5py.File(run / RESUME_PARTICLES, "r") as h5:
        np.testing.assert_array_equal(h5["material"][()], [0, 0, 0, 1])
        assert h5["masses"][3] == pytest.approx(1500.0 * 0.01)


@pytest.mark.parametrize("status, words", [("ok", "the run finished"), ("unstable", "went unstable")])
def test_resume_input_refuses_finished_and_unstable_runs(tmp_path, status, words):
    run = _stopped_run(tmp_path, status=status)
    with pytest.raises(OrchestratorError, match=words):
        write_resume_input(run)
    assert (run / "out.h5").is_file()  # nothing moved


def test_resume_input_carries_the_materials_state(tmp_path):
    """A solid's deviatoric stress and scalars and a PTT fluid's mode stresses reach the particle file as the frame
    holds them (rows in the frame's order, which the ids name); the engine reads them back (restore_fields.h)."""
    run = _stopped_run(tmp_path)
    stress, state, modes = np.arange(16.0).reshape(4, 4), np.arange(24.0).reshape(4, 6), np.arange(32.0).reshape(4, 8)
    with h5py.File(run / "out.h5", "a") as h5:
        h5["frames/0/stress"], h5["frames/0/solid_state"], h5["frames/0/mode_stress"] = stress, state, modes
    write_resume_input(run)
    with h5py.File(run / RESUME_PARTICLES, "r") as h5:
        for name, values in (("stress", stress), ("solid_state", state), ("mode_stress", modes)):
            np.testing.assert_array_equal(h5[name][()], values)


@pytest.mark.parametrize("key", ["impactors", "lees_edwards"])
def test_resume_input_refuses_state_a_frame_does_not_hold(tmp_path, key):
    """A rigid impactor's pose and spin, a Lees-Edwards cell's strain: not in the frames, so --resume refuses such
    a run and moves nothing."""
    run = _stopped_run(tmp_path)
    deck = json.loads((run / "deck.json").read_text())
    deck[key] = [{"name": "g"}] if key != "lees_edwards" else {"shear_rate": 1.0}
    (run / "deck.json").write_text(json.dumps(deck))
    with pytest.raises(OrchestratorError, match="start the run again"):
        write_resume_input(run)
    assert (run / "out.h5").is_file() and not (run / "out.1.h5").exists()


def test_a_grains_motion_is_its_particles_rigid_motion_made_whole_across_the_box():
    """grain_motion: particles of a rigid motion v = V + omega x r, one of them wrapped across a periodic face."""
    from orchestrator.kinds.sph_flow.resume import grain_motion

    rng = np.random.default_rng(5)
    x = rng.uniform(-1e-3, 1e-3, (30, 3)) + [0.0995, 0.05, 0.05]
    V, omega = np.array([0.1, -0.2, 0.05]), np.array([3.0, -1.0, 2.0])
    v = V + np.cross(omega, x - x.mean(axis=0))
    wrapped = x.copy()
    wrapped[x[:, 0] > 0.1, 0] -= 0.1  # the box is [0, 0.1) along x
    whole, velocity, spin = grain_motion(wrapped, v, {"axes": [0], "lo": [0.0], "hi": [0.1]})
    np.testing.assert_allclose(whole - whole[0], x - x[0], atol=1e-15)
    np.testing.assert_allclose(velocity, V, rtol=1e-12)
    np.testing.assert_allclose(spin, omega, rtol=1e-10)


@pytest.mark.sph
def test_a_stopped_grain_run_resumes_to_the_uninterrupted_result(tmp_path):
    """Two grains colliding in a light fluid, stopped in their contact (12 ms) and resumed to 30 ms: the grains
    start again with their particles' rigid motion, and end with the whole run's velocities (measured: to 1e-8 of
    them; angular velocities, which the contact and the fluid barely drive, to 3e-5)."""
    collision = VERIFICATION / "sph_grain_collision.toml"
    common = ["--set", "numerics.threads=1"]
    assert _run(str(collision), *common, "--out", str(tmp_path / "whole")) == 0
    assert _run(str(collision), *common, "--set", "simulation.duration=0.012", "--out", str(tmp_path / "half")) == 0
    assert _run("--resume", str(tmp_path / "half"), "--until", "0.03") == 0
    a, b = read_run(tmp_path / "whole")["series"], read_run(tmp_path / "half")["series"]
    for name in ("left", "right"):
        va, vb = a[f"grain_{name}_velocity"][-1], b[f"grain_{name}_velocity"][-1]
        assert np.abs(vb - va).max() < 1e-6 * np.abs(va).max()
        wa, wb = a[f"grain_{name}_angular_velocity"][-1], b[f"grain_{name}_angular_velocity"][-1]
        assert np.abs(wb - wa).max() < 1e-3 * np.abs(wa).max()


@pytest.mark.sph
def test_a_stopped_ptt_run_resumes_to_the_uninterrupted_result(tmp_path):
    """The Oldroyd-B start-up in a channel (quick preset), stopped at 0.1 s and resumed to 0.2 s: its mode stresses
    come back from the frame, and the kinetic energy follows the whole run's to 1e-10 of its largest value (measured
    1.0e-10; without the stresses it was 19 % above it at 0.2 s)."""
    channel = VERIFICATION / "sph_oldroyd_b_poiseuille.toml"
    common = ["--preset", "quick", "--set", "numerics.threads=1"]
    assert _run(str(channel), *common, "--set", "simulation.duration=0.2", "--out", str(tmp_path / "whole")) == 0
    assert _run(str(channel), *common, "--set", "simulation.duration=0.1", "--out", str(tmp_path / "half")) == 0
    assert _run("--resume", str(tmp_path / "half"), "--until", "0.2") == 0
    a, b = read_run(tmp_path / "whole")["series"], read_run(tmp_path / "half")["series"]
    np.testing.assert_allclose(b["time"], a["time"], rtol=1e-9)
    assert np.abs(b["kinetic_energy"] - a["kinetic_energy"]).max() < 1e-8 * a["kinetic_energy"].max()


@pytest.mark.sph
def test_a_stopped_solid_run_resumes_to_the_uninterrupted_result(tmp_path):
    """The quick Taylor bar, stopped half-way through the impact and resumed, against the whole run: its stresses,
    plastic strain, temperature and damage come back from the frame (before: the bar went on as a virgin material,
    its face's plastic strain 0.004 instead of 1.95, the energy balance -99 %)."""
    from orchestrator.case import load_case
    from orchestrator.run import run_case
    from paths import CASES

    bar = CASES / "verification" / "taylor_bar_42crmo4.toml"
    common = ["numerics.threads=1", "simulation.frames=4"]
    whole = run_case(load_case(bar, preset="quick", overrides=[*common, "simulation.duration=3e-5"]), engine="sph",
                     out_dir=tmp_path / "whole", progress=False).measured
    half = load_case(bar, preset="quick", overrides=[*common, "simulation.duration=1.5e-5"])
    run_case(half, engine="sph", out_dir=tmp_path / "half", progress=False)
    assert _run("--resume", str(tmp_path / "half"), "--until", "3e-5") == 0
    resumed = read_run(tmp_path / "half")["measured"]["attrs"]
    assert whole["face_plastic_strain"] > 0.5  # the impact has yielded the face
    for name in ("final_length", "face_diameter", "face_plastic_strain", "face_temperature", "rebound_speed"):
        assert resumed[name] == pytest.approx(whole[name], rel=5e-3), name
    assert resumed["energy_balance"] == pytest.approx(whole["energy_balance"], abs=5e-4)  # the same balance


def test_resume_input_refuses_a_run_without_output(tmp_path):
    run = _stopped_run(tmp_path)
    (run / "out.h5").unlink()
    with pytest.raises(OrchestratorError, match="no out.h5; there is nothing to continue from"):
        write_resume_input(run)


def test_resume_input_runs_a_finished_run_on_to_a_later_end(tmp_path):
    run = _stopped_run(tmp_path, status="ok")
    assert write_resume_input(run, t_end=2.5) == RESUME_DECK
    deck = json.loads((run / RESUME_DECK).read_text())
    assert deck["t_end"] == 2.5 and deck["t_start"] == 0.0 and deck["particles_file"] == RESUME_PARTICLES
    assert (run / "out.1.h5").is_file()


@pytest.mark.parametrize("status", ["ok", "terminated"])
def test_resume_input_refuses_an_end_not_after_the_last_frame(tmp_path, status):
    run = _stopped_run(tmp_path, status=status)
    with h5py.File(run / "out.h5", "a") as h5:  # the last whole frame at 0.8 s
        h5["frames/0"].attrs["time"] = 0.8
    words = "the run finished" if status == "ok" else "last frame is at 0.8 s, not before the end time 0.5 s"
    with pytest.raises(OrchestratorError, match=words):
        write_resume_input(run, t_end=0.5)
    if status == "terminated":  # the deck's own end time still works
        assert json.loads((run / write_resume_input(run)).read_text())["t_end"] == 1.0


def test_until_goes_with_resume_only_and_after_the_runs_duration(tmp_path, capsys):
    assert _run(str(PIPE), "--until", "2.0", "--out", str(tmp_path / "new")) == 2
    assert "--until goes with --resume" in capsys.readouterr().err
    assert not (tmp_path / "new").exists()
    run = tmp_path / "done"
    run.mkdir()
    (run / "case.toml").write_text(PIPE.read_text().split("[presets")[0])
    from orchestrator.rundir import MARKER

    (run / MARKER).write_text(json.dumps({"engine": "sph", "preset": "", "mpi_ranks": None}))
    for until, words in (("0.5", "after the run's simulation.duration"), ("nan", "after the run's")):
        assert _run("--resume", str(run), "--until", until) == 2
        assert words in capsys.readouterr().err
    (run / MARKER).write_text(json.dumps({"engine": "yade", "preset": "", "mpi_ranks": None}))
    assert _run("--resume", str(run), "--until", "9.0") == 2
    assert "only sph runs" in capsys.readouterr().err


def test_resume_input_after_a_resume_that_wrote_nothing_takes_the_part_before(tmp_path):
    run = _stopped_run(tmp_path)
    write_resume_input(run)  # out.h5 -> out.1.h5; say the engine then refused its input and wrote no out.h5
    assert not (run / "out.h5").exists()
    assert write_resume_input(run, t_end=2.0) == RESUME_DECK
    assert [p.name for p in sorted(run.glob("out*.h5"))] == ["out.1.h5"]  # nothing renamed
    deck = json.loads((run / RESUME_DECK).read_text())
    assert deck["t_end"] == 2.0 and deck["t_start"] == 0.0
    with h5py.File(run / RESUME_PARTICLES, "r") as h5:
        np.testing.assert_array_equal(h5["ids"][()], [0, 1, 2, 7])
