"""The ejector_drill kind: the shipped case and its presets load, bad keys are named, the scene's fluid regions
against their closed-form volumes, the balance arithmetic of eq. 2 and the comparison with the 1D network on
synthetic series, and a tiny run on the sph executable."""

import math

import numpy as np
import pytest

from orchestrator.case.loader import load_case
from orchestrator.errors import OrchestratorError
from orchestrator.kinds import build_scene, get_kind, kind_names
from orchestrator.kinds.ejector_drill.flows import balance, filling_times, flow_series, spaced_frames
from orchestrator.kinds.ejector_drill.comparison import comparison_rows, network_at_gap_flow
from orchestrator.kinds.ejector_drill.build import prefill_margin, wall_meshes
from orchestrator.drill.probe import end_particles, probe_scene
from orchestrator.reference.drill_network import LITRE_PER_MIN, solve
from paths import CASES

CASE = CASES / "ejector_drill_canini.toml"
PRESETS = ("flow_exit", "flow_exit_quick", "flow_exit_filled", "flow_exit_filled_quick", "drill_head",
           "drill_head_quick")


def test_registered_with_the_sph_engine():
    assert "ejector_drill" in kind_names() and get_kind("ejector_drill").engines() == ["sph"]


@pytest.mark.parametrize("preset", PRESETS)
def test_presets_load_with_the_papers_resolution(preset):
    case = load_case(CASE, preset=preset).model
    paper = {"flow_exit": (0.3e-3, 0.45e-3), "flow_exit_filled": (0.3e-3, 0.45e-3),
             "drill_head": (0.4e-3, 0.6e-3)}.get(preset)
    if paper:
        assert case.numerics.dx == pytest.approx(paper[0]) and case.numerics.h == pytest.approx(paper[1])
    assert case.network().d_bore == 0.030 and case.network().d_diff == 1.0e-3


@pytest.mark.parametrize("override, words", [
    ("drill.d_hole_typo=1e-3", "d_hole_typo"),
    ("drill.d_hole=0.02", "d_hole"),
    ("scene.area='nozzles'", "scene.area"),
    ("numerics.dx=0.6e-3", "numerics.dx"),
    ("output.picture_times=[3.3e-4]", "picture_times"),
    ("physics.eddy_viscosity=2.0", "physics.eddy_viscosity"),
])
def test_bad_values_name_the_key(override, words):
    with pytest.raises(OrchestratorError) as err:
        load_case(CASE, preset="flow_exit_quick", overrides=[override])
    assert words in str(err.value)


def test_eddy_viscosity_without_the_morris_term_is_refused():
    with pytest.raises(OrchestratorError, match="physics.eddy_viscosity needs physics.morris_viscosity"):
        load_case(CASE, preset="flow_exit_quick", overrides=["physics.morris_viscosity=false", "fluid.viscosity=null",
                                                             "physics.eddy_viscosity=0.1"])


