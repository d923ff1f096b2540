"""The crater on LAMMPS MACHDYN: the rendered deck read back as numbers against the case (the target's card, the
contact's stiffness, the step), the data file's target and sphere, what MACHDYN refuses, the reader on a small stored
output, and (engine) a short coarse run read back through measure_crater."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from paths import VERIFICATION
from machdyn_cards import pair_coeff_blocks

from orchestrator.case import load_case
from orchestrator.errors import OrchestratorError
from orchestrator.kinds import build_scene
from orchestrator.kinds.crater.analysis import measure_crater, rim_radius
from orchestrator.kinds.crater.lammps import DATA, DECK, LammpsCrater, sphere_particles
from orchestrator.kinds.crater.lammps_output import DUMP, SERIES, read_crater_output
from orchestrator.kinds.sph_flow.machdyn import run_steps
from orchestrator.run import run_case
from orchestrator.runh5 import read_run
from orchestrator.runner import LOG_NAME

CRATER = VERIFICATION / "crater_hutchings_100cr6.toml"
HERTZ = VERIFICATION / "hertz_sphere_elastic.toml"


def _deck(tmp_path, path=CRATER, overrides=()):
    case = load_case(path, preset="quick", overrides=list(overrides)).model
    scene = build_scene(case)
    LammpsCrater().write_input(None, scene, tmp_path)
    return case, scene, (tmp_path / DECK).read_text()


def _atoms(tmp_path) -> np.ndarray:
    """The data file's Atoms rows as numbers (id type molecule volume mass h contact x0 y0 z0 x y z)."""
    lines = (tmp_path / DATA).read_text().splitlines()
    count = int(lines[2].split()[0])
    start = lines.index("Atoms # smd") + 2
    return np.array([line.split() for line in lines[start:start + count]], dtype=float)


def test_the_target_card_is_the_case_material(tmp_path):
    """E and nu give back G = 80.769 GPa and K = rho0 C0^2; the shock EOS and the Johnson-Cook numbers are the case's
    (Steinberg's 4340 and Guo and Liu's 100Cr6); the viscosity alpha / 2, beta / 4."""
    case, scene, deck = _deck(tmp_path)
    card = pair_coeff_blocks(deck)
    assert list(card) == ["*COMMON", "*EOS_SHOCK", "*JOHNSON_COOK", "*END"]
    rho0, young, poisson, q1, q2, hourglass, cp = card["*COMMON"]
    assert rho0 == 7810.0 and (q1, q2, hourglass, cp) == (0.25, 0.25, 10.0, 475.0)
    bulk, shear = young / (3.0 * (1.0 - 2.0 * poisson)), young / (2.0 * (1.0 + poisson))
    assert bulk == pytest.approx(7810.0 * 4578.0**2, rel=1e-12) and shear == pytest.approx(80.769e9, rel=1e-12)
    assert card["*EOS_SHOCK"] == [4578.0, 1.33, 1.67]
    np.testing.assert_allclose(card["*JOHNSON_COOK"],
                               [688.17e6, 150.82e6, 0.3362, 0.043, 1.0, 293.15, 1760.15, 2.7], rtol=1e-12)
    contact = float(re.search(r"^pair_coeff\s+1 2 smd/hertz (\S+)$", deck, re.M).group(1))
    assert contact == pytest.approx(bulk + 4.0 / 3.0 * shear, rel=1e-12)  # rho0 c_L^2 of the target
    steps, dt, per_frame = run_steps(scene)
    assert float(re.search(r"^timestep\s+(\S+)", deck, re.M).group(1)) == dt <= scene.timestep
    assert int(re.search(r"^run\s+(\d+)", deck, re.M).group(1)) == steps == 6 * per_frame
    assert steps * dt == pytest.approx(1.5e-6, rel=1e-12)
    assert "aveforce 0.0 0.0 0.0" in deck and " move " not in deck
    assert case.case.name not in deck


