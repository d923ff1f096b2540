"""3D open boundaries of the sph_flow kind: inlet profiles and outlet pressure in the case and the deck, cylinder
blocks, and the pipe / annulus checks (checks_open) on synthetic runs against the exact laminar solutions."""

import math
from pathlib import Path

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

CASES = Path(__file__).resolve().parent.parent / "cases" / "verification"
PIPE = CASES / "sph_pipe_hagen_poiseuille.toml"
ANNULUS = CASES / "sph_annulus_laminar.toml"


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
    # the fluid block's lattice: sites of the annulus 3 mm <= r < 8 mm over 19 layers along x (by count, +-2 %)
    per_layer = np.count_nonzero(fluid) / 19
    assert per_layer == pytest.approx(math.pi * (8**2 - 3**2), rel=0.02)
    plug = load_case(CASES.parent.parent / "tests" / "data" / "sph_channel_3d.toml").model
    plug_inlet = json.loads(deck_context(build_scene(plug))["inlets"][0])
    assert "profile" not in plug_inlet and "pressure" not in plug_inlet  # a plug inlet's deck is as before


@pytest.mark.parametrize("old, new, message", [
    ('profile = "annular"', 'profile = "parabolic"', "inner_radius is given exactly with profile = 'annular'"),
    ("inner_radius = 0.003\nvelocity", "inner_radius = 0.009\nvelocity", "inner_radius < radius"),
    ("velocity = 0.02 ", "velocity = 0.03 ", "peaks at 0.06 m/s"),
    ('pressure = "extrapolated"', 'pressure = "fixed"', "pressure"),
    ("radius = 0.008, inner_radius = 0.003}", "radius = 0.008, inner_radius = 0.009}", "must be below radius"),
])
def test_bad_open_boundary_keys_are_named(tmp_path, old, new, message):
    text = ANNULUS.read_text()
    assert old in text
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace(old, new, 1))
    with pytest.raises(CaseError, match=message):
        load_case(bad)


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