@pytest.mark.parametrize("preset", ["flow_exit_quick", "drill_head_quick"])
def test_lattice_fills_the_regions_to_their_closed_form_volume(preset):
    case = load_case(CASE, preset=preset).model
    scene = build_scene(case)
    dx, layout = case.numerics.dx, scene.layout
    filled = probe_scene(scene, limit=10 ** 9)
    # the lattice's count times dx^3 against the sum of the rings' and holes' closed forms (0.2-2.4 % here: a
    # 0.875 mm clearance is two to three spacings wide, sampled by a lattice not aligned with it)
    assert filled.n_fluid * dx ** 3 == pytest.approx(layout.fluid_volume(), rel=0.03)
    assert probe_scene(scene).n_fluid == min(end_particles(scene), filled.n_fluid)
    assert filled.n_particles - filled.n_fluid == scene.walls.n  # the probe keeps the walls
    ring = layout.channel
    assert ring.volume() == pytest.approx(math.pi * (ring.r_out ** 2 - ring.r_in ** 2) * (ring.z_hi - ring.z_lo))
    # the prefill: the channel's lattice sites from the inlet plane down (no margin off boundary-particle walls),
    # moving at v_in
    assert prefill_margin(case, ring) == 0.0
    expected = math.pi * (ring.r_out ** 2 - ring.r_in ** 2) * case.scene.prefill / dx ** 3
    assert scene.n_fluid == pytest.approx(expected, rel=0.35)
    fluid = scene.kind == 0
    assert np.allclose(np.linalg.norm(scene.velocities[fluid], axis=1), case.scene.inlet_velocity)
    assert not scene.meshes and "wall_penalty" not in scene.physics
    # the penalty walls stay an option (for a head without pads and edges, which are boundary particles only): the
    # meshes, cut above the buffers, and the prefill s off the walls
    plain = ["physics.walls='penalty'", "head.pad_angles=[]", "head.edge_angles=[]"]
    penalty = build_scene(load_case(CASE, preset=preset, overrides=plain).model)
    assert penalty.walls is None and "wall_penalty" in penalty.physics
    width = ring.r_out - ring.r_in  # s = dx / 2, or what leaves one spacing across a narrower channel
    assert prefill_margin(penalty.drill, ring) == pytest.approx(min(0.5 * dx, max(0.0, 0.5 * (width - dx))), abs=1e-15)
    assert penalty.n_fluid <= scene.n_fluid
    for mesh in penalty.meshes.values():
        assert mesh.vertices[:, 2].max() <= layout.z_hi + 1e-8  # manifold3d rounds to float32


def test_a_filled_start_holds_every_region_at_rest_and_ramps_the_inlet():
    """start = 'filled': the fluid regions and the outlets' buffers on the lattice at rest, every wetted site occupied
    (so no boundary particle below the inlet books an empty site out: they start at rho0), and the inlet's deck
    entry ramps."""
    import json

    from orchestrator.drill.scene import filled_sites
    from orchestrator.kinds.sph_flow.sph import TEMPLATE, deck_context
    from orchestrator.templating import render

    case = load_case(CASE, preset="flow_exit_filled_quick").model
    scene = build_scene(case)
    dx, layout, flow = case.numerics.dx, scene.layout, scene
    fluid = flow.kind == 0
    assert np.count_nonzero(fluid) == len(filled_sites(layout, dx))
    assert not np.any(flow.velocities[fluid])
    # the regions' closed-form volume plus the outlets' buffers (the wetted rings beyond the regions)
    regions = {r.name: r for r in layout.regions}
    buffers = sum(r.volume() - regions[r.name].volume() for r in layout.wetted
                  if r.name in regions and r.name != layout.channel.name)
    assert np.count_nonzero(fluid) * dx ** 3 == pytest.approx(layout.fluid_volume() + buffers, rel=0.03)
    # walls start at rho0 except beside the channel's sites behind the inlet's 3-layer buffer (always empty)
    below_inlet = flow.positions[:, 2] < layout.inlet.center[2]
    assert np.all(flow.densities[~fluid & below_inlet] == case.fluid.density)
    inlet = json.loads(render(TEMPLATE, deck_context(flow, threads=1)))["inlets"][0]
    assert inlet["ramp_time"] == case.scene.ramp_time == 2.0e-4


@pytest.mark.parametrize("backflow", [False, True])
def test_backflow_makes_both_outlets_pressure_openings(backflow):
    """scene.backflow reaches the deck's mouth and leak outlets (engine: a buffer particle crossing inward becomes
    fluid at the held pressure); without it the deck has no backflow key (fluid only leaves)."""
    import json

    from orchestrator.kinds.sph_flow.sph import TEMPLATE, deck_context
    from orchestrator.templating import render

    case = load_case(CASE, preset="flow_exit_filled_quick", overrides=[f"scene.backflow={str(backflow).lower()}"])
    outlets = json.loads(render(TEMPLATE, deck_context(build_scene(case.model), threads=1)))["outlets"]
    assert sorted(o["name"] for o in outlets) == ["leak", "mouth"]
    assert all(o.get("backflow", False) is backflow and o["pressure"] == 0.0 for o in outlets)