def test_the_data_file_holds_the_target_its_support_and_the_sphere(tmp_path):
    case, scene, deck = _deck(tmp_path)
    rows = _atoms(tmp_path)
    n, dx = len(scene.positions), case.numerics.dx
    target, ball = rows[:n], rows[n:]
    np.testing.assert_array_equal(target[:, 10:13], scene.positions)
    assert set(target[:, 2]) == {1.0}  # one molecule: smd/tlsph bonds the support to the target
    first, last = (int(v) for v in re.search(r"^group\s+support id (\d+):(\d+)$", deck, re.M).groups())
    np.testing.assert_array_equal(np.flatnonzero(scene.kind == 1), np.arange(first - 1, last))
    np.testing.assert_allclose(target[:, 4], 7810.0 * dx**3, rtol=1e-15)
    np.testing.assert_allclose(rows[:, 5], 1.5 * dx, rtol=1e-15)
    np.testing.assert_allclose(rows[:, 6], 0.5 * dx, rtol=1e-15)
    assert set(ball[:, 1]) == {2.0} and set(ball[:, 2]) == {2.0}
    radius, centre = 300e-6, np.array([0.0, 0.0, 300e-6 + 0.25 * dx])
    assert ball[:, 4].sum() == pytest.approx(2500.0 * 4.0 / 3.0 * math.pi * radius**3, rel=1e-12)
    distance = np.linalg.norm(ball[:, 10:13] - centre, axis=1)
    shells = radius - np.array([0.5, 1.5]) * dx  # two layers, the outer one reaching r with its contact radius
    assert np.all(np.min(np.abs(distance[:, None] - shells), axis=1) < 1e-12 * radius)
    assert ball[:, 12].min() - 0.5 * dx == pytest.approx(0.25 * dx, rel=1e-9)  # the same start gap as the sph sphere
    assert len(ball) == pytest.approx(4.0 * math.pi * np.sum(shells**2) / dx**2, abs=2)
    outer = ball[np.abs(distance - shells[0]) < 1e-9 * radius, 10:13]
    gaps = np.sort(np.linalg.norm(outer[:, None] - outer[None], axis=2), axis=1)[:, 1]
    assert 0.7 * dx < np.median(gaps) < 1.1 * dx  # about dx apart on the surface
    offset = [float(re.search(rf"xcm\(sphere,{a}\)\+\((\S+)\)", deck).group(1)) for a in "xyz"]
    np.testing.assert_allclose(ball[:, 10:13].mean(axis=0) + offset, centre, atol=1e-12 * radius)
    velocities = (tmp_path / DATA).read_text().split("Velocities")[1].split()
    assert np.array(velocities, dtype=float).reshape(-1, 4)[n:, 3].tolist() == [-100.0] * len(ball)


def test_an_indenter_moves_at_its_speed_into_an_elastic_block(tmp_path):
    case, scene, deck = _deck(tmp_path, HERTZ)
    assert list(pair_coeff_blocks(deck)) == ["*COMMON", "*EOS_LINEAR", "*STRENGTH_LINEAR", "*END"]
    motion = re.search(r"^fix\s+sphere_motion sphere move linear (\S+) (\S+) (\S+) units box$", deck, re.M)
    assert [float(v) for v in motion.groups()] == [0.0, 0.0, -0.2] and "aveforce" not in deck
    ball, centre = sphere_particles(scene), scene.case.impactors[0].spheres[0][2]
    assert len(ball) > 0 and ball[:, 2].max() <= centre  # the lower half: what can touch the block


@pytest.mark.parametrize("override, words", [
    ('material.solid.rate_form="power"', "rate form 'power'"),
    ("material.solid.failure={d1=0.1, d2=0.2, d3=-1.0}", "Johnson-Cook failure"),
])
def test_what_machdyn_cannot_run_is_named(override, words):
    case = load_case(CRATER, preset="quick", overrides=[override]).model
    with pytest.raises(OrchestratorError, match=re.escape(words)):
        LammpsCrater().check_scene(None, build_scene(case))


def _stored_output(tmp_path, scene, steps: int, finished: bool = True):
    """A MACHDYN output of two frames (the start and `steps`, the top layer's centre 5 um down at the end, eps_p
    0.2 there) and a series of a sphere going in and back out at 30 m/s, in reverse id order."""
    (tmp_path / "output").mkdir()
    n, x0 = len(scene.positions), scene.positions
    sink = np.where((np.hypot(x0[:, 0], x0[:, 1]) < 100e-6) & (x0[:, 2] > -27e-6), 5e-6, 0.0)
    text = ""
    for step, down, eps in ((0, 0.0, 0.0), (steps, 1.0, 0.2)):
        x = (x0 - np.outer(down * sink, [0, 0, 1])).tolist()
        strain = (eps * (sink > 0)).tolist()
        rows = "".join(f"{i + 1} {x[i][0]!r} {x[i][1]!r} {x[i][2]!r} 0 0 0 {strain[i]!r} 0.0\n"
                       for i in reversed(range(n)))
        text += (f"ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{n}\nITEM: BOX BOUNDS ss ss ss\n0 1\n0 1\n0 1\n"
                 "ITEM: ATOMS id x y z vx vy vz c_plastic_strain c_energy\n" + rows)
    (tmp_path / DUMP).write_text(text)
    z = [306.75e-6, 300e-6, 290e-6, 285e-6, 295e-6]
    w = [-100.0, -100.0, -40.0, 0.0, 30.0]
    f = [0.0, 0.0, 50.0, 90.0, 0.0]
    header = ("# step time x y z vx vy vz fx fy fz sphere_kinetic contact_energy target_kinetic "
              "target_internal\n")
    lines = [f"{k} {k * 1e-7} 0 0 {z[k]} 0 0 {w[k]} 0 0 {f[k]} {0.5 * w[k] ** 2} 0.0 0 0\n" for k in range(5)]
    (tmp_path / SERIES).write_text(header + "".join(lines))
    log = f"Loop time of 12.5 on 1 procs for {steps} steps with {n} atoms\n"
    (tmp_path / LOG_NAME).write_text(log + ("STATUS finished step=1 t=1.5e-06\n" if finished else ""))


