"""Viscoelastic closed forms (reference/viscoelastic_flows.py) against independent numerical solutions: the
Waters & King start-up against a finite-difference method of lines, the PTT steady shear against a root of the
full constitutive equations, the oscillatory start-up against an integration of the UCM tensor law."""

import math

import numpy as np
import pytest

from orchestrator.errors import OrchestratorError
from orchestrator.reference.maxwell import TABLE_III, Mode, loss_modulus, storage_modulus
from orchestrator.reference.sph_flows import poiseuille_velocity
from orchestrator.reference.viscoelastic_flows import (
    maxwell_saos_stress,
    oldroyd_b_poiseuille_steady_velocity,
    ptt_f_in_shear,
    ptt_multimode_steady_shear,
    ptt_steady_shear,
    waters_king_centreline_velocity,
    waters_king_startup_velocity,
)

# Morris et al.'s channel (L = 1 mm, g = 2e-4 m/s^2) with water's density and nu_0 = 1e-6 m^2/s: the steady
# centre-line speed is 2.5e-5 m/s and El = lambda nu_0 / L^2 = lambda / (1 s).
L, G, RHO, ETA0 = 1e-3, 2e-4, 1000.0, 1e-3
PEAK = G * L**2 * RHO / (8 * ETA0)


def fluid(beta, relaxation_time):
    """Keyword arguments of the Waters & King functions for beta = eta_s / eta_0 and lambda (s)."""
    return dict(gap=L, body_force=G, rho=RHO, eta_polymer=(1 - beta) * ETA0, eta_solvent=beta * ETA0,
                relaxation_time=relaxation_time)


def method_of_lines(beta, relaxation_time, times, cells, method):
    """u (m/s) at the interior nodes y_j = j L / cells of rho u_t = d tau/dy + eta_s u_yy + rho g,
    lambda tau_t + tau = eta_p u_y, u = 0 at both plates, from rest: u on the nodes, tau between them (second
    order, staggered), integrated by scipy's solve_ivp."""
    from scipy import sparse
    from scipy.integrate import solve_ivp

    eta_p, eta_s, lam = (1 - beta) * ETA0, beta * ETA0, relaxation_time
    dy, nodes = L / cells, cells - 1
    div = sparse.diags([-np.ones(nodes), np.ones(nodes)], [0, 1], shape=(nodes, cells)) / dy  # tau -> nodes
    grad = sparse.diags([-np.ones(nodes), np.ones(nodes)], [-1, 0], shape=(cells, nodes)) / dy  # u -> midpoints
    lap = sparse.diags([np.ones(nodes - 1), -2 * np.ones(nodes), np.ones(nodes - 1)], [-1, 0, 1]) / dy**2
    a = sparse.bmat([[eta_s / RHO * lap, div / RHO], [eta_p / lam * grad, -sparse.identity(cells) / lam]]).tocsr()
    b = np.concatenate([np.full(nodes, G), np.zeros(cells)])
    options = dict(jac=a) if method == "Radau" else {}
    sol = solve_ivp(lambda _, x: a @ x + b, (0.0, max(times)), np.zeros(nodes + cells), method=method,
                    t_eval=times, rtol=1e-9, atol=1e-10 * PEAK, **options)
    assert sol.success
    return np.arange(1, cells) * dy, sol.y[:nodes].T


