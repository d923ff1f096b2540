"""The ejector drill's feed scene (kind ejector_feed): the tilted nozzles' closed-form volume and nearest points,
the layout (the two inlets on one lattice, C1 before and C2 behind the nozzles), the boundary particles (inside
their solids by the cut meshes' winding number, a full kernel support for every wetted site, wall points on the
surface and nearest), the network's numbers the boundaries carry, the start state, and the flows' arithmetic."""

import math
from functools import lru_cache

import numpy as np
import pytest

from orchestrator.case.loader import load_case
from orchestrator.errors import OrchestratorError
from orchestrator.kinds import build_scene
from orchestrator.drill.walls import scene_lattice
from orchestrator.kinds.ejector_feed.flows import feed_flows, slab_flow, steady_means
from orchestrator.kinds.ejector_feed.build import start_pressure, start_velocities, tait_density
from orchestrator.kinds.ejector_feed.layout import Nozzle
from orchestrator.kinds.ejector_feed.network import feed_boundary, gap_pressure_below_feed
from orchestrator.kinds.ejector_feed.walls import feed_solid_masks, feed_wall_meshes
from orchestrator.reference.drill_network import LITRE_PER_MIN, solve
from test_ejector_drill_walls import _closest, _winding
from paths import CASES

CASE = CASES / "ejector_feed_canini.toml"
#: The cut meshes' polygons: the tubes' 96-gon lies 10 mm x (1 - cos(pi / 96)) = 5 um inside the circle, the nozzles'
#: 32-gon 0.5 mm x (1 - cos(pi / 32)) = 2.4 um inside theirs.
MESH_TOLERANCE = 10e-6


@lru_cache(maxsize=1)
def _scene():
    case = load_case(CASE, preset="feed_quick", overrides=["numerics.dx=0.4e-3", "scene.c2_distance=4e-3"]).model
    return case, build_scene(case)


def _nozzle():
    return Nozzle("n", 0.3, 0.1, 1.0e-3, math.radians(30.0), 8.0e-3, 9.5e-3)


def test_nozzle_volume_and_membership_against_monte_carlo():
    """The oblique cylinder between the wall's faces: pi d^2 / 4 x 1.5 mm / cos 30 deg = 1.3603 mm^3; sampled in a
    box around it, the curved faces (r = 8 and 9.5 mm) change it by under 0.5 %."""
    nozzle = _nozzle()
    assert nozzle.volume() == pytest.approx(0.25 * math.pi * 1e-6 * 1.5e-3 / math.cos(math.radians(30.0)), rel=1e-12)
    assert nozzle.volume() == pytest.approx(1.3603e-9, rel=1e-4)
    rng = np.random.default_rng(4)
    lo, hi = nozzle.span(0.0)
    ends = np.array([nozzle.base + lo * nozzle.axis, nozzle.base + hi * nozzle.axis])
    box_lo, box_hi = ends.min(axis=0) - 0.6e-3, ends.max(axis=0) + 0.6e-3
    points = box_lo + rng.random((2_000_000, 3)) * (box_hi - box_lo)
    inside = nozzle.contains(points)
    volume = inside.mean() * np.prod(box_hi - box_lo)
    assert volume == pytest.approx(nozzle.volume(), rel=0.005)
    # every member lies in the wall and within d/2 of the axis
    r = np.hypot(points[inside, 0], points[inside, 1])
    assert r.min() >= 8.0e-3 and r.max() < 9.5e-3


def test_nozzle_nearest_points_lie_on_its_surface_for_the_wall():
    """For points of the wall outside the nozzle the nearest point is on the cylinder (d/2 off the axis) or, beyond
    its span, on a cap outside the wall; points off the wall get none (+inf)."""
    nozzle = _nozzle()
    rng = np.random.default_rng(5)
    points = nozzle.base + nozzle.length / 2 * nozzle.axis + rng.uniform(-1.5e-3, 1.5e-3, (20_000, 3))
    r = np.hypot(points[:, 0], points[:, 1])
    wall = (r >= 8.0e-3) & (r <= 9.5e-3) & ~nozzle.contains(points)
    near = nozzle.nearest(points)
    assert np.isinf(near[~((r >= 8.0e-3) & (r <= 9.5e-3))]).all()
    rel = near[wall] - nozzle.base
    s = rel @ nozzle.axis
    off = np.linalg.norm(rel - np.outer(s, nozzle.axis), axis=1)
    lo, hi = nozzle.span(0.25e-3)
    on_side = (s > lo + 1e-12) & (s < hi - 1e-12)
    assert np.allclose(off[on_side], 0.5e-3, rtol=0, atol=1e-12)
    assert on_side.sum() > 1000
    # no point of the nozzle is nearer than the returned one (the nozzle's own sample)
    members = points[nozzle.contains(points)]
    sample = np.nonzero(wall)[0][:200]
    d_returned = np.linalg.norm(near[sample] - points[sample], axis=1)
    d_members = np.min(np.linalg.norm(points[sample][:, None, :] - members[None, :, :], axis=2), axis=1)
    assert (d_returned <= d_members + 1e-12).all()


