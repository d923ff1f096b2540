"""The paper's law on LIGGGHTS (orchestrator/dem/liggghts_law.py), checked against LIGGGHTS-PUBLIC
3.8's own formulas (normal_model_hertz.h, global_properties.cpp) written out here; no engine needed."""

import math

import numpy as np
import pytest

from orchestrator.dem.liggghts_law import (MAX_BETA, MIN_COEFFICIENT_RESTITUTION, beta_for_restitution,
                                              liggghts_beta, restitution_for_beta, tangential_damping_ratio,
                                              wall_copies, wall_material)
from orchestrator.reference import closed_form, contact

SQRT_FIVE_SIXTHS = math.sqrt(5.0 / 6.0)


def liggghts_y_eff(e1, nu1, e2, nu2):
    """createYeff: 1 / ((1 - nu_i^2)/E_i + (1 - nu_j^2)/E_j)."""
    return 1.0 / ((1 - nu1**2) / e1 + (1 - nu2**2) / e2)


def liggghts_g_eff(e1, nu1, e2, nu2):
    """createGeff: 1 / (2 (2 - nu_i)(1 + nu_i)/E_i + 2 (2 - nu_j)(1 + nu_j)/E_j)."""
    return 1.0 / (2 * (2 - nu1) * (1 + nu1) / e1 + 2 * (2 - nu2) * (1 + nu2) / e2)


def liggghts_normal_dashpot(restitution, y_eff, radius, overlap, mass):
    """gamma_n of model hertz: 2 sqrt(5/6) beta sqrt(S_n m), S_n = 2 Y* sqrt(R delta), beta from e."""
    log_e = math.log(restitution)
    beta = -log_e / math.sqrt(log_e**2 + math.pi**2)
    return 2.0 * SQRT_FIVE_SIXTHS * beta * math.sqrt(2.0 * y_eff * math.sqrt(radius * overlap) * mass)


@pytest.mark.parametrize("restitution", [0.4, 0.68, 0.86, 0.98])
def test_restitution_given_to_liggghts_makes_its_dashpot_the_papers(restitution):
    """LIGGGHTS's gamma_n with e* equals Tsuji's c_n = alpha sqrt(m k_n0) delta^(1/4) of the case's alpha
    (e_n = 0.2 needs wall copies: test_copies_of_a_wall_sum_to_the_wall)."""
    alpha = closed_form.alpha_from_restitution(restitution, True)
    beta = liggghts_beta(alpha)
    assert beta <= MAX_BETA
    e_star = restitution_for_beta(beta)
    y_eff, radius, overlap, mass = 6.1e10, 3.27e-3, 2.0e-6, 3.9e-4
    paper = contact.damping_coefficient(alpha, mass, contact.hertz_stiffness(y_eff, radius), overlap)
    assert liggghts_normal_dashpot(e_star, y_eff, radius, overlap, mass) == pytest.approx(float(paper), rel=1e-12)


def test_eq10_is_liggghts_own_reading_of_restitution():
    """With alpha from eq. 10 (Antypov & Elliott) the e* LIGGGHTS gets is the case's e_n itself."""
    for restitution in (0.3, 0.68, 0.86, 0.95):
        alpha = float(contact.damping_alpha(restitution))
        assert restitution_for_beta(liggghts_beta(alpha)) == pytest.approx(restitution, rel=1e-12)


def test_beta_and_restitution_are_inverse_and_bounded():
    for beta in (0.0, 0.01, 0.2, 0.5, 0.66):
        assert beta_for_restitution(restitution_for_beta(beta)) == pytest.approx(beta, abs=1e-14)
    assert restitution_for_beta(MAX_BETA) == pytest.approx(MIN_COEFFICIENT_RESTITUTION, rel=1e-12)
    assert MIN_COEFFICIENT_RESTITUTION > 0.05  # LIGGGHTS 3.8's floor: 0.05 < coefficientRestitution
    with pytest.raises(ValueError):
        restitution_for_beta(1.0)


def test_copies_of_a_wall_sum_to_the_wall():
    """e_n = 0.2 'exact' on alumina against a rigid wall needs beta = 0.731 > 0.667: two copies, each with
    Y*/2, G*/2 and beta/sqrt(2), whose forces add up to the single wall's (stiffness and dash-pot)."""
    e_sphere, nu_sphere = 380e9, 0.23
    beta = liggghts_beta(closed_form.alpha_from_restitution(0.2, True))
    copies = wall_copies(beta)
    assert beta == pytest.approx(0.7312, abs=1e-4) and copies == 2
    material = wall_material(e_sphere, nu_sphere, math.inf, 0.0, copies)
    y_target = e_sphere / (1 - nu_sphere**2)
    g_target = e_sphere / (2 * (1 + nu_sphere)) / (2 - nu_sphere)  # Mindlin's limit for a rigid partner
    y_copy = liggghts_y_eff(e_sphere, nu_sphere, material.young, material.poisson)
    g_copy = liggghts_g_eff(e_sphere, nu_sphere, material.young, material.poisson)
    assert copies * y_copy == pytest.approx(y_target, rel=1e-12)
    assert copies * g_copy == pytest.approx(g_target, rel=1e-12)
    radius, overlap, mass = 2.5e-3, 3e-6, 2.6e-4
    per_copy = liggghts_normal_dashpot(restitution_for_beta(beta / math.sqrt(copies)), y_copy, radius, overlap, mass)
    whole = 2.0 * SQRT_FIVE_SIXTHS * beta * math.sqrt(2.0 * y_target * math.sqrt(radius * overlap) * mass)
    assert copies * per_copy == pytest.approx(whole, rel=1e-12)
    # a real plate: the copies reproduce the plate's Y* and G*
    plate = wall_material(77e9, 0.19, 210e9, 0.30, 3)
    assert 3 * liggghts_y_eff(77e9, 0.19, plate.young, plate.poisson) == pytest.approx(
        liggghts_y_eff(77e9, 0.19, 210e9, 0.30), rel=1e-12)
    assert 3 * liggghts_g_eff(77e9, 0.19, plate.young, plate.poisson) == pytest.approx(
        liggghts_g_eff(77e9, 0.19, 210e9, 0.30), rel=1e-12)
    assert 0.0 <= plate.poisson <= 0.5


def test_one_copy_is_the_wall_itself_and_a_rigid_wall_is_very_stiff():
    assert wall_material(77e9, 0.19, 210e9, 0.3).young == 210e9
    rigid = wall_material(380e9, 0.23, math.inf, 0.0)
    y = liggghts_y_eff(380e9, 0.23, rigid.young, rigid.poisson)
    assert y == pytest.approx(380e9 / (1 - 0.23**2), rel=2e-6)
    assert [wall_copies(b) for b in (0.1, MAX_BETA, 1.2 * MAX_BETA, 2.1 * MAX_BETA)] == [1, 1, 2, 5]


def test_tangential_damping_differs_from_the_papers():
    """c_t / c_n = sqrt(k_t / S_n): 0.933 for alumina on a rigid wall (the paper: 1)."""
    assert tangential_damping_ratio(380e9, 0.23, math.inf, 0.0) == pytest.approx(0.9328, abs=1e-4)
    nu = np.linspace(0.0, 0.5, 6)
    like = [tangential_damping_ratio(1e9, v, 1e9, v) for v in nu]
    assert np.allclose(like, np.sqrt(2 * (1 - nu) / (2 - nu)))