def test_columns_give_the_outlets_the_passages_beyond_them():
    """scene.columns: the leak outlet's column is the tube/bore clearance from the outlet to the bore mouth, the
    mouth's the chip mouth to the head's rear and the inner tube to the feed (inertia-equivalent on the mouth's
    section), with their friction (Colebrook at the scene's inflow) and exit losses (columns.py)."""
    import json

    from fluids.friction import friction_factor

    from orchestrator.kinds.sph_flow.sph import TEMPLATE, deck_context
    from orchestrator.templating import render

    case = load_case(CASE, preset="flow_exit_filled_quick", overrides=["scene.columns=true"])
    outlets = {o["name"]: o for o in json.loads(render(TEMPLATE, deck_context(build_scene(case.model),
                                                                                threads=1)))["outlets"]}
    net, head = case.model.network(), case.model.geometry().head_length
    q = 60.0 * net.annular_gap().area  # m^3/s: the inlet's 60 m/s in the gap
    leak, mouth = outlets["leak"], outlets["mouth"]
    # leak: 0.3 m of bore less the outlet's 34 mm; D_h = 30 - 24 mm; exit K = 1
    area = math.pi / 4 * (0.030**2 - 0.024**2)
    f = friction_factor(Re=q / area * 0.006 * net.rho / net.mu, eD=net.roughness / 0.006)
    assert leak["column_length"] == pytest.approx(0.3 - leak["center"][2], rel=1e-12) and leak["center"][2] > 0.02
    assert leak["column_area"] == pytest.approx(area, rel=1e-12)
    assert leak["column_loss"] == pytest.approx(f * leak["column_length"] / 0.006 + 1.0, rel=1e-9)
    # mouth: Ø12 mm from z = 5 mm to the head's rear, then 0.4 m of Ø16 mm tube scaled by (12/16)^2
    ratio = (12.0 / 16.0) ** 2
    assert mouth["column_length"] == pytest.approx(head - 0.005 + 0.4 * ratio, rel=1e-12)
    f_m = friction_factor(Re=q / (math.pi / 4 * 0.012**2) * 0.012 * net.rho / net.mu, eD=net.roughness / 0.012)
    f_t = friction_factor(Re=q / (math.pi / 4 * 0.016**2) * 0.016 * net.rho / net.mu, eD=net.roughness / 0.016)
    k = f_m * (head - 0.005) / 0.012 + (1 - ratio) ** 2 + f_t * 0.4 / 0.016 * ratio**2
    assert mouth["column_loss"] == pytest.approx(k, rel=1e-9)
    plain = load_case(CASE, preset="flow_exit_filled_quick").model
    deck = json.loads(render(TEMPLATE, deck_context(build_scene(plain), threads=1)))
    assert not any("column_length" in o for o in deck["outlets"])  # off by default: the outlets as before
    # column_inertia keeps a fraction of each length (inertia and chamber), and the whole passage's loss
    light = load_case(CASE, preset="flow_exit_filled_quick", overrides=["scene.columns=true",
                                                                         "scene.column_inertia=0.05"])
    scaled = {o["name"]: o for o in json.loads(render(TEMPLATE, deck_context(build_scene(light.model),
                                                                             threads=1)))["outlets"]}
    for name, full in (("leak", leak), ("mouth", mouth)):
        assert scaled[name]["column_length"] == pytest.approx(0.05 * full["column_length"], rel=1e-12)
        assert scaled[name]["column_loss"] == pytest.approx(full["column_loss"], rel=1e-12)
        assert scaled[name]["column_area"] == pytest.approx(full["column_area"], rel=1e-12)
    with pytest.raises(OrchestratorError, match="column_inertia"):
        load_case(CASE, preset="flow_exit_filled_quick", overrides=["scene.columns=true", "scene.column_inertia=0"])