def test_layout_puts_the_inlets_on_one_lattice_and_the_sensors_in_order():
    case, scene = _scene()
    layout, dx = scene.layout, case.numerics.dx
    z_n = case.geometry().head_length + case.network().tube_length
    assert layout.z_nozzles == pytest.approx(0.425)
    k = (layout.inlet.center[2] - layout.tube_inlet.center[2]) / dx
    assert k == pytest.approx(round(k), abs=1e-9)
    for name in ("AG_all", "IB", "mixed"):  # the discs lie midway between two lattice layers
        k = (layout.inlet.center[2] - layout.planes[name].center[2]) / dx
        assert k == pytest.approx(round(k), abs=1e-9)
    assert layout.planes["IB"].center[2] == pytest.approx(z_n - case.scene.c1_distance, abs=0.5 * dx)
    assert layout.sensors["C1"][2] == pytest.approx(z_n - case.scene.c1_distance)
    assert layout.sensors["C2"][2] == pytest.approx(z_n + case.scene.c2_distance)
    assert layout.tube_inlet.center[2] < layout.sensors["C1"][2] - 2 * case.numerics.h
    # the gap outlet's disc (it covers the bore) lies below the tube inlet's buffer
    assert layout.outlets["gap"].center[2] < layout.tube_inlet.center[2] - 3 * dx - 2 * case.numerics.h
    assert all(layout.in_scene(p) for p in layout.sensors.values())
    # the lattice fills the regions to their closed-form volume (gap 30.63 mm^2 x its length, six nozzles, the bore)
    filled = scene.n_fluid * dx ** 3
    assert filled == pytest.approx(layout.fluid_volume(), rel=0.03)
    gap = math.pi * (10e-3 ** 2 - 9.5e-3 ** 2) * (layout.gap.z_hi - layout.gap.z_lo)
    assert layout.gap.volume() == pytest.approx(gap, rel=1e-12)
    per_nozzle = [np.count_nonzero(z.contains(scene.positions[scene.kind == 0])) for z in layout.nozzles]
    assert min(per_nozzle) > 0.5 * layout.nozzles[0].volume() / dx ** 3


def test_boundary_particles_lie_in_the_solids_within_the_support():
    case, scene = _scene()
    walls, layout = scene.walls, scene.layout
    h = case.numerics.h
    assert walls.n > 10_000 and not layout.wetted_contains(walls.positions).any()
    d = walls.distances()
    assert d.max() <= 2 * h * (1 + 1e-12)
    meshes = feed_wall_meshes(layout)
    rng = np.random.default_rng(6)
    far = d > MESH_TOLERANCE
    near_nozzle = np.zeros(walls.n, dtype=bool)
    for z in layout.nozzles:
        near_nozzle |= np.linalg.norm(walls.positions - (z.base + 0.5 * z.length * z.axis), axis=1) < 1.5e-3
    for k, name in enumerate(walls.parts):
        mine = np.nonzero((walls.part == k) & far)[0]
        rows = rng.choice(mine, size=min(80, len(mine)), replace=False)
        if name == "inner_tube":  # and the walls around the nozzles
            rows = np.concatenate([rows, rng.choice(np.nonzero((walls.part == k) & far & near_nozzle)[0], 80)])
        assert np.allclose(_winding(meshes[name], walls.positions[rows]), 1.0, atol=1e-6), name


def test_every_wetted_site_has_a_full_support_of_wall_particles():
    from scipy.spatial import cKDTree

    case, scene = _scene()
    walls, layout, dx, h = scene.walls, scene.layout, case.numerics.dx, case.numerics.h
    # away from the walls' cut ends (the open boundaries' buffers end there)
    sites = scene_lattice(layout, dx, layout.r_max, layout.gap.z_lo, layout.tube.z_hi)
    wet = layout.wetted_contains(sites)
    fluid, other = sites[wet], sites[~wet]
    solid = np.zeros(len(other), dtype=bool)
    for mask in feed_solid_masks(other, layout, 1e-6 * dx).values():
        solid |= mask
    needed = cKDTree(fluid).query(other[solid], distance_upper_bound=2 * h)[0] < 2 * h
    have = cKDTree(walls.positions).query(other[solid][needed], distance_upper_bound=1e-3 * dx)[0] < 1e-3 * dx
    assert needed.sum() > 10_000 and have.all()


