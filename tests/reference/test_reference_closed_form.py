"""Closed forms of single impacts (orchestrator.reference.closed_form and .oblique)."""

from __future__ import annotations

import math

import pytest
from scipy.special import gamma

from orchestrator.reference import closed_form, contact, oblique
from expected import EQ10_REBOUND_WITHOUT_TENSION



def test_hertz_duration_constant_is_the_beta_function_integral():
    # 2 int_0^1 dx / sqrt(1 - x^(5/2)) = (4/5) B(2/5, 1/2)
    beta = gamma(0.4) * gamma(0.5) / gamma(0.9)
    assert closed_form.HERTZ_DURATION_FACTOR == pytest.approx(0.8 * beta, rel=1e-14)
    assert closed_form.HERTZ_DURATION_FACTOR == pytest.approx(2.943275, rel=1e-6)
    # the textbook 2.87 (m^2 / (R E^2 v))^(1/5) is this times (15/16)^(2/5)
    assert closed_form.HERTZ_DURATION_FACTOR * (15 / 16) ** 0.4 == pytest.approx(2.86827, rel=1e-5)


def test_hertz_closed_form_for_chung_and_ooi_test_2():
    # Al alloy sphere R = 0.1 m at 0.2 m/s on a rigid plane (E = 70 GPa, nu = 0.3, rho = 2699)
    mass = 2699 * 4 / 3 * math.pi * 0.1**3
    e_eq = contact.effective_modulus(70e9, 0.3, math.inf, 0.3)
    overlap = closed_form.hertz_max_overlap(mass, 0.1, e_eq, 0.2)
    force = closed_form.hertz_max_force(mass, 0.1, e_eq, 0.2)
    duration = closed_form.hertz_contact_duration(mass, 0.1, e_eq, 0.2)
    # energy balance: 1/2 m v^2 = 2/5 k_n delta_max^(5/2)
    k_n = contact.hertz_stiffness(e_eq, 0.1)
    assert 0.5 * mass * 0.2**2 == pytest.approx(0.4 * k_n * overlap**2.5, rel=1e-12)
    assert force == pytest.approx(k_n * overlap**1.5, rel=1e-12)
    assert duration == pytest.approx(2.86827 * (mass**2 / (0.1 * e_eq**2 * 0.2)) ** 0.2, rel=1e-5)
    assert duration == pytest.approx(closed_form.HERTZ_DURATION_FACTOR * overlap / 0.2, rel=1e-14)


def test_undamped_integration_reproduces_the_closed_form():
    impact = closed_form.damped_hertz_impact(0.0)
    assert impact.restitution == pytest.approx(1.0, abs=1e-9)
    assert impact.peak_force_ratio == pytest.approx(1.0, abs=1e-9)
    assert impact.peak_overlap_ratio == pytest.approx(1.0, abs=1e-9)
    assert impact.duration_ratio == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize("restitution", [0.2, 0.5, 0.68, 0.86, 0.95])
def test_eq10_is_exact_when_the_dash_pot_may_pull_and_overshoots_when_it_may_not(restitution):
    alpha_eq10 = contact.damping_alpha(restitution)
    # Antypov & Elliott's relation holds to integration accuracy for the bare eqs. 8-9 ...
    assert closed_form.restitution_from_alpha(alpha_eq10, no_tension=False) == pytest.approx(restitution, rel=1e-8)
    assert closed_form.alpha_from_restitution(restitution, no_tension=False) == pytest.approx(alpha_eq10, rel=1e-8)
    # ... but with the normal force clipped at zero the rebound is larger
    rebound = closed_form.restitution_from_alpha(alpha_eq10)
    assert rebound == pytest.approx(EQ10_REBOUND_WITHOUT_TENSION[restitution], rel=2e-6)
    exact_alpha = closed_form.alpha_from_restitution(restitution)
    assert exact_alpha > alpha_eq10
    assert closed_form.restitution_from_alpha(exact_alpha) == pytest.approx(restitution, rel=1e-9)


