"""Viscoelastic closed forms (reference/viscoelastic_flows.py) against independent numerical solutions: the
Waters & King start-up against a finite-difference method of lines, the PTT steady shear against a root of the
full constitutive equations, the oscillatory start-up against an integration of the UCM tensor law."""

import math

import numpy as np
import pytest

from orchestrator.errors import OrchestratorError
from orchestrator.reference.maxwell import TABLE_III, Mode, loss_modulus, storage_modulus
from orchestrator.reference.sph_flows import poiseuille_velocity
from orchestrator.reference.sph_ptt import PttFluid, ptt_mode_rates
from orchestrator.reference.viscoelastic_flows import (
    ptt_startup_shear,
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
    return {"gap": L, "body_force": G, "rho": RHO, "eta_polymer": (1 - beta) * ETA0, "eta_solvent": beta * ETA0,
            "relaxation_time": relaxation_time}


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
    options = {"jac": a} if method == "Radau" else {}
    sol = solve_ivp(lambda _, x: a @ x + b, (0.0, max(times)), np.zeros(nodes + cells), method=method,
                    t_eval=times, rtol=1e-9, atol=1e-10 * PEAK, **options)
    assert sol.success
    return np.arange(1, cells) * dy, sol.y[:nodes].T


def test_oldroyd_b_startup_matches_the_method_of_lines_and_overshoots():
    lam = 1.0  # El = 1, beta = 1/9: modes n = 1, 3, 5 oscillate, n >= 7 are overdamped
    times = lam * np.array([0.2, 0.5, 1.0, 2.0, 5.0])
    y, numerical = method_of_lines(1 / 9, lam, times, cells=400, method="Radau")
    series = waters_king_startup_velocity(y[None, :], times[:, None], **fluid(1 / 9, lam))
    # measured: at most 8e-6 of the peak (the grid's (k dy)^2 error)
    np.testing.assert_allclose(series, numerical, rtol=0, atol=5e-5 * PEAK)
    centre = waters_king_centreline_velocity(np.linspace(0, 3 * lam, 601), **fluid(1 / 9, lam))
    assert centre.max() == pytest.approx(2.7804 * PEAK, rel=1e-4)  # the overshoot, at t = 0.525 s
    assert numerical[1, len(y) // 2] > 2.7 * PEAK  # the method of lines overshoots too (t = 0.5 s)


def test_overdamped_first_mode_matches_the_method_of_lines():
    lam = 0.01  # El = 0.01: the first mode overdamped, n = 3..55 oscillating, n >= 57 overdamped
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


# ------------------------------------------------------------------------------------------ PTT steady shear
def homogeneous_shear_rates(modes, epsilon):
    """d tau / dt (flattened) of each 2-D mode in the homogeneous shear of reference/sph_ptt.py's rate law
    (eq. R1, the engine's), as a function of (t, tau, gamma_dot) for solve_ivp."""
    fluid = PttFluid(rho0=1.0, c0=1.0, lambdas=tuple(m.relaxation_time for m in modes),
                     etas=tuple(m.viscosity for m in modes), epsilon=epsilon, eta_s=0.0, h=1.0, box=(1.0, 1.0))

    def rate(_, tau_flat, gamma_dot):
        grad_v = np.array([[[0.0, gamma_dot], [0.0, 0.0]]])  # L_xy = d v_x / d y
        return ptt_mode_rates(grad_v, tau_flat.reshape(1, len(modes), 2, 2), fluid).ravel()

    return rate


def test_ptt_shear_by_hand_and_ucm():
    one = ptt_steady_shear(1.0, 1.0, 1.0, 0.1)  # Wi = 1, eps = 0.1
    assert one.f == pytest.approx(1.150973, abs=1e-6)
    assert one.f**3 - one.f**2 == pytest.approx(0.2, rel=1e-14)
    assert one.viscosity == pytest.approx(0.868830, abs=1e-6)
    rate, lam, eta = np.array([0.0, 0.3, 2.0, 50.0]), 0.5, 20.0
    ucm = ptt_steady_shear(rate, lam, eta, 0.0)
    np.testing.assert_array_equal(ucm.f, 1.0)
    np.testing.assert_allclose(ucm.shear_stress, eta * rate, rtol=1e-15)
    np.testing.assert_allclose(ucm.first_normal_stress_difference, 2 * eta * lam * rate**2, rtol=1e-15)
    wi = np.array([0.0, 1e-6, 1e-2, 1.0, 1e2, 1e5])
    f = ptt_f_in_shear(wi, 0.25)
    assert np.all(np.abs(f**3 - f**2 - 0.5 * wi**2) <= 4e-16 * f**3)  # the cubic, to rounding
    assert np.all(np.diff(f) > 0) and f[0] == 1.0
    with pytest.raises(OrchestratorError, match="epsilon"):
        ptt_f_in_shear(1.0, -0.1)


@pytest.mark.parametrize("epsilon, weissenberg", [(0.1, 1.0), (0.02, 30.0), (0.5, 0.05), (0.25, 400.0)])
def test_ptt_shear_solves_the_tensor_equations(epsilon, weissenberg):
    """The steady 2-D law f tau - lambda (L tau + tau L^T) = eta (L + L^T), f = 1 + (eps lambda / eta) tr tau,
    solved for (tau_xx, tau_xy, tau_yy) by scipy's root finder from the UCM stresses."""
    from scipy.optimize import root

    lam, eta = 0.2, 50.0
    rate = weissenberg / lam
    grad_v = np.array([[0.0, rate], [0.0, 0.0]])

    def residual(p):
        tau = modulus * np.array([[p[0], p[1]], [p[1], p[2]]])
        f = 1.0 + epsilon * lam / eta * np.trace(tau)
        r = f * tau - lam * (grad_v @ tau + tau @ grad_v.T) - eta * (grad_v + grad_v.T)
        return np.array([r[0, 0], r[0, 1], r[1, 1]]) / modulus

    modulus = eta / lam  # G, Pa: the stresses in units of G
    guess = [2 * weissenberg**2 / (1 + weissenberg), weissenberg / (1 + weissenberg), 0.0]
    sol = root(residual, guess, method="hybr", options={"xtol": 1e-13})
    assert sol.success, sol.message
    sol.x *= modulus
    closed = ptt_steady_shear(rate, lam, eta, epsilon)
    assert sol.x[1] == pytest.approx(closed.shear_stress, rel=1e-10)
    assert sol.x[0] - sol.x[2] == pytest.approx(closed.first_normal_stress_difference, rel=1e-10)
    assert abs(sol.x[2]) < 1e-10 * abs(sol.x[0])


def test_multimode_shear_is_where_the_engines_rate_law_settles():
    """Table III's five modes at eps = 0.1 (and 0): the rate law of reference/sph_ptt.py integrated from rest under
    a constant shear rate until steady (60 lambda_max) ends on the closed form."""
    from scipy.integrate import solve_ivp

    low = ptt_multimode_steady_shear(1e-6, TABLE_III, 0.1)
    assert low.viscosity == pytest.approx(sum(m.viscosity for m in TABLE_III), rel=1e-9)
    psi1 = 2 * sum(m.viscosity * m.relaxation_time for m in TABLE_III)  # first normal stress coefficient, Pa s^2
    assert low.first_normal_stress_difference == pytest.approx(psi1 * 1e-12, rel=1e-9)
    for epsilon, gamma_dot in ((0.1, 2.0), (0.0, 0.7)):
        rate = homogeneous_shear_rates(TABLE_III, epsilon)
        sol = solve_ivp(rate, (0.0, 60 * 5.0), np.zeros(4 * len(TABLE_III)), method="Radau", rtol=1e-10,
                        atol=1e-8, args=(gamma_dot,))
        tau = sol.y[:, -1].reshape(len(TABLE_III), 2, 2)
        closed = ptt_multimode_steady_shear(gamma_dot, TABLE_III, epsilon)
        assert tau[:, 0, 1].sum() == pytest.approx(closed.shear_stress, rel=1e-8)
        assert (tau[:, 0, 0] - tau[:, 1, 1]).sum() == pytest.approx(closed.first_normal_stress_difference, rel=1e-8)
        assert closed.viscosity == pytest.approx(closed.shear_stress / gamma_dot, rel=1e-14)
        assert closed.f.shape == (len(TABLE_III),)


# ------------------------------------------------------------------------------------- oscillatory shear
def test_saos_settles_on_the_moduli():
    omega, gamma_a = 3.0, 0.01
    t = 300.0 + np.linspace(0, 2 * math.pi / omega, 50)  # 60 lambda_max after the start
    stress = maxwell_saos_stress(t, gamma_a, omega, TABLE_III)
    expected = gamma_a * (storage_modulus(omega, TABLE_III) * np.sin(omega * t)
                          + loss_modulus(omega, TABLE_III) * np.cos(omega * t))
    amplitude = gamma_a * math.hypot(storage_modulus(omega, TABLE_III), loss_modulus(omega, TABLE_III))
    np.testing.assert_allclose(stress, expected, rtol=0, atol=1e-12 * amplitude)
    assert maxwell_saos_stress(0.0, gamma_a, omega, TABLE_III) == 0.0


@pytest.mark.parametrize("epsilon, gamma_a, tolerance", [(0.0, 2.0, 1e-9), (0.1, 1e-4, 5e-9)])
def test_saos_startup_is_the_tensor_law_integrated(epsilon, gamma_a, tolerance):
    """The start-up transient against reference/sph_ptt.py's rate law integrated from rest: exact for UCM at any
    amplitude (gamma_A = 2), the small-amplitude limit for PTT (eps = 0.1, gamma_A = 1e-4)."""
    from scipy.integrate import solve_ivp

    modes, omega = (Mode(0.05, 10.0), Mode(1.0, 100.0), Mode(4.0, 30.0)), 2.0
    rate = homogeneous_shear_rates(modes, epsilon)
    times = np.linspace(0.0, 12.0, 97)
    sol = solve_ivp(lambda s, x: rate(s, x, gamma_a * omega * math.cos(omega * s)), (0.0, 12.0),
                    np.zeros(4 * len(modes)), method="DOP853", t_eval=times, rtol=1e-11, atol=1e-14)
    numerical = sol.y.reshape(len(modes), 2, 2, -1)[:, 0, 1].sum(axis=0)
    closed = maxwell_saos_stress(times, gamma_a, omega, modes)
    amplitude = gamma_a * math.hypot(storage_modulus(omega, modes), loss_modulus(omega, modes))
    np.testing.assert_allclose(closed, numerical, rtol=0, atol=tolerance * amplitude)
    # the transient matters: early on the stress is far from the settled sine
    settled = gamma_a * (storage_modulus(omega, modes) * np.sin(omega * times)
                         + loss_modulus(omega, modes) * np.cos(omega * times))
    assert np.max(np.abs(closed - settled)[times < 4.0]) > 0.1 * amplitude


@pytest.mark.parametrize("epsilon", [0.01, 0.1, 0.5])
def test_the_cubic_root_holds_over_seven_decades_of_wi(epsilon):
    """f from Cardano and two Newton steps solves f^3 - f^2 - 2 eps Wi^2 = 0 to round-off, Wi = 1e-3 .. 1e4."""
    wi = np.logspace(-3, 4, 71)
    f = ptt_f_in_shear(wi, epsilon)
    q = 2.0 * epsilon * wi**2
    assert np.all(f >= 1.0)
    assert np.abs(f**3 - f**2 - q).max() <= 1e-13 * np.maximum(f**3, 1.0).max()
    largest = np.array([max(np.roots([1.0, -1.0, 0.0, -x]).real) for x in q])
    assert np.allclose(f, largest, rtol=1e-12)


def test_startup_of_ucm_is_the_exponential():
    """eps = 0: tau_xy = eta gamma_dot (1 - e^{-t/lambda}), N1 its integral, no overshoot (peak at the end)."""
    t = np.linspace(0.0, 8.0, 801)
    run = ptt_startup_shear(t, 2.0, [Mode(1.0, 1000.0)], 0.0)
    assert np.allclose(run.shear_stress, 2000.0 * -np.expm1(-t), rtol=1e-8, atol=1e-6)
    n1 = 2 * 1000.0 * 2.0**2 * (1.0 - np.exp(-t) - t * np.exp(-t))  # 2 eta lambda gd^2 (1 - e^-s - s e^-s), s = t
    assert np.allclose(run.first_normal_stress_difference, n1, rtol=1e-7, atol=1e-5)
    assert run.peak_time == t[-1]


@pytest.mark.parametrize("epsilon,weissenberg", [(0.01, 5.0), (0.1, 20.0), (0.5, 100.0)])
def test_startup_overshoots_and_settles_on_the_closed_form(epsilon, weissenberg):
    lam, eta = 0.5, 400.0
    rate = weissenberg / lam
    exact = ptt_steady_shear(rate, lam, eta, epsilon)
    t = np.linspace(0.0, 40.0 * lam / float(exact.f), 4001)
    run = ptt_startup_shear(t, rate, [Mode(lam, eta)], epsilon)
    assert run.shear_stress[-1] == pytest.approx(float(exact.shear_stress), rel=1e-7)
    assert run.first_normal_stress_difference[-1] == pytest.approx(float(exact.first_normal_stress_difference),
                                                                   rel=1e-7)
    assert run.peak_shear_stress > 1.005 * float(exact.shear_stress)  # the overshoot
    assert 0.0 < run.peak_time < t[-1]


def test_startup_of_two_modes_is_the_sum_and_adds_the_solvent():
    t = np.linspace(0.0, 3.0, 301)
    modes = [Mode(1.0, 1000.0), Mode(0.1, 50.0)]
    both = ptt_startup_shear(t, 4.0, modes, 0.2, solvent_viscosity=3.0)
    parts = [ptt_startup_shear(t, 4.0, [m], 0.2) for m in modes]
    solvent = 3.0 * 4.0 * (t > 0)
    assert np.allclose(both.shear_stress, parts[0].shear_stress + parts[1].shear_stress + solvent, rtol=1e-8)


def test_startup_refuses_bad_parameters():
    with pytest.raises(OrchestratorError, match="epsilon"):
        ptt_startup_shear([0.0, 1.0], 1.0, [Mode(1.0, 1.0)], -0.1)
    with pytest.raises(OrchestratorError, match="relaxation_time"):
        ptt_startup_shear([0.0, 1.0], 1.0, [Mode(0.0, 1.0)], 0.1)
