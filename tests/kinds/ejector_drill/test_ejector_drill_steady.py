"""The flow-exit scene's steady comparison with the network (preset flow_exit_steady_quick): its operating point,
the light columns and the back pressure that keeps the SPH's acoustic noise above the vapour floor."""

from __future__ import annotations

import json

import numpy as np
import pytest

from orchestrator.case.loader import load_case
from orchestrator.errors import OrchestratorError
from orchestrator.kinds import build_scene
from orchestrator.drill.series import sensor_pressures
from orchestrator.kinds.ejector_drill.flows import less_back_pressure
from orchestrator.kinds.sph_flow.sph import TEMPLATE, deck_context
from orchestrator.reference.drill_network import LITRE_PER_MIN, solve
from orchestrator.templating import render
from paths import CASES

CASE = CASES / "ejector_drill_canini.toml"


def _deck(case) -> dict:
    return json.loads(render(TEMPLATE, deck_context(build_scene(case), threads=1)))


def test_the_steady_preset_runs_at_the_networks_operating_point():
    """Its inflow is the network's V_AG at the case's network_flow (60 l/min) over the gap, and c0 is ten times
    the engine's bound on the inlet profile's peak (2 x the mean)."""
    case = load_case(CASE, preset="flow_exit_steady_quick").model
    net = case.network()
    v_ag = solve(net, case.scene.network_flow * LITRE_PER_MIN).V_AG
    assert case.scene.inlet_velocity * net.annular_gap().area == pytest.approx(v_ag, rel=1e-3)
    assert case.c0 >= 10.0 * 2.0 * case.scene.inlet_velocity
    assert case.scene.columns and 0.0 < case.scene.column_inertia < 1.0


def test_the_back_pressure_lifts_the_rest_and_both_held_pressures():
    """scene.back_pressure adds to eq. 6's p_B and to both outlets' held pressures; the vapour floor stays."""
    plain = load_case(CASE, preset="flow_exit_steady_quick", overrides=["scene.back_pressure=0"]).model
    lifted = load_case(CASE, preset="flow_exit_steady_quick", overrides=["scene.back_pressure=1e6",
                                                                         "scene.mouth_pressure=-5e4"]).model
    a, b = _deck(plain), _deck(lifted)
    assert b["background_pressure"] == pytest.approx(a["background_pressure"] + 1e6, abs=1e-6)
    assert b["min_pressure"] == a["min_pressure"] == pytest.approx(-0.99e5)
    held = {o["name"]: o["pressure"] for o in b["outlets"]}
    assert held == pytest.approx({"mouth": 1e6 - 5e4, "leak": 1e6})
    # the liquid's floor density lies 11 bar below the rest density now, not 1 bar
    assert lifted.scene_fluid().floor_density < plain.scene_fluid().floor_density < plain.fluid.density


def test_the_analysis_takes_the_back_pressure_off_every_pressure():
    series = {"pressure_probe_A": np.array([10.5e5, 11.5e5]), "column_pressure_leak": np.array([10.2e5, 10.2e5]),
              "flow_rate_AG": np.array([1e-3, 1e-3])}
    frames = {"0": {"pressures": np.array([9.0e5, 12.0e5]), "attrs": {"time": 0.0}}, "attrs": {}}
    s, f = less_back_pressure(series, frames, 1e6)
    assert sensor_pressures(s, np.array([0.0, 1.0]))["A"] == pytest.approx(1.5e5, rel=1e-12)
    np.testing.assert_allclose(s["column_pressure_leak"], [0.2e5, 0.2e5], rtol=1e-12)
    np.testing.assert_allclose(f["0"]["pressures"], [-1e5, 2e5], rtol=1e-12)
    assert s["flow_rate_AG"] is series["flow_rate_AG"] and frames["0"]["pressures"][0] == 9.0e5  # no side effects
    assert less_back_pressure(series, frames, 0.0) == (series, frames)


@pytest.mark.parametrize("overrides, words", [
    (["scene.back_pressure=-1e5"], "scene.back_pressure"),
    (["scene.area='feed'"], "scene.area = 'feed': the feed scene is the kind ejector_feed"),
    (["scene.column_inertia=1.5"], "scene.column_inertia"),
    (["scene.columns=false"], "scene.column_inertia = 0.05 needs scene.columns = true"),
])
def test_bad_steady_settings_name_the_key(overrides, words):
    with pytest.raises(OrchestratorError) as err:
        load_case(CASE, preset="flow_exit_steady_quick", overrides=overrides)
    assert words in str(err.value)


def test_the_pressure_beside_the_jets_leaves_out_the_jets_and_other_heights():
    """Fluid in the head clearance at the holes' height 30 degrees or more from every hole's axis counts; a
    particle on a hole's axis (its jet meeting the bore), one above the holes, one in the gap and a wall
    particle do not."""
    from orchestrator.kinds.ejector_drill.flows import pressure_beside_jets
    from orchestrator.kinds.ejector_drill.layout import drill_layout

    case = load_case(CASE, preset="flow_exit_steady_quick").model
    layout = drill_layout(case)
    x_a, _, z_a = layout.sensors["A"]  # on hole 0's axis (angle 0), mid-clearance
    hole_deg = [np.degrees(np.arctan2(p.normal[1], p.normal[0])) for k, p in layout.planes.items()
                if k.startswith("hole")]
    assert sorted(round(a) % 360 for a in hole_deg) == [0, 120, 240]

    def at(deg, z=z_a, r=x_a):
        return (r * np.cos(np.radians(deg)), r * np.sin(np.radians(deg)), z)

    points = [at(60), at(180), at(35, z_a + 1e-3), at(0), at(125), at(60, z_a + 5e-3), at(60, r=9.75e-3), at(300)]
    pressures = [1e5, 3e5, 2e5, 50e5, 40e5, 70e5, 90e5, 80e5]
    kind = [0, 0, 0, 0, 0, 0, 0, 1]
    p, n = pressure_beside_jets(layout, {"positions": np.array(points), "pressures": np.array(pressures),
                                         "kind": np.array(kind)})
    assert n == 3 and p == pytest.approx(2e5, rel=1e-12)
    assert np.isnan(pressure_beside_jets(layout, {"positions": np.array([at(0)]), "pressures": np.array([1.0]),
                                                  "kind": np.array([0])})[0])


def test_the_elements_between_the_network_own_ends_give_back_its_state():
    """The network's elements carrying its own V_AG between its own C1 (where the mouth column ends) and the
    flooded bore mouth return its p_A, V_IB and V_loss (the ejector's suction, V_loss < 0); between two ends at
    gauge 0 they split the flow with p_A above both and both flows out."""
    from orchestrator.kinds.ejector_drill.comparison import elements_at_flow

    net = load_case(CASE, preset="flow_exit_steady_quick").model.network()
    state = solve(net, 60.0 * LITRE_PER_MIN)
    p_a, flows = elements_at_flow(net, state.V_AG, state.p_C1 - net.p_ambient, 0.0, columns=True)
    assert p_a == pytest.approx(state.p_A - net.p_ambient, abs=1.0)  # Pa
    assert flows["V_IB"] == pytest.approx(state.V_IB, rel=1e-6) and flows["V_loss"] == pytest.approx(state.V_loss,
                                                                                                      rel=1e-5)
    assert state.V_loss < 0
    p_a, flows = elements_at_flow(net, state.V_AG, 0.0, 0.0, columns=True)
    assert p_a > 0 and flows["V_IB"] > 0 and flows["V_loss"] > 0
    assert flows["V_IB"] + flows["V_loss"] == pytest.approx(state.V_AG, rel=1e-6)
