"""The channel's medium (kinds/afm_channel/medium.py) and the MF20 case: the developed flow against plane
Poiseuille, the inverted PTT shear law against the closed form, the cell's two parts at one flow rate, the steady
start's particles (profile, mode stresses, grain speed) and the MF20 case's sound speed, step and refusals."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from paths import CASES

from orchestrator.case import load_case
from orchestrator.errors import CaseError
from orchestrator.kinds import build_scene
from orchestrator.kinds.afm_channel.medium import MediumLaw, cell_flow, developed_velocity, flow_rate
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
