"""The channel's medium (kinds/afm_channel/medium.py) and the MF20 case: the developed flow against plane
Poiseuille, the inverted PTT shear law against the closed form, the cell's two parts at one flow rate, the steady
start's particles (profile, mode stresses, grain speed) and the MF20 case's sound speed, step and refusals."""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from paths import CASES

from orchestrator.case import load_case
from orchestrator.errors import CaseError
from orchestrator.kinds import build_scene
from orchestrator.kinds.afm_channel.medium import MediumLaw, cell_flow, developed_state, developed_velocity, flow_rate
from orchestrator.kinds.sph_flow.sph import deck_context
from orchestrator.reference.maxwell import Mode
from orchestrator.reference.viscoelastic_flows import ptt_multimode_steady_shear

MF20 = CASES / "afm" / "afm_channel_mf20.toml"
TABLE_III = tuple(Mode(t, v) for t, v in ((0.002, 15.0), (0.02, 40.0), (0.5, 738.0), (2.0, 756.0), (5.0, 17315.0)))


def test_a_newtonian_medium_flows_as_plane_poiseuille():
    law, gap, gradient = MediumLaw(5.0), 140e-6, 8e10
    z = np.linspace(0.0, gap, 9)
    assert developed_velocity(law, z, gap, gradient) == pytest.approx(gradient * z * (gap - z) / (2 * 5.0),
                                                                       rel=1e-5, abs=1e-12)
    assert flow_rate(law, gap, gradient) == pytest.approx(gradient * gap**3 / (12 * 5.0), rel=1e-5)
    # two parts at one flow rate: G_w H_w^3 = G_n H_n^3, L_w G_w + L_n G_n = rho f L
    flow = cell_flow(law, 8e10, (140e-6, 90e-6), (205e-6, 95e-6))
    ratio = (90e-6 / 140e-6) ** 3
    wide = 8e10 * 300e-6 / (205e-6 + 95e-6 / ratio)
    assert flow.wide_gradient == pytest.approx(wide, rel=1e-9)
    assert flow.narrow_gradient == pytest.approx(wide / ratio, rel=1e-9)


def test_the_ptt_shear_law_is_inverted_at_every_rate():
    law = MediumLaw(5.0, TABLE_III, 0.1)
    rates = np.geomspace(1e-3, 1e6, 37)
    stress = 5.0 * rates + ptt_multimode_steady_shear(rates, TABLE_III, 0.1).shear_stress
    assert law.shear_stress(rates) == pytest.approx(stress, rel=1e-12)
    assert law.rate(stress) == pytest.approx(rates, rel=1e-6)
    assert law.rate(-stress) == pytest.approx(-rates, rel=1e-6)
    # the flow rate of the shear-thinning medium exceeds that of its zero-shear viscosity, at one flow rate for both
    flow = cell_flow(law, 1e10, (140e-6, 90e-6), (205e-6, 95e-6))
    assert flow_rate(law, 90e-6, flow.narrow_gradient) == pytest.approx(flow.flow_rate, rel=1e-9)
    assert 205e-6 * flow.wide_gradient + 95e-6 * flow.narrow_gradient == pytest.approx(1e10 * 300e-6, rel=1e-12)
    assert flow.flow_rate > 100 * flow.wide_gradient * (140e-6) ** 3 / (12 * 18869.0)


def test_the_mf20_channel_starts_in_its_steady_flow():
    case = load_case(MF20, preset="quick").model
    scene = build_scene(case)
    flow, law = case.cell(), case.medium.law()
    x, v = scene.positions, scene.velocities
    medium = (scene.material == 0) & (scene.kind == 0)
    wide = medium & (x[:, 0] < case.workpiece.front)
    z = x[wide, 2] - 30e-6  # above the bottom wall's face
    assert v[wide, 0] == pytest.approx(developed_velocity(law, z, flow.wide_gap, flow.wide_gradient), rel=1e-12)
    assert np.all(v[scene.kind == 1] == 0.0) and np.all(v[:, 1:] == 0.0)
    stress = scene.state["mode_stress"].reshape(len(x), 5, 3, 3)
    # each mode's steady shear at the particle's rate: tau_xz odd about the middle, tau_xx = N1 >= 0, the rest 0
    rate = law.rate(flow.wide_gradient * (0.5 * flow.wide_gap - z))
    expected = ptt_multimode_steady_shear(np.abs(rate), TABLE_III[4:], 0.1)
    assert stress[wide, 4, 0, 2] == pytest.approx(np.sign(rate) * expected.shear_stress, rel=1e-9)
    assert stress[wide, 4, 0, 0] == pytest.approx(expected.first_normal_stress_difference, rel=1e-9)
    assert np.all(stress[~medium] == 0.0) and np.all(stress[:, :, 1, :] == 0.0)
    # the grain starts at the speed of the flow at its centre; the deck runs with the fixed step and 50 x inertia
    context = deck_context(scene)
    grain = json.loads(context["grains"][0])
    assert grain["velocity"][0] == pytest.approx(developed_velocity(law, 45e-6, flow.wide_gap, flow.wide_gradient))
    assert grain["density"] == 3950.0 * 50
    assert float(context["dt"]) == pytest.approx(case.timestep())
    medium_deck = json.loads(context["materials"][0])
    assert medium_deck["model"] == "ptt" and medium_deck["rho0"] == 1000.0 * 50
    # c0 carries the largest stress (the passage's N1 at its walls) at 1 % density, in the 50 times heavier medium
    assert medium_deck["c0"] == pytest.approx(math.sqrt(case.steady_stress() / (50 * 1000.0 * 0.01)))
    assert json.loads(context["body_force"]) == [1e7 / 50, 0.0, 0.0]