def test_stored_volume_counts_cavitating_fluid_at_the_floors_density():
    """A particle below the cavitation floor's density holds its mass as liquid at that density (the rest of
    m / rho is vapour): the control volume's liquid is m / max(rho, rho_floor); outside it nothing counts."""
    from orchestrator.kinds.ejector_drill.comparison import stored_volume

    case = load_case(CASE, preset="flow_exit_filled_quick", overrides=["fluid.min_pressure=-0.99e5"]).model
    layout = build_scene(case).layout
    rho0, floor = case.fluid.density, case.fluid.floor_density
    # eq. 6 inverted at -0.99e5 Pa with c0 = 1500 m/s: rho0 (1 - 7 x 0.99e5 / (1000 x 1500^2))^(1/7)
    assert floor == pytest.approx(rho0 * (1 - 7 * 0.99e5 / (rho0 * 1500.0 ** 2)) ** (1 / 7), rel=1e-12)
    inside = [0.0, 14.6e-3, -0.5e-3]  # ahead of the head's face at the bore's rim, below the AG plane
    outside = [0.0, 0.0, layout.planes["IB"].center[2] + 1e-3]  # in the chip mouth past IB
    frame = {"kind": np.zeros(3), "positions": np.array([inside, inside, outside]),
             "densities": np.array([0.5 * rho0, 1.01 * rho0, 0.5 * rho0]), "attrs": {"time": 1e-4}}
    mass = 1e-6
    _, cavitating = stored_volume(layout, {"0": frame}, mass, floor)
    _, as_m_over_rho = stored_volume(layout, {"0": frame}, mass)
    assert cavitating[0] == pytest.approx(mass / floor + mass / (1.01 * rho0), rel=1e-12)
    assert as_m_over_rho[0] == pytest.approx(mass / (0.5 * rho0) + mass / (1.01 * rho0), rel=1e-12)


@pytest.mark.parametrize("overrides, words", [
    (["scene.ramp_time=0.0"], "rho0 c0 v_in = 900 bar"),
    (["scene.prefill=1e-3"], "scene.prefill is for start = 'empty'"),
    (["scene.ramp_time=1e-3"], "scene.ramp_time = 0.001 s is longer"),
    (["scene.area='feed'"], "the feed scene is the kind ejector_feed: set case.kind"),
])
def test_a_filled_start_needs_a_ramp(overrides, words):
    with pytest.raises(OrchestratorError) as err:
        load_case(CASE, preset="flow_exit_filled_quick", overrides=overrides)
    assert words in str(err.value)


def test_the_head_has_its_holes_cut():
    case = load_case(CASE, preset="flow_exit_quick").model
    scene = build_scene(case)
    net, g = case.network(), case.geometry()
    head = g.meshes()["head"]
    # the holes run through the head from the groove's outer wall (the collector's, groove_depth out) to its body
    holes = net.n_holes * 0.25 * math.pi * net.d_hole ** 2 * (net.d_head_body / 2 - g.groove_outer_radius)
    cut = wall_meshes(case, scene.layout)["head"]
    assert cut.is_watertight
    assert head.volume - cut.volume == pytest.approx(holes, rel=0.03)  # the hole cylinders' N-gon deficit


def _synthetic(time):
    ramp = np.clip(time / 1e-4, 0.0, 1.0)
    v_ag = 1.0e-3 * ramp
    return {"flow_rate_AG": v_ag, "flow_rate_rear": -v_ag + 0.1e-3 * ramp, "flow_rate_IB": 0.9e-3 * ramp,
            "flow_rate_hole0": v_ag / 3, "flow_rate_hole1": v_ag / 3, "flow_rate_hole2": v_ag / 3,
            "flow_rate_front": 0.9e-3 * ramp}