def test_wall_points_are_the_nearest_points_of_the_meshes_surface():
    """Around the nozzles: the wall point of each sampled particle lies on the cut meshes' surface and is its
    nearest point that faces the fluid (brute force over the triangles)."""
    import trimesh

    case, scene = _scene()
    walls, layout = scene.walls, scene.layout
    meshes = feed_wall_meshes(layout)
    solid = trimesh.boolean.union(list(meshes.values()), engine="manifold")
    z = layout.nozzles[1]
    close = np.nonzero(np.linalg.norm(walls.positions - (z.base + 0.5 * z.length * z.axis), axis=1) < 1.5e-3)[0]
    assert len(close) > 60
    rows = np.random.default_rng(7).choice(close, size=min(150, len(close)), replace=False)
    x, w = walls.positions[rows], walls.wall_points[rows]
    near, d_mesh = _closest(solid, x)
    assert _closest(solid, w)[1].max() < MESH_TOLERANCE
    beyond = near + (near - x) / d_mesh[:, None] * 0.05 * case.numerics.dx
    wetted = layout.wetted_contains(beyond)
    assert wetted.sum() > 0.5 * len(rows)
    assert np.abs(np.linalg.norm(w - x, axis=1) - d_mesh)[wetted].max() < MESH_TOLERANCE
    assert (np.linalg.norm(w - x, axis=1) >= d_mesh - MESH_TOLERANCE).all()


def test_the_boundaries_carry_the_networks_state():
    """At 60 l/min (the case file's drill: the head's flats as a 28.25 mm body): V_total over the gap (30.63 mm^2) is
    32.65 m/s, V_IB = 45.20 l/min over the bore (201 mm^2) 3.75 m/s; the gap pressure at the network's sensor B
    (0.05 m below the feed) is its p_B, 25.70 bar; the tube outlet holds p_C2 = 0.17 bar."""
    case, scene = _scene()
    net = case.network()
    state = solve(net, 60.0 * LITRE_PER_MIN)
    b = feed_boundary(case, 5.8e-3)
    assert b.gap_speed == pytest.approx(1e-3 / (math.pi * (10e-3 ** 2 - 9.5e-3 ** 2)), rel=1e-12)
    assert b.gap_speed == pytest.approx(32.65, abs=0.01)
    assert b.tube_speed * math.pi * 8e-3 ** 2 == pytest.approx(state.V_IB, rel=1e-12)
    assert state.V_IB / LITRE_PER_MIN == pytest.approx(45.20, abs=0.01)
    assert gap_pressure_below_feed(net, state, net.sensor_b_from_feed) == pytest.approx(state.p_B - net.p_ambient,
                                                                                       rel=1e-12)
    assert state.gauge_bar("p_B") == pytest.approx(25.70, abs=0.01)
    assert b.tube_outlet_pressure == pytest.approx(state.p_C2 - net.p_ambient) and 0.1e5 < b.tube_outlet_pressure
    # the gap outlet's pressure lies between p_feed less the entrance loss and p_B (friction ~0.9 bar / 10 mm)
    assert state.p_B - net.p_ambient < b.gap_outlet_pressure < state.p_feed - net.p_ambient
    deck_outlets = {o.name: o.pressure for o in scene.case.outlets}
    below = scene.layout.z_nozzles - scene.layout.outlets["gap"].center[2]
    assert below > 0 and deck_outlets["gap_outlet"] == pytest.approx(gap_pressure_below_feed(net, state, below),
                                                                     rel=1e-12)


