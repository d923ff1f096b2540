"""The Taylor bar on LAMMPS MACHDYN: the rendered deck read back as numbers (the Johnson-Cook card, the wall's
potential, the particles), what MACHDYN refuses, the reader on a small stored output, and (engine, slow) the quick
preset against the published shape with the tolerance its numbers support (docs/taylor_bar.md)."""

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
from orchestrator.kinds.taylor_bar.analysis import measure_taylor_bar
from orchestrator.kinds.taylor_bar.lammps import (
    DATA,
    DECK,
    LammpsTaylorBar,
    machdyn_parameters,
    run_steps,
)
from orchestrator.kinds.taylor_bar.lammps_output import (
    DUMP,
    SERIES,
    read_taylor_bar_output,
)
from orchestrator.kinds.taylor_bar.scene import wall_penalty
from orchestrator.runner import LOG_NAME

BAR = VERIFICATION / "taylor_bar_42crmo4.toml"


def _deck(tmp_path, overrides=()):
    case = load_case(BAR, preset="quick", overrides=list(overrides)).model
    scene = build_scene(case)
    LammpsTaylorBar().write_input(None, scene, tmp_path)
    return case, scene, (tmp_path / DECK).read_text()


def test_the_johnson_cook_card_is_the_case_material(tmp_path):
    """E and nu from G = 79.5769 GPa and K = 172.417 GPa are DynELA's 206.9 GPa and 0.3; the Johnson-Cook numbers,
    the viscosity (alpha / 2, beta / 4 for MACHDYN's mu written with 2h) and C_p are the case's."""
    case, scene, deck = _deck(tmp_path)
    card = pair_coeff_blocks(deck)
    rho0, young, poisson, q1, q2, hourglass, cp = card["*COMMON"]
    assert rho0 == 7830.0 and young == pytest.approx(206.9e9, rel=1e-5) and poisson == pytest.approx(0.3, rel=1e-5)
    assert (q1, q2, hourglass, cp) == (0.25, 0.25, 10.0, 460.0)
    assert card["*EOS_LINEAR"] == []
    np.testing.assert_allclose(card["*JOHNSON_COOK"], [806e6, 614e6, 0.168, 0.0089, 1.0, 293.15, 1813.15, 1.1],
                               rtol=1e-12)
    assert list(card) == ["*COMMON", "*EOS_LINEAR", "*JOHNSON_COOK", "*END"]
    mapped = machdyn_parameters(scene)
    bulk = mapped["E"] / (3.0 * (1.0 - 2.0 * mapped["nu"]))
    shear = mapped["E"] / (2.0 * (1.0 + mapped["nu"]))
    assert bulk == pytest.approx(172.417e9, rel=1e-12) and shear == pytest.approx(79.5769e9, rel=1e-12)
    assert case.case.name not in deck and case.case.name not in (tmp_path / DATA).read_text()


def test_the_wall_potential_gives_the_sph_wall_force(tmp_path):
    """-dE/dr of the deck's Lepton expression is eq. 14: F(0) = psi, zero at s = 0.99 dx and beyond the range dx."""
    case, _, deck = _deck(tmp_path)
    m = re.search(r'wall/lepton zlo 0\.0 "([^"]+)" (\S+) units box', deck)
    expression, reach = m.group(1), float(m.group(2))
    assert re.fullmatch(r"[0-9eE+\-.*/()^r]+", expression)  # numbers and r only
    energy = lambda r: eval(expression.replace("^", "**"), {"__builtins__": {}}, {"r": r})
    wall = wall_penalty(case)
    big_r, s, psi = wall["range"], wall["s"], wall["psi"]
    assert reach == big_r and energy(big_r) == pytest.approx(0.0, abs=1e-20)
    for d in (1e-7, 0.25 * big_r, 0.5 * big_r, s, 0.995 * big_r):
        step = 1e-9 * big_r
        force = -(energy(d + step) - energy(d - step)) / (2.0 * step)
        e = big_r - d
        expected = psi * (e**4 - (big_r - s) ** 2 * e**2) / (big_r**2 * s * (2.0 * big_r - s))
        assert force == pytest.approx(expected, rel=1e-5, abs=1e-6 * psi)


def test_the_data_file_holds_the_scene_particles(tmp_path):
    case, scene, deck = _deck(tmp_path)
    lines = (tmp_path / DATA).read_text().splitlines()
    start = lines.index("Atoms # smd") + 2
    rows = np.array([line.split() for line in lines[start:start + len(scene.positions)]], dtype=float)
    dx = case.numerics.dx
    np.testing.assert_array_equal(rows[:, 0], np.arange(1, len(scene.positions) + 1))
    np.testing.assert_allclose(rows[:, 3], dx**3, rtol=1e-15)
    np.testing.assert_allclose(rows[:, 4], 7830.0 * dx**3, rtol=1e-15)
    np.testing.assert_allclose(rows[:, 5], 1.5 * dx, rtol=1e-15)  # kernel radius h: the pair support is our 2h
    np.testing.assert_array_equal(rows[:, 7:10], scene.positions)
    np.testing.assert_array_equal(rows[:, 10:13], scene.positions)
    steps, dt, per_frame = run_steps(scene)
    assert steps == 8 * per_frame and dt <= scene.timestep and steps * dt == pytest.approx(8e-5, rel=1e-12)
    assert float(re.search(r"^timestep\s+(\S+)", deck, re.MULTILINE).group(1)) == dt
    assert int(re.search(r"^run\s+(\d+)", deck, re.MULTILINE).group(1)) == steps