def test_balance_of_eq2_on_synthetic_series():
    time = np.linspace(0.0, 1e-3, 101)
    flows = flow_series(_synthetic(time), time)
    assert np.allclose(flows["V_loss"], 0.1e-3 * np.clip(time / 1e-4, 0, 1))  # rear + AG
    bal = balance(time, flows, stored=np.zeros_like(time))
    assert bal["V_AG"] == pytest.approx(1e-3) and bal["V_IB"] == pytest.approx(0.9e-3)
    assert abs(bal["residual"]) < 1e-15 and bal["filling_share"] == 0.0
    leaky = dict(flows, V_IB=flows["V_IB"] * 0.95)
    assert balance(time, leaky)["residual_share"] == pytest.approx(0.045)
    times = filling_times(time, flows)
    assert times["t_gap"] == pytest.approx(1e-6, abs=1e-5) and times["t_holes"] == pytest.approx(time[1])


def test_the_window_balance_counts_volumes_from_frame_to_frame():
    """Eq. 2 as volumes: records every 1e-5 s, each the mean flow since the one before (V_AG 1e-3 m^3/s, V_IB
    0.6e-3, V_loss 0.1e-3 from t = 0.3 ms on), frames every 1e-4 s holding a volume that gains 0.4e-3 m^3/s before
    and 0.3e-3 after 0.3 ms: over the last 20 % (frames 0.8..1.0 ms) the planes count 2e-7, 1.2e-7, 2e-8 m^3 and the
    storage 6e-8: nothing missing; a volume series that misses 1 % of V_AG is named."""
    from orchestrator.kinds.ejector_drill.flows import window_balance

    time = np.linspace(0.0, 1e-3, 101)
    flows = {"V_AG": np.full_like(time, 1e-3), "V_IB": np.full_like(time, 0.6e-3),
             "V_loss": np.where(time > 0.3e-3 + 1e-12, 0.1e-3, 0.0)}
    t_frames = np.linspace(0.0, 1e-3, 11)
    volumes = np.where(t_frames <= 0.3e-3, 0.4e-3 * t_frames, 0.12e-6 + 0.3e-3 * (t_frames - 0.3e-3))
    win = window_balance(time, flows, t_frames, volumes)
    assert (win["t_a"], win["t_b"]) == pytest.approx((0.8e-3, 1e-3))
    assert (win["V_AG"], win["V_IB"], win["V_loss"], win["stored"]) == pytest.approx((2e-7, 1.2e-7, 2e-8, 6e-8))
    assert abs(win["closure_share"]) < 1e-12 and win["stored_share"] == pytest.approx(0.3)
    short = window_balance(time, flows, t_frames, volumes - 0.01 * 1e-3 * t_frames)
    assert short["closure_share"] == pytest.approx(0.01)
    assert window_balance(time, flows, t_frames[:1], volumes[:1]) == {}
    # a stop frame 4e-6 s after the last regular one (no series record between them): no window
    frames = np.append(t_frames[:8], [0.9e-3, 0.904e-3])
    stop = window_balance(time[:91], {k: v[:91] for k, v in flows.items()}, frames, np.append(volumes[:8], [0.2e-6, 0.3e-6]))
    assert stop == {}


@pytest.mark.parametrize("residual, storage, words", [
    (0.004, math.nan, "closes within 1 %"),
    (0.5, 0.495, "still filling the scene"),
    (-0.456, -0.462, "draining from the scene"),
    (0.05, 0.001, "5 % of V_AG, of which the control volume's storage accounts for 0.1 %"),
])
def test_the_balance_verdict_says_where_the_volume_is(residual, storage, words):
    from orchestrator.kinds.ejector_drill.analysis import balance_verdict

    assert words in balance_verdict(residual, storage)


