"""The sph_flow adapter on LAMMPS (orchestrator/kinds/sph_flow/lammps.py, lammps_output.py): what it refuses, the
deck and data file read back, the dump reader on a stored record; and, with LAMMPS installed, the Couette start-up
of Morris et al. 1997 against its series, with the measured position of LAMMPS's no-slip plane."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from orchestrator.case import load_case
from orchestrator.kinds import build_scene
from orchestrator.kinds.sph_flow.lammps import DATA, deck_context, refusal, write_data_file
from orchestrator.kinds.sph_flow.lammps_output import (planned_steps, probe_pressure, read_lammps_output, read_records,
                                                       run_step, tait_pressure)
from orchestrator.runner import LOG_NAME
from orchestrator.templating import render
from orchestrator.kinds.sph_flow.lammps import TEMPLATE
from paths import VERIFICATION



def scene_of(name: str, *overrides: str):
    return build_scene(load_case(VERIFICATION / f"{name}.toml", overrides=list(overrides)).model)


@pytest.mark.parametrize("name, reason", [
    ("sph_penalty_column", "wall meshes with penalty forces"),
    ("sph_two_layer_couette", "[[materials]]"),
    ("sph_steady_ptt", "[[materials]]"),
])
def test_scenes_with_other_physics_are_refused(name, reason):
    assert reason in refusal(scene_of(name))


@pytest.mark.parametrize("name", ["sph_poiseuille_morris1997", "sph_couette_morris1997", "sph_hydrostatic_tank",
                                  "sph_dam_break_2d"])
def test_the_channel_tank_and_dam_break_are_accepted(name):
    assert refusal(scene_of(name)) == ""


def test_a_refused_scene_is_one_error_line_and_exit_2(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "orchestrator", "run", str(VERIFICATION / "sph_penalty_column.toml"),
                           "--engine", "lammps", "--out", str(tmp_path / "run"), "--no-progress"],
                          capture_output=True, text=True, timeout=300, env={"ORCHESTRATOR_LAMMPS": sys.executable,
                                                                           "PATH": "/usr/bin:/bin"})
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and "penalty" in lines[0]


def test_the_deck_carries_the_mapped_physics():
    scene = scene_of("sph_couette_morris1997")
    context = deck_context(scene)
    deck = render(TEMPLATE, context)
    assert "pair_style      sph/taitwater/morris" in deck
    words = next(line for line in deck.splitlines() if line.startswith("pair_coeff")).split()
    rho0, c0, mu, cutoff = (float(w) for w in words[3:])
    assert rho0 == 1000.0 and c0 == pytest.approx(scene.c0, rel=1e-15)
    assert mu == pytest.approx(1000.0 * 1e-6, rel=1e-15)  # rho0 nu, Pa s
    assert cutoff == pytest.approx(2 * 1.5 * 2.5e-5, rel=1e-15)
    assert "fix             plates plates sph" in deck  # the upper plate moves
    steps, dt = planned_steps(scene), run_step(scene)
    assert steps * dt == pytest.approx(1.0, rel=1e-12) and dt <= scene.timestep


def test_artificial_viscosity_maps_to_lammps_cutoff():
    context = deck_context(scene_of("sph_dam_break_2d"))
    assert context["pair_style"] == "sph/taitwater"
    assert float(context["viscosity"]) == pytest.approx(0.1 / 2)  # eq. 12's h is half LAMMPS's cutoff
    assert context["boundary"] == "s s p"
    assert context["gravity"]["y"] == "-1.0"


def test_data_file_round_trip(tmp_path):
    scene = scene_of("sph_couette_morris1997")
    before = np.array(scene.positions, copy=True)
    write_data_file(scene, tmp_path / DATA)
    text = (tmp_path / DATA).read_text()
    atoms = text.split("Atoms # sph\n\n")[1].split("\n\nVelocities")[0].splitlines()
    rows = np.array([line.split() for line in atoms], dtype=float)
    velocities = np.array([line.split() for line in text.split("Velocities\n\n")[1].strip().splitlines()], float)
    np.testing.assert_array_equal(rows[:, 5:7], scene.positions)
    np.testing.assert_array_equal(rows[:, 2], scene.densities)
    np.testing.assert_array_equal(velocities[:, 1:3], scene.velocities)
    assert set(rows[:, 1][np.asarray(scene.kind) == 0]) == {1.0}
    assert np.count_nonzero(rows[:, 1] == 3) == np.count_nonzero(np.asarray(scene.block) == 2)  # the upper plate
    np.testing.assert_array_equal(scene.positions, before)  # the scene is not changed


def _record(step: int, rows: np.ndarray) -> str:
    head = f"ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{len(rows)}\nITEM: BOX BOUNDS ss ss pp\n0 1\n0 1\n0 1\n"
    body = "\n".join(" ".join(repr(float(v)) for v in row) for row in rows)
    return head + "ITEM: ATOMS id type x y z vx vy vz c_rho\n" + body + "\n"


def test_dump_reader_series_and_frames(tmp_path):
    scene = scene_of("sph_hydrostatic_tank", "simulation.duration=0.001", "output.frame_interval=0.0005",
                     "output.series_interval=0.0005")
    n = scene.n_particles
    dt = run_step(scene)
    rows = np.zeros((n, 9))
    rows[:, 0] = np.arange(1, n + 1)
    rows[:, 1] = np.where(np.asarray(scene.kind) == 0, 1, 2)
    rows[:, 2:4] = scene.positions
    rows[:, 5] = 0.1 * (np.asarray(scene.kind) == 0)  # the fluid moving at 0.1 m/s along x
    rows[:, 8] = 1001.0
    last = planned_steps(scene)
    text = _record(0, rows) + _record(last, rows) + _record(last, rows) + _record(last + 9, rows)[:-200]
    (tmp_path / "records.dump").write_text(text)
    (tmp_path / LOG_NAME).write_text("Loop time of 0.5 on 2 procs for 16 steps with 658 atoms\n\n"
                                     "98.4% CPU use with 2 MPI tasks x 1 OpenMP threads\nDONE steps=16\n")
    assert [step for step, _ in read_records(tmp_path / "records.dump")] == [0, last]  # repeat and cut record dropped
    result = read_lammps_output(tmp_path, scene)
    assert result.status == "ok", result.message
    assert result.time[-1] == pytest.approx(0.001, rel=1e-12)
    fluid = scene.n_fluid
    assert result.series["kinetic_energy"].values[-1] == pytest.approx(0.5 * fluid * scene.masses[0] * 0.01)
    assert result.series["max_density_deviation"].values[0] == pytest.approx(1e-3)
    probe = result.series["pressure_probe_y075"].values[-1]
    assert probe == pytest.approx(float(tait_pressure(1001.0, 1000.0, scene.c0)), rel=1e-12)
    t, frame = result.frames[-1]
    assert t == pytest.approx(last * dt, rel=1e-12)  # a record's time is its step times LAMMPS's fixed step
    assert frame["pressures"][0] == pytest.approx(scene.c0**2 * 1000.0 / 7 * (1.001**7 - 1))
    assert result.attrs["engine_wall_time_s"] == 0.5
    assert result.attrs["engine_cpu_time_s"] == pytest.approx(2 * 0.5 * 0.984, rel=1e-12)  # the loop's, both ranks


def test_a_lammps_error_fails_the_run(tmp_path):
    scene = scene_of("sph_hydrostatic_tank")
    (tmp_path / LOG_NAME).write_text("ERROR: Lost atoms: original 658 current 657 (src/thermo.cpp:494)\n")
    result = read_lammps_output(tmp_path, scene)
    assert result.status == "failed" and "Lost atoms" in result.message


def test_probe_is_shepard_normalised_and_periodic():
    x = np.array([[0.05, 0.0], [0.95, 0.0]])
    p = np.array([10.0, 30.0])
    value = probe_pressure([0.0, 0.0], x, p, np.ones(2), 0.04, 2, [1.0, 0.0])  # both 0.05 m away through x
    assert value == pytest.approx(20.0)
    assert math.isnan(probe_pressure([0.5, 0.5], x, p, np.ones(2), 0.04, 2, [1.0, 0.0]))


@pytest.mark.lammps
def test_couette_on_lammps_against_the_series(tmp_path):
    """The quick Couette start-up (0.5 s, about 3 s of LAMMPS): each profile within the case's tolerance of the
    series once the no-slip planes are put where LAMMPS's fixed particles hold them, 0.64 dx beyond each plate
    (docs/verify_sph.md); against the plates themselves only the late profile is (its rows say so)."""
    from orchestrator.kinds.sph_flow.checks_base import fluid_mask, frame_at, frames_of
    from orchestrator.reference.sph_flows import couette_velocity
    from orchestrator.runh5 import read_run
    from orchestrator.workflows.verify import run_scene

    checked = run_scene(VERIFICATION / "sph_couette_morris1997.toml", "lammps", tmp_path / "run", preset="quick")
    assert checked.status == "ok", checked.message
    rows = {row["quantity"].split("(")[0] + ("_end" if "0.5" in row["quantity"] else ""): row for row in checked.rows}
    assert rows["u_profile_end"]["rel_error"] < 0.05
    run = read_run(tmp_path / "run")
    gap, nu, speed, dx = 1e-3, 1e-6, 2.5e-5, 2.5e-5
    offset = 0.64 * dx
    for wanted in (0.02, 0.04, 0.1, 0.2, 0.5):
        t, frame = frame_at(frames_of(run), wanted)
        fluid = fluid_mask(frame)
        y, u = np.asarray(frame["positions"])[fluid, 1], np.asarray(frame["velocities"])[fluid, 0]
        error = np.max(np.abs(u - couette_velocity(y + offset, t, gap + 2 * offset, nu, speed))) / speed
        assert error < 0.02, f"t = {t:.3g} s: {error:.4f}"