def test_damped_peak_force_is_below_the_undamped_one():
    alpha = closed_form.alpha_from_restitution(0.68)
    impact = closed_form.damped_hertz_impact(alpha)
    assert impact.peak_force_ratio == pytest.approx(0.81726, rel=1e-4)  # integrated here; the DEM checks it
    assert impact.duration_ratio > 1.0
    mass, radius, e_eq = 3.9e-4, 3.27e-3, 59.35e9
    assert closed_form.damped_hertz_peak_force(mass, radius, e_eq, 0.44, alpha) == pytest.approx(
        impact.peak_force_ratio * closed_form.hertz_max_force(mass, radius, e_eq, 0.44), rel=1e-12)


def test_bounce_sequence_is_ballistic():
    speeds, times = closed_form.bounce_sequence(0.01, 0.68, 9.81, 3)
    assert speeds == pytest.approx([math.sqrt(2 * 9.81 * 0.01), 0.68 * 0.442945, 0.68**2 * 0.442945], rel=1e-5)
    assert times[1] - times[0] == pytest.approx(2 * speeds[1] / 9.81, rel=1e-12)


def test_walton_rigid_body_theory_in_both_regimes():
    mu, e_n, radius, v_n = 0.1, 0.8, 0.01, 1.0
    threshold = oblique.sliding_incidence_threshold(mu, e_n)
    assert threshold == pytest.approx(3.5 * 0.1 * 1.8)
    sliding = oblique.oblique_impact_rebound(v_n, 2.0 * threshold, radius, mu, e_n)
    assert sliding.sliding
    assert sliding.tangential_velocity == pytest.approx(2.0 * threshold - mu * (1 + e_n))
    assert sliding.spin * radius == pytest.approx(2.5 * mu * (1 + e_n))
    sticking = oblique.oblique_impact_rebound(v_n, 0.5 * threshold, radius, mu, e_n)
    assert not sticking.sliding
    assert sticking.contact_point_velocity == pytest.approx(0.0, abs=1e-15)  # beta_0 = 0: leaves rolling
    assert sticking.tangential_velocity == pytest.approx(5 / 7 * 0.5 * threshold)
    reversed_point = oblique.oblique_impact_rebound(v_n, 0.1, radius, mu, e_n, tangential_restitution=0.4)
    assert reversed_point.contact_point_velocity == pytest.approx(-0.04)


def test_mindlin_oblique_impact_slides_like_rigid_body_theory_at_grazing_incidence():
    nu, e_n, mu = 0.23, 0.86, 0.092
    alpha = closed_form.alpha_from_restitution(e_n)
    ratio = 3 * (1 - nu) / (2 - nu)
    tangent = 3.0  # > 3.5 mu (1 + e_n) = 0.599
    impact = oblique.oblique_impact_mindlin(tangent, mu, ratio, alpha)
    walton = oblique.oblique_impact_rebound(1.0, tangent, 1.0, mu, e_n)
    assert impact.restitution == pytest.approx(e_n, rel=1e-9)
    assert impact.tangential_velocity == pytest.approx(walton.tangential_velocity, rel=1e-9)
    assert impact.spin == pytest.approx(walton.spin, rel=1e-8)


def test_no_slip_tangential_restitution_of_the_law():
    ratio = 3 * (1 - 0.23) / (2 - 0.23)
    # undamped, the Mindlin spring with k_t ~ sqrt(delta) gives back slightly more than it took
    assert oblique.no_slip_tangential_restitution(ratio, 0.0) == pytest.approx(-1.01351, abs=1e-4)
    beta_0 = oblique.no_slip_tangential_restitution(ratio, closed_form.alpha_from_restitution(0.86))
    # linear in the slip: the same beta_0 at any incidence without slip
    alpha = closed_form.alpha_from_restitution(0.86)
    for tangent in (0.1, 1.0):
        impact = oblique.oblique_impact_mindlin(tangent, math.inf, ratio, alpha)
        assert impact.contact_point_velocity == pytest.approx(-beta_0 * tangent, rel=1e-8)
    assert -1.0 < beta_0 < 0.0