def test_oldroyd_b_startup_matches_the_method_of_lines_and_overshoots():
    lam = 1.0  # El = 1, beta = 1/9: the first modes oscillate, the high ones are overdamped
    times = lam * np.array([0.2, 0.5, 1.0, 2.0, 5.0])
    y, numerical = method_of_lines(1 / 9, lam, times, cells=400, method="Radau")
    series = waters_king_startup_velocity(y[None, :], times[:, None], **fluid(1 / 9, lam))
    # measured: at most 8e-6 of the peak (the grid's (k dy)^2 error)
    np.testing.assert_allclose(series, numerical, rtol=0, atol=5e-5 * PEAK)
    centre = waters_king_centreline_velocity(np.linspace(0, 3 * lam, 601), **fluid(1 / 9, lam))
    assert centre.max() == pytest.approx(2.7804 * PEAK, rel=1e-4)  # the overshoot, at t = 0.525 s
    assert numerical[1, len(y) // 2] > 2.7 * PEAK  # the method of lines overshoots too (t = 0.5 s)


def test_overdamped_oldroyd_b_matches_the_method_of_lines():
    lam = 0.01  # El = 0.01: every mode overdamped
    times = lam * np.array([0.2, 1.0, 5.0, 50.0])
    y, numerical = method_of_lines(1 / 9, lam, times, cells=200, method="Radau")
    series = waters_king_startup_velocity(y[None, :], times[:, None], **fluid(1 / 9, lam))
    np.testing.assert_allclose(series, numerical, rtol=0, atol=1e-4 * PEAK)


def test_ucm_startup_converges_to_the_series():
    """beta = 0 (UCM): shear waves with kinks cross the channel, so the finite differences converge only to
    first order; the RMS gap to the series halves when the grid is refined (measured 1.3e-3 -> 6.6e-4 of the
    peak at t = lambda/5, 2.0e-3 -> 1.0e-3 at t = lambda)."""
    lam = 1.0
    times = lam * np.array([0.2, 1.0, 2.0])
    gaps = []
    for cells in (400, 800):
        y, numerical = method_of_lines(0.0, lam, times, cells=cells, method="DOP853")
        series = waters_king_startup_velocity(y[None, :], times[:, None], **fluid(0.0, lam))
        gaps.append(np.sqrt(np.mean((series - numerical) ** 2, axis=1)) / PEAK)
    assert np.all(gaps[1] < 2.5e-3)
    np.testing.assert_allclose(gaps[0] / gaps[1], 2.0, rtol=0.1)
    centre = waters_king_centreline_velocity(np.linspace(0, 3 * lam, 601), **fluid(0.0, lam))
    assert centre.max() == pytest.approx(4.0 * PEAK, rel=1e-3)  # g t until the waves from the plates meet


def test_startup_begins_at_rest_and_ends_on_the_parabola():
    y = np.linspace(0, L, 21)
    for beta in (0.0, 1 / 9):
        assert np.max(np.abs(waters_king_startup_velocity(y, 0.0, **fluid(beta, 1.0)))) < 2e-6 * PEAK
    late = waters_king_startup_velocity(y, 200.0, **fluid(1 / 9, 1.0))
    steady = oldroyd_b_poiseuille_steady_velocity(y, gap=L, body_force=G, rho=RHO, eta_polymer=8 / 9 * ETA0,
                                                  eta_solvent=ETA0 / 9)
    np.testing.assert_allclose(late, steady, rtol=0, atol=1e-10 * PEAK)
    assert steady[10] == pytest.approx(PEAK, rel=1e-14)


def test_newtonian_limits_are_morris_series():
    y, t = np.linspace(0, L, 41), np.array([0.01, 0.1, 0.4])[:, None]
    for nu in (ETA0 / RHO, ETA0 / 9 / RHO):
        morris = np.array([poiseuille_velocity(y, when, L, nu, G) for when in t[:, 0]])
        eta = nu * RHO
        # beta -> 1: no polymer, any lambda
        solvent_only = waters_king_startup_velocity(y, t, gap=L, body_force=G, rho=RHO, eta_polymer=0.0,
                                                    eta_solvent=eta, relaxation_time=1.0)
        np.testing.assert_allclose(solvent_only, morris, rtol=0, atol=1e-12 * PEAK)
        # lambda = 0 and lambda -> 0 (El = 1e-7): the polymer answers at once
        for lam, tolerance in ((0.0, 1e-12), (1e-7, 1e-5)):
            quick = waters_king_startup_velocity(y, t, gap=L, body_force=G, rho=RHO, eta_polymer=0.5 * eta,
                                                 eta_solvent=0.5 * eta, relaxation_time=lam)
            np.testing.assert_allclose(quick, morris, rtol=0, atol=tolerance * PEAK)
    nearly = waters_king_startup_velocity(y, t, **fluid(1 - 1e-6, 1.0))  # beta = 1 - 1e-6
    morris = np.array([poiseuille_velocity(y, when, L, ETA0 / RHO, G) for when in t[:, 0]])
    np.testing.assert_allclose(nearly, morris, rtol=0, atol=1e-5 * PEAK)


def test_critically_damped_mode_is_continuous():
    """lambda at which the first mode is critically damped: (1 + lambda nu_s k^2)^2 = 4 lambda nu_0 k^2; the
    overdamped and underdamped branches meet there."""
    beta, k2 = 1 / 9, (math.pi / L) ** 2
    nus, nu0 = beta * ETA0 / RHO, ETA0 / RHO
    a, b = (nus * k2) ** 2, 2 * nus * k2 - 4 * nu0 * k2
    critical = (-b - math.sqrt(b * b - 4 * a)) / (2 * a)  # s, the smaller root (0.106 s)
    assert (1 + critical * nus * k2) ** 2 == pytest.approx(4 * critical * nu0 * k2, rel=1e-12)
    y, t = np.linspace(0, L, 11), np.array([0.0, 0.02, 0.1, 0.3])[:, None]
    at = waters_king_startup_velocity(y, t, **fluid(beta, critical))
    for factor in (1 - 1e-9, 1 + 1e-9):
        np.testing.assert_allclose(waters_king_startup_velocity(y, t, **fluid(beta, critical * factor)), at,
                                   rtol=0, atol=1e-8 * PEAK)
    # and it solves the PDE: the method of lines at this lambda
    yn, numerical = method_of_lines(beta, critical, np.array([0.02, 0.1, 0.3]), cells=200, method="Radau")
    series = waters_king_startup_velocity(yn[None, :], np.array([0.02, 0.1, 0.3])[:, None], **fluid(beta, critical))
    np.testing.assert_allclose(series, numerical, rtol=0, atol=1e-4 * PEAK)


def test_bad_fluid_is_named():
    with pytest.raises(OrchestratorError, match="relaxation_time"):
        waters_king_startup_velocity(0.5 * L, 1.0, **fluid(0.5, -1.0))
    with pytest.raises(OrchestratorError, match="rho"):
        waters_king_startup_velocity(0.5 * L, 1.0, **{**fluid(0.5, 1.0), "rho": 0.0})