@pytest.mark.parametrize("override, words", [
    ('material.solid.rate_form="power"', "rate form 'power'"),
    ("material.solid.failure={d1=0.1, d2=0.2, d3=-1.0}", "Johnson-Cook failure"),
])
def test_what_machdyn_cannot_run_is_named(override, words):
    case = load_case(BAR, preset="quick", overrides=[override]).model
    with pytest.raises(OrchestratorError, match=re.escape(words)):
        LammpsTaylorBar().check_scene(None, build_scene(case))


def _stored_output(tmp_path, scene, steps: int, finished: bool = True):
    """A MACHDYN output of two records (the start and steps) for the scene's particles, in reverse id order."""
    (tmp_path / "output").mkdir()
    n = len(scene.positions)
    header = "ITEM: ATOMS id x y z vx vy vz c_plastic_strain c_energy\n"
    text = ""
    for step, eps, speed in ((0, 0.0, -287.0), (steps, 0.5, 20.0)):
        rows = "".join(f"{i + 1} {x[0]!r} {x[1]!r} {x[2]!r} 0 0 {speed} {eps} {1e-3 * eps}\n"
                       for i, x in reversed(list(enumerate(scene.positions.tolist()))))
        text += (f"ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{n}\nITEM: BOX BOUNDS ss ss ss\n0 1\n0 1\n0 1\n"
                 + header + rows)
    (tmp_path / DUMP).write_text(text)
    (tmp_path / SERIES).write_text(f"# step time kinetic_energy internal_energy wall_force\n0 0 331.0 0 0\n{steps} "
                                   "8e-05 1.3 2.1 0\n")
    log = f"Loop time of 86.5 on 1 procs for {steps} steps with {n} atoms\n"
    (tmp_path / LOG_NAME).write_text(log + ("STATUS finished step=1 t=8e-05\n" if finished else ""))


def test_the_reader_gives_frames_that_measure_taylor_bar_reads(tmp_path):
    case = load_case(BAR, preset="quick").model
    scene = build_scene(case)
    _stored_output(tmp_path, scene, run_steps(scene)[0])
    result = read_taylor_bar_output(tmp_path, scene, run_steps(scene))
    assert result.status == "ok" and len(result.frames) == 2 and result.frames[-1][0] == pytest.approx(8e-5)
    frame = result.frames[-1][1]
    np.testing.assert_array_equal(frame["ids"], np.arange(len(scene.positions)))  # sorted back to input order
    np.testing.assert_array_equal(frame["positions"], scene.positions)
    mass = 7830.0 * case.numerics.dx**3
    np.testing.assert_allclose(frame["internal_energy"], 5e-4 / mass, rtol=1e-12)  # J per particle -> J/kg
    assert "temperature" not in frame
    assert result.series["internal_energy"].values[-1] == 2.1 and result.attrs["engine_wall_time_s"] == 86.5
    measured = measure_taylor_bar(case, result)
    assert measured["final_length"] == pytest.approx(case.bar.length, rel=1e-12)
    assert measured["face_plastic_strain"] == 0.5 and measured["rebound_speed"] == 20.0
    assert "face_temperature" not in measured and "max_temperature" not in measured
    kinetic0 = 0.5 * mass * len(scene.positions) * 287.0**2
    expected = (0.5 * mass * len(scene.positions) * 400.0 + 5e-4 * len(scene.positions)) / kinetic0 - 1.0
    assert measured["energy_balance"] == pytest.approx(expected, rel=1e-9)


def test_an_unfinished_run_fails(tmp_path):
    scene = build_scene(load_case(BAR, preset="quick").model)
    _stored_output(tmp_path, scene, run_steps(scene)[0], finished=False)
    result = read_taylor_bar_output(tmp_path, scene, run_steps(scene))
    assert result.status == "failed" and "without finishing" in result.message


@pytest.mark.lammps
@pytest.mark.slow
def test_the_quick_bar_on_machdyn(tmp_path, capsys):
    """5 particles across the radius (4 752), about 90 s of one core. MACHDYN's bar is stiffer than the published
    one (no thermal softening, hourglass control): measured length 27.12 mm (+2.1 % beyond 26.52-26.56 mm), face
    diameter 8.71 mm (-22 % below 11.15-11.22 mm), face plastic strain 0.64 (published 1.78-1.84)."""
    import json

    from orchestrator.cli import main

    code = main(["verify", "solids", "--engine", "lammps", "--preset", "quick", "--out", str(tmp_path / "v"),
                 "--json"])
    rows = [row for row in json.loads(capsys.readouterr().out) if row["scene"].startswith("taylor_bar")]
    by = {row["quantity"]: row for row in rows}
    assert {row["engine"] for row in rows} == {"lammps"}
    assert by["final_length"]["value"] > 0.02656 and by["final_length"]["rel_error"] < 0.03
    assert by["face_diameter"]["value"] < 0.01115 and 0.15 < by["face_diameter"]["rel_error"] < 0.3
    assert by["energy_balance"]["passed"] and code != 0  # the face diameter row fails its 5 %
    from orchestrator.runh5 import read_run

    measured = read_run(next((tmp_path / "v" / "taylor_bar_42crmo4").rglob("run.h5")))["measured"]["attrs"]
    assert 0.4 < measured["face_plastic_strain"] < 0.9 and "face_temperature" not in measured
    assert math.isfinite(measured["rebound_speed"])