def test_network_at_the_sph_gap_flow_and_the_table():
    case = load_case(CASE, preset="flow_exit_quick").model
    net = case.network()
    v_ag = 60.0 * 30.63e-6  # the paper's 60 m/s over the gap
    at_gap = network_at_gap_flow(net, v_ag)
    assert at_gap.V_AG == pytest.approx(v_ag, rel=1e-6) and at_gap.V_total > v_ag
    standard = solve(net, 60.0 * LITRE_PER_MIN)
    sph = {"V_AG": v_ag, "V_IB": 0.8 * v_ag, "V_loss": 0.2 * v_ag, "p_A": 12e5, "p_B": 30e5}
    rows = {r[0]: r for r in comparison_rows(sph, net, at_gap, standard, 0.013, 60.0)}
    assert rows["V_AG"][2] == pytest.approx(v_ag / LITRE_PER_MIN) and rows["V_AG"][3] == pytest.approx(rows["V_AG"][2])
    assert math.isnan(rows["V_total"][2]) and rows["V_total"][4] == pytest.approx(60.0)
    assert rows["p_A"][2] == pytest.approx(12.0) and math.isnan(rows["p_C1"][2])
    assert rows["p_B"][4] == pytest.approx(standard.gauge_bar("p_B"))
    # the gap pressure 13 mm up from the head exceeds p_A by the holes' orifice drop at least
    assert rows["p_B at the SPH's B"][4] > standard.gauge_bar("p_A") + 0.5 * 1000 * (
        standard.V_AG / (net.cd_hole * net.hole_area)) ** 2 / 1e5 - 1e-9



@pytest.mark.parametrize("feed", [50.0, 80.0, 167.0])
def test_element_flows_return_the_networks_own_split(feed):
    """At a solved network state, its leak path driven from p_A to ambient carries its V_loss (negative: the ejector
    draws), and its way into the chip mouth driven from p_A to the pressure just inside the mouth carries its V_IB;
    and a drop of 1/2 rho v^2 (1.5 + 0.57 (80/113.1)^2) at 11.6 m/s on the 80 mm^2 front gives 55.7 l/min."""
    from orchestrator.kinds.ejector_drill.comparison import element_flows
    from orchestrator.reference.drill_network import front_pressure_drop

    net = load_case(CASE, preset="drill_head").model.network()
    state = solve(net, feed * LITRE_PER_MIN)
    p_a = state.p_A - net.p_ambient
    p_mouth = p_a - front_pressure_drop(net, state.V_IB)
    flows = element_flows(net, p_a, p_mouth, 0.0)
    assert flows["V_loss"] == pytest.approx(state.V_loss, rel=1e-7, abs=1e-12)
    assert flows["V_IB"] == pytest.approx(state.V_IB, rel=1e-7)
    assert state.V_loss < 0  # this case file: the ejector draws at every feed flow
    k_sum = net.k_cutting_zone + net.k_chip_mouth_entry * (net.front_area / (0.25 * math.pi * net.d_chip_mouth ** 2)) ** 2
    assert element_flows(net, 1.2e5, 0.0, 0.0)["V_IB"] == pytest.approx(
        net.front_area * math.sqrt(2 * 1.2e5 / (net.rho * k_sum)), rel=1e-9)
    # with columns the mouth's column ends at C1: from p_A to the network's p_C1 the whole way carries its V_IB
    with_columns = element_flows(net, p_a, state.p_C1 - net.p_ambient, 0.0, columns=True)
    assert with_columns["V_IB"] == pytest.approx(state.V_IB, rel=1e-7)


