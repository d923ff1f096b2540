"""3D open boundaries of the sph_flow kind: inlet profiles and outlet pressure in the case and the deck, cylinder
blocks, and the pipe / annulus checks (checks_open) on synthetic runs against the exact laminar solutions."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from orchestrator.case import load_case
from orchestrator.errors import CaseError
from orchestrator.kinds.sph_flow.checks import evaluate
from orchestrator.kinds.sph_flow.checks_open import annulus_velocity
from orchestrator.kinds.sph_flow.scene import build_sph_flow as build_scene
from orchestrator.kinds.sph_flow.sph import deck_context
from orchestrator.reference.hydraulics import annulus_laminar_flow
from paths import VERIFICATION

PIPE = VERIFICATION / "sph_pipe_hagen_poiseuille.toml"
ANNULUS = VERIFICATION / "sph_annulus_laminar.toml"


@pytest.mark.parametrize("r_inner", [0.0, 0.003])
def test_annulus_velocity_carries_the_flow_of_the_network_model(r_inner):
    """2 pi int u r dr over the section equals annulus_laminar_flow (an independent closed form)."""
    r_outer, mu, gradient = 0.008, 0.1, 500.0
    q, _ = quad(lambda r: 2 * math.pi * r * float(annulus_velocity(r, gradient, r_outer, r_inner, mu)),
                max(r_inner, 1e-12), r_outer, epsabs=0, epsrel=1e-12)
    assert q == pytest.approx(annulus_laminar_flow(gradient, 1.0, r_outer, r_inner, mu), rel=1e-9)
    assert float(annulus_velocity(r_outer, gradient, r_outer, r_inner, mu)) == pytest.approx(0.0, abs=1e-15)
    if r_inner:
        assert float(annulus_velocity(r_inner, gradient, r_outer, r_inner, mu)) == pytest.approx(0.0, abs=1e-12)
    else:  # Hagen-Poiseuille: peak G R^2 / (4 mu)
        assert float(annulus_velocity(0.0, gradient, r_outer, 0.0, mu)) == pytest.approx(gradient * r_outer**2 / 0.4)


def test_the_cases_reach_the_deck_and_build_cylinders():
    case = load_case(ANNULUS).model
    deck = deck_context(build_scene(case))
    import json

    inlet, outlet = json.loads(deck["inlets"][0]), json.loads(deck["outlets"][0])
    assert inlet["profile"] == "annular" and inlet["inner_radius"] == 0.003 and inlet["pressure"] == "extrapolated"
    assert outlet["pressure"] == 0.0
    scene = build_scene(case)
    r = np.hypot(scene.positions[:, 1], scene.positions[:, 2])
    fluid = scene.kind == 0
    assert np.all((r[fluid] >= 0.003) & (r[fluid] < 0.008)) and np.all((r[~fluid] < 0.003) | (r[~fluid] >= 0.008))
    # the fluid block's lattice: sites of the annulus 3 mm <= r < 8 mm in each layer along x of its 17.5 mm (to the
    # end of the outlet buffer), by count, +-2 % (the circles' staircase: 700 sites against 691.2 at dx = 0.5 mm)
    dx = case.numerics.dx
    per_layer = np.count_nonzero(fluid) / round(17.5e-3 / dx)
    assert per_layer == pytest.approx(math.pi * (8e-3**2 - 3e-3**2) / dx**2, rel=0.02)
    plug = load_case(VERIFICATION.parent.parent / "tests" / "data" / "sph_channel_3d.toml").model
    plug_inlet = json.loads(deck_context(build_scene(plug))["inlets"][0])
    assert "profile" not in plug_inlet and "pressure" not in plug_inlet  # a plug inlet's deck is as before


@pytest.mark.parametrize("old, new, message", [
    ('profile = "annular"', 'profile = "parabolic"', "inner_radius is given exactly with profile = 'annular'"),
    ("inner_radius = 0.003\nvelocity", "inner_radius = 0.009\nvelocity", "inner_radius < radius"),
    ("velocity = 0.02 ", "velocity = 0.03 ", "peaks at 0.06 m/s"),
    ('pressure = "extrapolated"', 'pressure = "fixed"', "pressure"),
    ("radius = 0.008, inner_radius = 0.003}", "radius = 0.008, inner_radius = 0.009}", "must be below radius"),
    ('radius = 0.003, wall = "outer"}', 'radius = 0.003, wall = "inner"}', "wall = 'inner' needs an inner face"),
    ("radius = 0.008, inner_radius = 0.003}", 'radius = 0.008, inner_radius = 0.003, wall = "both"}',
     r"blocks\[0\].cylinder.wall is given for a fluid block"),
    ('wall = "outer"}', 'wall = "out"}', "wall"),
    ("pressure = 0.0               # Pa: the domain's reference pressure", "backflow = true",
     "outlet 'drain': backflow needs a pressure"),
    ("pressure = 0.0               # Pa: the domain's reference pressure", "column_length = 0.2",
     "outlet 'drain': a column .column_length. needs a pressure"),
    ("pressure = 0.0               # Pa: the domain's reference pressure", "pressure = 0.0\ncolumn_loss = 2.0",
     "outlet 'drain': column_loss and column_area need a column_length"),
    ("pressure = 0.0               # Pa: the domain's reference pressure", "pressure = 0.0\ncolumn_length = -1.0",
     "column_length"),
])
def test_bad_open_boundary_keys_are_named(tmp_path, old, new, message):
    text = ANNULUS.read_text()
    assert old in text
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace(old, new, 1))
    with pytest.raises(CaseError, match=message):
        load_case(bad)


def test_cylinder_walls_give_each_boundary_site_its_nearest_point_of_the_true_wall(tmp_path):
    """cylinder.wall: a boundary site's wall_point lies on the wetted face, along its radial direction, at its axial
    position; the particle file carries it only when a block asks for it."""
    import h5py

    from orchestrator.kinds.sph_flow.case_cylinder import BlockCylinder
    from orchestrator.kinds.sph_flow.sph import write_particles

    scene = build_scene(load_case(ANNULUS).model)
    wall, boundary = scene.wall_point, scene.kind == 1
    assert np.all(np.isnan(wall[~boundary])) and not np.any(np.isnan(wall[boundary]))
    r_site = np.hypot(scene.positions[:, 1], scene.positions[:, 2])[boundary]
    r_wall = np.hypot(wall[boundary, 1], wall[boundary, 2])
    np.testing.assert_allclose(r_wall, np.where(r_site >= 0.008, 0.008, 0.003), rtol=1e-12)
    assert np.array_equal(wall[boundary, 0], scene.positions[boundary, 0])  # the same axial position
    radial = scene.positions[boundary, 1:] / r_site[:, None]
    np.testing.assert_allclose(wall[boundary, 1:] / r_wall[:, None], radial, atol=1e-12)  # along the radius
    write_particles(scene, tmp_path / "p.h5")
    with h5py.File(tmp_path / "p.h5") as h5:
        np.testing.assert_array_equal(h5["wall_point"][:], wall)
    channel = build_scene(load_case(VERIFICATION.parent.parent / "tests" / "data" / "sph_channel_3d.toml").model)
    assert channel.wall_point is None
    write_particles(channel, tmp_path / "c.h5")
    with h5py.File(tmp_path / "c.h5") as h5:
        assert "wall_point" not in h5  # no block names a wall: the engine keeps Adami's mirror, bitwise as before
    # a tube wetted on both sides: each site's nearer face; a site on the axis has no direction (NaN)
    tube = BlockCylinder(axis=2, center=(1.0, 2.0, 0.0), radius=0.005, inner_radius=0.002, wall="both")
    points = np.array([[1.0, 2.0025, 0.3], [1.0045, 2.0, -0.1], [1.0, 2.0, 0.0]])
    np.testing.assert_allclose(tube.wall_points(points)[:2], [[1.0, 2.002, 0.3], [1.005, 2.0, -0.1]], rtol=1e-15)
    assert np.all(np.isnan(tube.wall_points(points)[2]))
    core = BlockCylinder(axis=0, center=(0.0, 0.0, 0.0), radius=0.003, wall="outer")
    np.testing.assert_allclose(core.wall_points([[0.5, 0.0012, -0.0016]]), [[0.5, 0.0018, -0.0024]], rtol=1e-14)


def _synthetic_run(case, perturb=0.0, gradient_error=0.0, lost=0):
    """A run.h5 dict of the exact steady flow: particles on the case's lattice with the exact profile and a linear
    pressure, frames over the second half, inflow and outflow series of U A."""
    inlet = case.inlets[0]
    r_outer, r_inner = inlet.radius, inlet.inner_radius or 0.0
    mu, dx, length = case.fluid.density * case.fluid.viscosity, case.numerics.dx, case.outlets[0].center[0]
    flow = inlet.velocity * math.pi * (r_outer**2 - r_inner**2)
    gradient = flow / annulus_laminar_flow(1.0, 1.0, r_outer, r_inner, mu)
    g = (np.arange(-10, 10) + 0.5) * dx
    x, y, z = np.meshgrid((np.arange(int(length / dx)) + 0.5) * dx, g, g, indexing="ij")
    x, y, z = x.ravel(), y.ravel(), z.ravel()
    r = np.hypot(y, z)
    keep = (r >= r_inner) & (r < r_outer)
    x, y, z, r = x[keep], y[keep], z[keep], r[keep]
    u = annulus_velocity(r, gradient, r_outer, r_inner, mu) * (1 + perturb * np.sin(np.pi * (r - r_inner)
                                                                                     / (r_outer - r_inner)))
    p = (1 + gradient_error) * gradient * (length - x)
    rho0 = case.fluid.density
    frames = {"attrs": {}}
    times = np.linspace(0.5, 1.0, 6) * case.simulation.duration
    for k, t in enumerate(times):
        n = len(x) - (lost * k)
        frames[str(k)] = {"attrs": {"time": t}, "kind": np.zeros(n, np.int8),
                          "positions": np.column_stack([x, y, z])[:n],
                          "velocities": np.column_stack([u, 0 * u, 0 * u])[:n], "pressures": p[:n],
                          "densities": np.full(n, rho0)}
    time = np.linspace(0.0, case.simulation.duration, 49)
    series = {"time": time, "inflow_feed": np.full(len(time), flow), "outflow_drain": np.full(len(time), flow)}
    return {"attrs": {"status": "ok"}, "series": series, "frames": frames}


@pytest.mark.parametrize("path", [PIPE, ANNULUS])
def test_open_checks_pass_the_exact_flow_and_fail_errors(path):
    case = load_case(path).model
    rows, _plots = evaluate(case, _synthetic_run(case))
    by = {r["quantity"]: r for r in rows}
    assert set(by) == {"u_profile", "pressure_gradient", "mass_balance", "density_drift"}
    assert all(r["passed"] for r in rows), rows
    assert by["pressure_gradient"]["rel_error"] < 1e-9 and by["mass_balance"]["rel_error"] < 1e-12
    assert by["u_profile"]["rel_error"] < 1e-9  # bin means of the exact profile at the bins' mean radius: exact
    rows, _ = evaluate(case, _synthetic_run(case, perturb=0.05, gradient_error=0.04))
    by = {r["quantity"]: r for r in rows}
    assert not by["u_profile"]["passed"] and by["u_profile"]["rel_error"] > 0.03
    assert not by["pressure_gradient"]["passed"] and by["pressure_gradient"]["rel_error"] == pytest.approx(0.04)
    # particles lost from the domain (neither in the outflow nor in the fluid): the mass balance fails
    rows, _ = evaluate(case, _synthetic_run(case, lost=20))
    assert not {r["quantity"]: r for r in rows}["mass_balance"]["passed"]