def test_start_state_carries_the_inlets_flows_at_the_held_pressures():
    case, scene = _scene()
    layout, flow, dx = scene.layout, scene, case.numerics.dx
    b = feed_boundary(case, scene.layout.z_nozzles - scene.layout.outlets["gap"].center[2])
    fluid = flow.kind == 0
    x, v = flow.positions[fluid], flow.velocities[fluid]
    # one lattice layer of the gap and of the tube carries V_total and V_IB (as the engine scales its inlets)
    z_layer = x[layout.gap.contains(x), 2].min()
    layer = np.abs(x[:, 2] - z_layer) < 0.25 * dx
    gap_layer, tube_layer = layer & layout.gap.contains(x), layer & layout.tube.contains(x)
    assert -v[gap_layer, 2].sum() * dx * dx == pytest.approx(b.state.V_total, rel=1e-9)
    z_tube = x[layout.tube.contains(x) & (x[:, 2] > layout.z_nozzles + 2e-3), 2].min()
    tube_layer = (np.abs(x[:, 2] - z_tube) < 0.25 * dx) & layout.tube.contains(x)
    assert v[tube_layer, 2].sum() * dx * dx == pytest.approx(b.state.V_IB, rel=1e-9)
    nozzles = np.zeros(len(x), dtype=bool)
    for z in layout.nozzles:
        nozzles |= z.contains(x)
    assert nozzles.sum() > 0 and not v[nozzles].any()
    # densities: the Tait EOS (gamma 7, c0 = 1000 m/s) inverted at the held pressures
    rho0, c0 = case.fluid.density, case.c0
    p_back = rho0 * c0 ** 2 / 7 * ((flow.densities[fluid] / rho0) ** 7 - 1)
    assert np.allclose(p_back, start_pressure(layout, b, x), rtol=0, atol=1e-3)
    assert tait_density(case, np.array([b.gap_outlet_pressure]))[0] == pytest.approx(
        rho0 * (1 + 7 * b.gap_outlet_pressure / (rho0 * c0 ** 2)) ** (1 / 7), rel=1e-14)
    assert np.allclose(p_back[layout.gap.contains(x)], b.gap_outlet_pressure, atol=1e-3)
    assert np.allclose(p_back[layout.tube.contains(x)], b.tube_outlet_pressure, atol=1e-3)
    assert np.allclose(start_velocities(case, layout, b, x), flow.velocities[fluid])


def test_flows_and_balances_on_synthetic_series():
    t = np.linspace(0.0, 1e-3, 101)
    ag_all, ib, nz = np.full(101, 0.4e-3), np.full(101, 0.7e-3), np.full(101, 0.1e-3)
    series = {"inflow_feed_inlet": np.full(101, 1.6e-3), "flow_rate_AG_all": ag_all, "flow_rate_IB": ib,
              "flow_rate_mixed": np.full(101, 1.3e-3), **{f"flow_rate_nozzle{k}": nz for k in range(6)}}
    flows = feed_flows(series)
    assert flows["V_AG"] == pytest.approx(np.full(101, 1.1e-3))  # AG_all counts the tube's +z flow negative
    means = steady_means(t, flows)
    assert means["V_EN"] == pytest.approx(0.6e-3) and means["EN_share"] == pytest.approx(0.375)
    assert means["residual_eq1"] == pytest.approx(-0.1e-3) and means["residual_eq1_share"] == pytest.approx(-1 / 16)
    assert means["residual_tube"] == pytest.approx(0.0, abs=1e-15)


def test_the_feed_inlets_peak_must_fit_under_max_speed():
    """80 l/min over the gap's 30.63 mm^2 is 43.53 m/s, its annular profile's peak bound 87.06 m/s: above
    max_speed = 80 (refused, by name), below 100 (the presets')."""
    load_case(CASE, preset="feed_quick", overrides=["scene.network_flow=80"])
    with pytest.raises(OrchestratorError) as err:
        load_case(CASE, preset="feed_quick", overrides=["scene.network_flow=80", "fluid.max_speed=80"])
    assert "fluid.max_speed" in str(err.value) and "87.06" in str(err.value)


def test_a_feed_scene_needs_the_boundary_particles():
    with pytest.raises(OrchestratorError) as err:
        load_case(CASE, preset="feed_quick", overrides=["physics.walls='penalty'"])
    assert "physics.walls = 'penalty'" in str(err.value) and "allowed: 'particles'" in str(err.value)


def test_a_dx_with_two_lattices_is_refused():
    """dx = 0.39 mm: round(20 / 0.39) = 51, round(16 / 0.39) = 41 -- odd, one lattice; dx = 0.38 mm: 53 and 42."""
    load_case(CASE, preset="feed_quick", overrides=["numerics.dx=0.39e-3"])
    with pytest.raises(OrchestratorError) as err:
        load_case(CASE, preset="feed_quick", overrides=["numerics.dx=0.38e-3"])
    assert "different lattices" in str(err.value) and "numerics.dx" in str(err.value)