@pytest.mark.sph
def test_tiny_flow_exit_run(tmp_path):
    from orchestrator.run import run_case

    loaded = load_case(CASE, preset="flow_exit_quick", overrides=["simulation.duration=5e-5", "numerics.threads=1",
                                                                  "output.picture_times=[]",
                                                                  "output.frame_interval=2.5e-5"])
    summary = run_case(loaded, engine="sph", out_dir=tmp_path / "run", progress=False)
    assert summary.status == "ok"
    # the inlet delivers v_in times its annulus, the whole gap between the walls' particles (the engine scales the
    # profile's columns to it), to within one lattice layer across the inlet: at dx = 0.5 mm the gap's columns all
    # sit near one radius and cross the patch together, so a mean over a few records is quantised by whole layers
    import h5py

    area, dx = math.pi * (10e-3 ** 2 - 9.5e-3 ** 2), loaded.model.numerics.dx
    with h5py.File(tmp_path / "run" / "run.h5", "r") as h5:
        time, rate = h5["series/time"][()], h5["series/inflow_gap_inlet"][()]
    delivered = float(np.sum(rate[1:] * np.diff(time)))
    assert abs(delivered - 60.0 * area * time[-1]) <= area * dx
    assert summary.measured["V_in"] == pytest.approx(60.0 * area, rel=0.1)


@pytest.mark.sph
@pytest.mark.slow  # 2 min on 2 cores; the tiny run above keeps the deck and the walls in the default suite
def test_the_quick_flow_exit_run_keeps_the_fluid_out_of_the_walls(tmp_path):
    """The quick flow-exit preset runs its 0.4 ms (a free jet leaves the holes at ~200 m/s at a tension of ~-400
    bar): no fluid particle lies deeper than one spacing inside a solid in any frame (measured 0.77 dx; the staircase
    between the true surface and the first boundary layer is up to 0.5 dx at this lattice). Before the walls' pressure floor (eq.
    WP3 took the jet's tension and pulled fluid in) it stopped as unstable at 0.387 ms, 860 fluid particles inside
    the solids."""
    import h5py

    from orchestrator.kinds.ejector_drill.layout import drill_layout
    from orchestrator.drill.walls import wall_points
    from orchestrator.kinds.ejector_drill.walls import solid_masks
    from orchestrator.run import run_case

    loaded = load_case(CASE, preset="flow_exit_quick", overrides=["numerics.threads=2", "output.picture_times=[]"])
    summary = run_case(loaded, engine="sph", out_dir=tmp_path / "run", progress=False)
    assert summary.status == "ok"
    case = loaded.model
    layout, dx = drill_layout(case), case.numerics.dx
    deepest = []
    with h5py.File(tmp_path / "run" / "out.h5", "r") as h5:
        for frame in h5["frames"].values():
            x = frame["positions"][()][frame["kind"][()] == 0]
            x = x[~layout.wetted_contains(x)]
            inside = np.zeros(len(x), dtype=bool)
            for mask in solid_masks(x, case, layout).values():
                inside |= mask
            x = x[inside]
            deepest.append(float(np.max(np.linalg.norm(wall_points(x, layout) - x, axis=1), initial=0.0)) / dx)
    assert len(deepest) == 5 and max(deepest) < 1.0, deepest


@pytest.mark.parametrize("preset, probed", [("drill_head", True), ("drill_head_quick", False)])
def test_the_paper_resolution_starts_with_a_timing_probe(preset, probed):
    """A drill run's cost is particles x steps: the paper's drill-head scene (about 1.4e9 particle-steps) is probed
    before it starts, its quick preset (about 4e8) is not; neither plans more steps than the step-count rule's."""
    from orchestrator.kinds import bind
    from orchestrator.kinds.base import PROBE_ABOVE_STEPS
    from orchestrator.drill.sph import PROBE_ABOVE_PARTICLE_STEPS

    case = load_case(CASE, preset=preset).model
    scene = build_scene(case)
    particle_steps = case.planned_steps * probe_scene(scene).n_fluid
    assert case.planned_steps < PROBE_ABOVE_STEPS
    assert (particle_steps > PROBE_ABOVE_PARTICLE_STEPS) is probed
    assert bind("ejector_drill", "sph", scene).wants_probe(scene) is probed


