"""The contact law of Uhlmann et al. 2015 as pure functions (orchestrator.reference.contact)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orchestrator.reference import contact

CERAMIC = dict(young=77e9, poisson=0.19)
STEEL = dict(young=210e9, poisson=0.30)


def test_effective_modulus_of_the_paper_ceramic_on_steel():
    e_eq = contact.effective_modulus(CERAMIC["young"], CERAMIC["poisson"], STEEL["young"], STEEL["poisson"])
    expected = 1.0 / ((1 - 0.19**2) / 77e9 + (1 - 0.3**2) / 210e9)
    assert e_eq == pytest.approx(expected, rel=1e-14)
    assert e_eq == pytest.approx(59.35e9, rel=1e-3)


def test_rigid_wall_drops_out_of_the_effective_modulus_and_a_flat_out_of_the_radius():
    assert contact.effective_modulus(70e9, 0.3, math.inf, 0.3) == pytest.approx(70e9 / (1 - 0.09), rel=1e-14)
    assert contact.effective_radius(0.1, math.inf) == pytest.approx(0.1, rel=1e-15)
    assert contact.effective_radius(0.01, 0.01) == pytest.approx(0.005, rel=1e-15)
    assert contact.effective_mass(2.0, math.inf) == pytest.approx(2.0, rel=1e-15)


def test_mindlin_coefficient_is_mindlins_8_g_star_a_for_equal_materials():
    # k_t = 4 sqrt(R) G/(2-nu) sqrt(delta) = 8 G* a with G* = G / (2 (2 - nu)), a = sqrt(R delta)
    radius, delta, young, poisson = 3.27e-3, 2e-6, 77e9, 0.19
    coefficient = contact.mindlin_stiffness_coefficient(radius, young, poisson, young, poisson)
    g_star = contact.shear_modulus(young, poisson) / (2 * (2 - poisson))
    assert contact.mindlin_tangential_stiffness(coefficient, delta) == pytest.approx(
        8 * g_star * math.sqrt(radius * delta), rel=1e-14)
    # on a wall of its own material, k_t0 / k_n = 3 (1 - nu) / (2 - nu)
    k_n = contact.hertz_stiffness(contact.effective_modulus(young, poisson, young, poisson), radius)
    assert coefficient / k_n == pytest.approx(3 * (1 - poisson) / (2 - poisson), rel=1e-14)


def test_mindlin_coefficient_uses_the_mean_moduli_and_mindlins_limit_on_a_rigid_wall():
    mixed = contact.mindlin_stiffness_coefficient(1.0, 77e9, 0.19, 210e9, 0.3)
    g_mean = (contact.shear_modulus(77e9, 0.19) + contact.shear_modulus(210e9, 0.3)) / 2
    assert mixed == pytest.approx(4 * g_mean / (2 - 0.245), rel=1e-14)
    rigid = contact.mindlin_stiffness_coefficient(1.0, 70e9, 0.3, math.inf, 0.3)
    assert rigid == pytest.approx(8 * contact.shear_modulus(70e9, 0.3) / 1.7, rel=1e-14)
    with pytest.raises(ValueError, match="two rigid bodies"):
        contact.mindlin_stiffness_coefficient(1.0, math.inf, 0.3, math.inf, 0.3)


def test_damping_alpha_is_eq_10():
    assert contact.damping_alpha(1.0) == 0.0
    log_e = math.log(0.68)
    assert contact.damping_alpha(0.68) == pytest.approx(-math.sqrt(5) * log_e / math.sqrt(log_e**2 + math.pi**2))
    assert contact.damping_alpha(0.68) == pytest.approx(0.272455, rel=1e-5)


def test_normal_force_is_hertz_plus_tsuji_and_never_pulls_by_default():
    k_n, m_eq, alpha, delta = 4.5e9, 3.9e-4, 0.3, 2e-6
    c_n = alpha * math.sqrt(m_eq * k_n) * delta**0.25
    assert contact.damping_coefficient(alpha, m_eq, k_n, delta) == pytest.approx(c_n, rel=1e-14)
    approaching = contact.normal_force(delta, 0.4, k_n, m_eq, alpha)
    assert approaching == pytest.approx(k_n * delta**1.5 + c_n * 0.4, rel=1e-14)
    fast_separation = -10.0
    assert contact.normal_force(delta, fast_separation, k_n, m_eq, alpha) == 0.0
    assert contact.normal_force(delta, fast_separation, k_n, m_eq, alpha, no_tension=False) < 0.0
    assert contact.normal_force(-1e-9, 1.0, k_n, m_eq, alpha) == 0.0


@pytest.mark.parametrize("limit", ["total", "elastic"])
def test_tangential_force_sticks_below_and_slides_on_the_coulomb_limit(limit):
    velocity = np.array([[0.01, 0.0, 0.0], [1.0, 0.0, 0.0]])
    elastic, total, sliding = contact.tangential_force_update(
        np.zeros((2, 3)), velocity, 1e-6, np.array([1e6, 1e6]), np.array([10.0, 10.0]),
        np.array([1.0, 1.0]), np.array([0.5, 0.5]), coulomb_limit=limit)
    # first contact: increment k_t v dt = 0.01 N, plus dash-pot 0.1 N: sticks under mu F_n = 0.5 N
    assert not sliding[0]
    assert elastic[0] == pytest.approx([0.01, 0, 0])
    assert total[0] == pytest.approx([0.11, 0, 0])
    # second: 1 N elastic (+10 N viscous) exceeds 0.5 N: slides with |F_t| = mu F_n, no dash-pot
    assert sliding[1]
    assert total[1] == pytest.approx([0.5, 0, 0])
    assert elastic[1] == pytest.approx([0.5, 0, 0])


def test_total_limit_also_bounds_the_dash_pot_where_yades_elastic_limit_does_not():
    args = (np.zeros((1, 3)), np.array([[1.0, 0, 0]]), 1e-9, np.array([1e6]), np.array([10.0]),
            np.array([1.0]), np.array([0.5]))
    _, total, sliding = contact.tangential_force_update(*args, coulomb_limit="total")
    assert sliding[0] and np.linalg.norm(total[0]) == pytest.approx(0.5)
    _, total, sliding = contact.tangential_force_update(*args, coulomb_limit="elastic")
    assert not sliding[0] and np.linalg.norm(total[0]) == pytest.approx(10.001)


def test_no_tangential_force_without_normal_force_even_without_slip_limit():
    elastic, total, sliding = contact.tangential_force_update(
        np.array([[0.2, 0, 0]]), np.array([[0.1, 0, 0]]), 1e-6, np.array([1e6]), np.array([1.0]),
        np.array([0.0]), np.array([math.inf]))
    assert sliding[0]
    assert np.all(elastic == 0) and np.all(total == 0)