def test_slab_flow_is_the_volume_flux_of_a_lattice_pipe_flow():
    """A bore of R = 8 mm filled on a lattice of dx = 0.25 mm, Hagen-Poiseuille v = 2 U (1 - r^2 / R^2) with
    U = 3.75 m/s (45.2 l/min), at rho = 1001 kg/m^3 with m = rho0 dx^3: the slab's flux is U pi R^2 rho0 / rho
    (the volume m / rho each particle stands for) to the lattice's sampling of the disc (0.3 %)."""
    dx, radius, u = 0.25e-3, 8e-3, 3.75
    g = (np.arange(-40, 40) + 0.5) * dx
    x, y, z = np.meshgrid(g, g, (np.arange(-6, 6) + 0.5) * dx, indexing="ij")
    pos = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    r = np.hypot(pos[:, 0], pos[:, 1])
    pos = pos[r < radius]
    r = r[r < radius]
    vel = np.zeros_like(pos)
    vel[:, 2] = 2 * u * (1 - (r / radius) ** 2)
    arrays = {"positions": pos, "velocities": vel, "densities": np.full(len(pos), 1001.0),
              "kind": np.zeros(len(pos), dtype=np.int8)}
    flow = slab_flow(arrays, 1000.0 * dx ** 3, 0.0, 1.0e-3, radius)
    assert flow == pytest.approx(u * math.pi * radius ** 2 * 1000.0 / 1001.0, rel=0.003)
    assert slab_flow(arrays, 1000.0 * dx ** 3, 5e-3, 1.0e-3, radius) == 0.0  # no fluid there


@pytest.mark.sph
def test_tiny_feed_run(tmp_path):
    """20 us of a coarse feed scene on the sph executable: it stays stable, the feed inlet delivers V_total times the
    time to within one lattice layer of the gap (the inlet converts whole layers), and the outlets' held pressures
    keep the gap and the tube near the network's (B within 40 bar of 28.6, C2 within 5 bar of 0.17: the start's
    radial ringing, damped by the walls' artificial viscosity)."""
    import h5py

    from orchestrator.run import run_case

    loaded = load_case(CASE, preset="feed_quick", overrides=[
        "numerics.dx=0.4e-3", "scene.c2_distance=4e-3", "simulation.duration=2e-5", "numerics.threads=1",
        "output.picture_times=[]", "output.frame_interval=1e-5", "output.series_interval=2e-6"])
    summary = run_case(loaded, engine="sph", out_dir=tmp_path / "run", progress=False)
    assert summary.status == "ok"
    area, dx = math.pi * (10e-3 ** 2 - 9.5e-3 ** 2), loaded.model.numerics.dx
    with h5py.File(tmp_path / "run" / "run.h5", "r") as h5:
        time, rate = h5["series/time"][()], h5["series/inflow_feed_inlet"][()]
        b = h5["series/pressure_probe_B"][()]
        c2 = h5["series/pressure_probe_C2"][()]
    delivered = float(np.sum(rate[1:] * np.diff(time)))
    assert abs(delivered - 1e-3 * time[-1]) <= area * dx
    assert np.all(np.abs(b - 28.6e5) < 40e5) and np.all(np.abs(c2 - 0.17e5) < 5e5)
    assert summary.measured["max_density_deviation"] < 0.05


@pytest.mark.parametrize("preset, probed", [("feed", True), ("feed_quick", False)])
def test_the_feed_presets_sizes_and_timing_probe(preset, probed):
    """The feed scene starts filled (probe.end_particles is its fluid count): feed (dx = 0.25 mm, 4 particles across
    a nozzle) plans 11,734 steps over 280,936 fluid particles (its inlets 4 layers deep: layout.inlet_layers), 3.3e9 particle-steps, and is probed before it starts;
    feed_quick (2,292 steps over 47,628) is not."""
    from orchestrator.kinds import bind
    from orchestrator.drill.probe import end_particles
    from orchestrator.drill.sph import PROBE_ABOVE_PARTICLE_STEPS

    case = load_case(CASE, preset=preset).model
    scene = build_scene(case)
    assert end_particles(scene) == scene.n_fluid
    nozzle_d = case.network().d_ejector_nozzle
    assert nozzle_d / case.numerics.dx >= (4 - 1e-9 if preset == "feed" else 2.5 - 1e-9)
    expected = {"feed": (11_734, 280_936), "feed_quick": (2_292, 47_628)}[preset]
    assert (case.planned_steps, scene.n_fluid) == expected
    assert (case.planned_steps * scene.n_fluid > PROBE_ABOVE_PARTICLE_STEPS) is probed
    assert bind("ejector_feed", "sph", scene).wants_probe(scene) is probed