def _refusal(path, overrides=()) -> str:
    with pytest.raises(CaseError) as error:
        load_case(path, preset="quick", overrides=overrides)
    lines = str(error.value).splitlines()
    assert len(lines) == 2, lines
    return lines[1]


def test_bad_mf20_channels_are_named_in_one_line(tmp_path):
    assert "numerics.inertia_scaling = 1000 gives the grain a Reynolds number of" in \
        _refusal(MF20, ["numerics.inertia_scaling=1000"])
    path = tmp_path / "case.toml"
    path.write_text("\n".join(line for line in MF20.read_text().splitlines() if not line.startswith("epsilon")))
    assert "medium.epsilon is missing: a PTT medium" in _refusal(path)


def test_epsilon_without_modes_is_named():
    with pytest.raises(CaseError, match="medium.epsilon is a key of a PTT medium"):
        load_case(CASES / "afm" / "afm_channel_nutto.toml", overrides=["medium.epsilon=0.1"])


CHANNEL_2D = """
[case]
kind = "sph_flow"
name = "ptt_channel_developed"
engine = "sph"
[domain]
dimension = 2
lo = [0.0, -3e-5]
hi = [1e-4, 1.7e-4]
periodic = [0]
[fluid]
max_speed = 0.035
[[materials]]
name = "medium"
model = "ptt"
density = 1000.0
sound_speed = 30.7
epsilon = 0.1
solvent_viscosity = 1.0
background_pressure = {p_b}
[[materials.modes]]
relaxation_time = 1e-3
viscosity = 8.0
[physics]
terms = ["morris_viscosity", "body_force"]
body_force = [1e5, 0.0]
[[blocks]]
name = "medium"
kind = "fluid"
material = "medium"
lo = [0.0, 0.0]
hi = [1e-4, 1.4e-4]
[[blocks]]
name = "bottom"
kind = "boundary"
material = "medium"
lo = [0.0, -3e-5]
hi = [1e-4, 0.0]
[[blocks]]
name = "top"
kind = "boundary"
material = "medium"
lo = [0.0, 1.4e-4]
hi = [1e-4, 1.7e-4]
[numerics]
dx = 1e-5
h_over_dx = 1.3
dt = 2.1e-8
[simulation]
duration = 0.01
[output]
frame_interval = 0.005
series_interval = 0.005
"""


@pytest.mark.sph
def test_a_ptt_channel_started_in_its_developed_flow_keeps_it(tmp_path):
    """A periodic 2D channel (140 um, 14 particles across) of one linear PTT mode (lambda 1 ms, eta_p 8 Pa s,
    epsilon 0.1, Morris solvent 1 Pa s: beta 1/9) under 1e5 m/s^2, Wi 0.8 at the walls, started in its developed
    flow (medium.developed_state: speeds and mode stresses through the particle file): after 10 relaxation times
    the middle half of the gap runs within 7 % of it (measured +5-6 %: the SPH's own steady flow, faster still
    near the walls).
    The background pressure of the walls' first normal stress difference keeps it there: without it the flow
    doubled and turned over by 10 relaxation times (the tension along the streamlines)."""
    import os
    import subprocess

    import h5py
    from paths import REPO

    from orchestrator.kinds.sph_flow.sph import TEMPLATE, write_particles
    from orchestrator.templating import render

    executable = Path(os.environ.get("ORCHESTRATOR_SPH") or REPO / "engines/sph/build/sph")
    if not executable.exists():
        pytest.skip(f"{executable} is not built")

    law, gap, gradient = MediumLaw(1.0, (Mode(1e-3, 8.0),), 0.1), 1.4e-4, 1000.0 * 1e5
    wall_rate = law.rate(np.array([0.5 * gap * gradient]))
    n1 = float(law.mode_stresses(wall_rate)[0, :, 1].sum())
    path = tmp_path / "case.toml"
    path.write_text(CHANNEL_2D.format(p_b=n1))
    scene = build_scene(load_case(path).model)
    medium = scene.kind == 0
    velocities, stresses = np.array(scene.velocities), np.zeros((len(scene.masses), 1, 2, 2))
    velocities[medium, 0], stresses[medium] = developed_state(law, scene.positions[medium, 1], gap, gradient, 2)
    scene = replace(scene, velocities=velocities, state={"mode_stress": stresses.reshape(len(stresses), -1)})
    write_particles(scene, tmp_path / "particles.h5")
    (tmp_path / "deck.json").write_text(render(TEMPLATE, deck_context(scene, threads=2)))
    done = subprocess.run([str(executable), "deck.json"], cwd=tmp_path, capture_output=True, text=True, timeout=600,
                          env={**os.environ, "OMP_WAIT_POLICY": "PASSIVE"})
    assert done.returncode == 0, done.stderr[-2000:]
    with h5py.File(tmp_path / "out.h5") as out:
        last = out["frames"][max(out["frames"], key=int)]
        x, v, kind = last["positions"][()], last["velocities"][()], last["kind"][()]
    fluid = kind == 0
    z, u = x[fluid, 1], v[fluid, 0]
    middle = (z > 0.25 * gap) & (z < 0.75 * gap)  # the SPH's own profile: 1.05 here, 1.08 at 2.5 dx, 1.39 at the wall
    assert u[middle] == pytest.approx(developed_velocity(law, z[middle], gap, gradient), rel=0.07)
    assert np.abs(v[fluid, 1]).max() < 1e-3 * u.max()