def test_a_plastic_rim_that_begins_off_the_axis_is_measured_outward_from_its_peak():
    """MACHDYN's top layer stays below eps_p = 0.01 on the axis and yields in a ring round it: the rim is where the
    ring means fall below the level outside the peak."""
    r = np.linspace(0.0, 10.0, 401)
    value = np.where(r < 3.0, 0.005 + 0.01 * r, 0.035 - 0.01 * (r - 3.0))  # peak 0.035 at r = 3, 0.01 at r = 5.5
    assert rim_radius(r, value, 0.5, 0.01) == pytest.approx(5.5, abs=0.05)


def test_the_reader_gives_what_measure_crater_reads(tmp_path):
    case = load_case(CRATER, preset="quick").model
    scene = build_scene(case)
    steps = run_steps(scene)
    _stored_output(tmp_path, scene, steps[0])
    result = read_crater_output(tmp_path, scene, steps)
    assert result.status == "ok" and len(result.frames) == 2 and result.attrs["engine_wall_time_s"] == 12.5
    assert result.frames[-1][0] == pytest.approx(1.5e-6, rel=1e-12)
    frame = result.frames[-1][1]
    np.testing.assert_array_equal(frame["ids"], np.arange(len(scene.positions)))  # sorted back to input order
    np.testing.assert_array_equal(frame["kind"], scene.kind)
    assert result.series["impactor_sphere_position"].values.shape == (5, 3)
    measured = measure_crater(case, result)
    assert measured["max_penetration"] == pytest.approx(15e-6, rel=1e-9)  # r - z at the deepest, 300 - 285 um
    assert measured["contact_diameter"] == pytest.approx(2.0 * math.sqrt(2 * 300e-6 * 15e-6 - 15e-6**2), rel=1e-9)
    assert measured["restitution"] == pytest.approx(0.3, rel=1e-12) and measured["peak_force"] == 90.0
    assert measured["permanent_depth"] == pytest.approx(5e-6, rel=1e-9)
    assert 0.0 < measured["plastic_zone_diameter"] < 260e-6 and measured["max_plastic_strain"] == 0.2
    assert measured["mean_pressure"] > 0.0 and "max_temperature" not in measured


def test_an_unfinished_run_fails(tmp_path):
    scene = build_scene(load_case(CRATER, preset="quick").model)
    _stored_output(tmp_path, scene, run_steps(scene)[0], finished=False)
    result = read_crater_output(tmp_path, scene, run_steps(scene))
    assert result.status == "failed" and "without finishing" in result.message


@pytest.mark.lammps
def test_a_coarse_crater_on_machdyn(tmp_path):
    """dx 40.5 um (5 200 target and 1 700 sphere particles), the first 0.5 us: the sphere goes in, the contact
    pushes it back, the energy is kept within 1 %, and the top layer yields under it (a few seconds of one core)."""
    overrides = ["numerics.dx=40.5e-6", "numerics.threads=1", "simulation.duration=0.5e-6", "simulation.frames=2"]
    run_case(load_case(CRATER, overrides=overrides), engine="lammps", out_dir=tmp_path / "run", progress=False)
    run = read_run(tmp_path / "run" / "run.h5")
    assert run["attrs"]["status"] == "ok"
    measured = run["measured"]["attrs"]
    assert 5e-6 < measured["max_penetration"] < 30e-6 and measured["peak_force"] > 10.0
    assert abs(measured["energy_balance"]) < 0.01 and measured["max_plastic_strain"] > 0.01
    assert measured["rebound_speed"] > -100.0