def test_user_meshes_need_the_penalty_walls(tmp_path):
    """The boundary particles are cut from the parametric solids in closed form: a user's mesh for a part is refused
    with them, by name, and accepted with walls = 'penalty'."""
    import trimesh

    stl = tmp_path / "head.stl"
    trimesh.creation.box(extents=(10.0, 10.0, 10.0)).export(stl)
    with pytest.raises(OrchestratorError) as err:
        load_case(CASE, preset="flow_exit_quick", overrides=[f"parts.head.file='{stl}'"])
    assert "parts.head" in str(err.value) and "penalty" in str(err.value)
    case = load_case(CASE, preset="flow_exit_quick", overrides=[f"parts.head.file='{stl}'", "parts.head.scale=1e-3",
                                                                "physics.walls='penalty'"]).model
    assert case.parts["head"].scale == 1e-3


def test_zones_find_the_still_fluid_and_the_pressure_peak():
    """A synthetic frame: the flow-exit quick scene's lattice sites moving at v_in, those in the groove below the
    holes at rest, 1 % of the particles at 500 bar in the head clearance at the face: zones() finds both where they
    were put."""
    from orchestrator.kinds.ejector_drill.flows import zones
    from orchestrator.drill.scene import filled_sites

    case = load_case(CASE, preset="flow_exit_quick").model
    layout = build_scene(case).layout
    x = filled_sites(layout, case.numerics.dx, buffers=False)
    n = len(x)
    v = np.tile([0.0, 0.0, -60.0], (n, 1))
    gap = layout.channel
    hole = next(r for r in layout.regions if r.name == "hole1")
    floor = gap.contains(x) & (x[:, 2] < hole.z - 0.5 * hole.d)
    v[floor] = 0.0
    p = np.full(n, 1e5)
    clearance = next(r for r in layout.regions if r.name == "head_clearance")
    near_face = np.nonzero(clearance.contains(x))[0]
    hot = near_face[np.argsort(x[near_face, 2], kind="stable")][:round(0.01 * n)]  # the clearance at the face
    p[hot] = 5e7
    frame = {"kind": np.zeros(n), "positions": x, "velocities": v, "pressures": p}
    found = zones(layout, frame, 60.0)
    name, count, share, r, z = found["still"][0]
    assert (name, count) == ("annular_gap", int(floor.sum())) and len(found["still"]) == 1
    assert gap.r_in <= r <= gap.r_out and gap.z_lo <= z < hole.z - 0.5 * hole.d
    assert share == pytest.approx(floor.sum() / gap.contains(x).sum())
    count, mean, top, where, r, z = found["peak"]
    assert (count, where, top, mean) == (len(hot), "head_clearance", 5e7, 5e7)
    assert r == pytest.approx(np.hypot(x[hot, 0], x[hot, 1]).mean()) and z == pytest.approx(x[hot, 2].mean())


def test_spaced_frames_leave_out_a_stop_frame_close_to_the_grid():
    # frames every 1 ms, the stop's extra frame 0.0095 ms after 7 ms (a run stopped and resumed there), and a
    # final frame 0.6 ms after the last regular one (kept: more than half an interval)
    t = np.array([0.0, 1.0, 2.0, 7.0, 7.0095, 8.0, 9.0, 9.6]) * 1e-3
    np.testing.assert_array_equal(spaced_frames(t, 1e-3), [True, True, True, True, False, True, True, True])


def test_eddy_viscosity_reaches_the_scene():
    """[physics] eddy_viscosity = cs switches Smagorinsky's term on in the scene's physics (engine eqs. SM1-SM2)."""
    from orchestrator.drill.scene import drill_physics

    case = load_case(CASE, preset="flow_exit_quick", overrides=["physics.eddy_viscosity=0.12"]).model
    physics = drill_physics(case)
    assert physics.eddy_viscosity == 0.12 and "morris_viscosity" in physics.terms
    assert drill_physics(load_case(CASE, preset="flow_exit_quick").model).eddy_viscosity is None
