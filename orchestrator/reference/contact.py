"""The contact law of Uhlmann et al. 2015 (eqs. 1-10) as small pure
functions: Hertz normal force, Mindlin no-slip tangential stiffness with an
incremental tangential force and a Coulomb limit, and Tsuji's non-linear
viscous damping. SI units throughout (m, kg, s, N, Pa).

Every function works on floats and on numpy arrays (one value per contact).

Where the paper is silent or loose we choose, and say so at the function:

- the total normal force is not allowed to pull (clipped at zero), as in
  Yade's ``Law2_ScGeom_MindlinPhys_Mindlin`` (the engine the paper used);
  ``no_tension=False`` gives the bare eqs. 8-9;
- "force transmitted in tangential direction ... is limited by the
  Mohr-Coulomb friction law": by default the whole tangential force
  (elastic plus viscous) is kept within mu F_n; Yade and LIGGGHTS 3.8
  limit only the elastic part and add the dash-pot on top while the
  contact sticks (``coulomb_limit="elastic"``). The two differ early in a
  sliding impact, when the dash-pot term c_t v_t is large (about +0.5 % of
  tangential impulse at 70 degrees incidence, mu = 0.092).

Rigid bodies (an immovable wall) have E = inf and R = inf for a flat face.
"""

from __future__ import annotations

import math

import numpy as np

#: Radius of gyration squared over radius squared of a solid sphere, I = k m R^2.
SOLID_SPHERE_GYRATION = 0.4


def shear_modulus(young_modulus, poisson_ratio):
    """G = E / (2 (1 + nu)), Pa (eq. 6)."""
    return young_modulus / (2.0 * (1.0 + poisson_ratio))


def effective_modulus(young_1, poisson_1, young_2, poisson_2):
    """E_eq, Pa, from 1/E_eq = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 (eq. 3).

    A rigid body has E = inf and drops out: a sphere on a rigid plane has
    E_eq = E1 / (1 - nu1^2).
    """
    compliance = (1.0 - np.square(poisson_1)) / young_1 + (1.0 - np.square(poisson_2)) / young_2
    return 1.0 / compliance


def effective_radius(radius_1, radius_2):
    """R_eq, m, from 1/R_eq = 1/R1 + 1/R2 (eq. 4).

    A plane or flat facet has R = inf, so a sphere on it has R_eq = R_sphere
    (Hertz's sphere on a flat).
    """
    return 1.0 / (1.0 / np.asarray(radius_1, dtype=float) + 1.0 / np.asarray(radius_2, dtype=float))


def effective_mass(mass_1, mass_2):
    """m_eq, kg, from 1/m_eq = 1/m1 + 1/m2 ("analogous to eq. 4"); an immovable
    wall (m = inf) gives m_eq = mass of the sphere, as in Yade."""
    return 1.0 / (1.0 / np.asarray(mass_1, dtype=float) + 1.0 / np.asarray(mass_2, dtype=float))


def hertz_stiffness(effective_young, effective_rad):
    """k_n = 4/3 E_eq sqrt(R_eq), N/m^(3/2) (eq. 2), so that F_n = k_n delta^(3/2)."""
    return 4.0 / 3.0 * effective_young * np.sqrt(effective_rad)


def mindlin_stiffness_coefficient(effective_rad, young_1, poisson_1, young_2, poisson_2):
    """k_t0, N/m^(3/2), such that k_t = k_t0 sqrt(delta_n) (eq. 5).

    k_t0 = 4 sqrt(R_eq) G_m / (2 - nu_m) with the arithmetic means G_m and
    nu_m of the two bodies (eq. 5, eq. 6; Yade's ``kso``).

    Eq. 5 as printed multiplies by delta_n, not sqrt(delta_n); that gives
    k_t in N/m^(1/2), which eq. 7 (F_t in N from k_t v_t dt) cannot use. Yade,
    which the paper ran, uses ks = kso sqrt(delta_n), which is Mindlin's
    8 G* a with a = sqrt(R_eq delta_n) for equal materials; we do the same.

    The arithmetic mean of a rigid body's G is infinite; for a rigid partner
    (E = inf) we take Mindlin's own limit 8 G* a with G* = G1 / (2 - nu1),
    i.e. k_t0 = 8 sqrt(R_eq) G1 / (2 - nu1). Yade cannot express this case.
    """
    young_1, poisson_1, young_2, poisson_2 = np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (young_1, poisson_1, young_2, poisson_2)))
    rigid_1, rigid_2 = np.isinf(young_1), np.isinf(young_2)
    if np.any(rigid_1 & rigid_2):
        raise ValueError("two rigid bodies (E = inf) cannot be in contact: give one a finite Young's modulus")
    g_1, g_2 = shear_modulus(young_1, poisson_1), shear_modulus(young_2, poisson_2)
    paper = 4.0 * ((g_1 + g_2) / 2.0) / (2.0 - (poisson_1 + poisson_2) / 2.0)
    mindlin_limit = np.where(rigid_2, 8.0 * g_1 / (2.0 - poisson_1), 8.0 * g_2 / (2.0 - poisson_2))
    return np.where(rigid_1 | rigid_2, mindlin_limit, paper) * np.sqrt(effective_rad)


def mindlin_tangential_stiffness(stiffness_coefficient, overlap):
    """k_t = k_t0 sqrt(delta_n), N/m (eq. 5 as Yade uses it; see mindlin_stiffness_coefficient).

    overlap: delta_n, m (values <= 0 give 0).
    """
    return stiffness_coefficient * np.sqrt(np.maximum(overlap, 0.0))


def damping_alpha(restitution):
    """alpha(e_n) = -sqrt(5) ln e_n / sqrt(ln^2 e_n + pi^2), dimensionless (eq. 10,
    Antypov & Elliott 2011).

    Exact for the damped Hertz spring when the viscous term may pull at the end
    of a contact; with the normal force clipped at zero (Yade, and our
    default) it gives a larger rebound than e_n: see
    closed_form.restitution_from_alpha and closed_form.alpha_from_restitution.
    """
    log_e = np.log(restitution)
    return -math.sqrt(5.0) * log_e / np.sqrt(log_e * log_e + math.pi**2)


def damping_coefficient(alpha, effective_m, normal_stiffness, overlap):
    """c_n = alpha sqrt(m_eq k_n) delta_n^(1/4), N s/m (eq. 9 read as Tsuji et al. 1992).

    alpha: dimensionless; effective_m: m_eq, kg; normal_stiffness: k_n,
    N/m^(3/2); overlap: delta_n, m. The tangential coefficient is the same,
    c_t = c_n (section 3.1).
    """
    return alpha * np.sqrt(effective_m * normal_stiffness) * np.sqrt(np.sqrt(np.maximum(overlap, 0.0)))


def normal_force(overlap, approach_rate, normal_stiffness, effective_m, alpha, no_tension=True):
    """Normal contact force magnitude F_n = k_n delta^(3/2) + c_n d(delta)/dt, N (eqs. 1, 8, 9).

    overlap: delta_n, m (<= 0 means no contact and gives 0); approach_rate:
    d(delta_n)/dt, m/s, positive while the bodies approach; normal_stiffness:
    k_n, N/m^(3/2); effective_m: m_eq, kg; alpha: damping constant, -.
    Positive F_n pushes the bodies apart. With no_tension (Yade's rule) the
    sum is clipped at zero, so the dash-pot never pulls; without it the
    viscous term may pull as the bodies separate (bare eqs. 8-9).
    """
    overlap = np.asarray(overlap, dtype=float)
    positive = np.maximum(overlap, 0.0)
    dash_pot = damping_coefficient(alpha, effective_m, normal_stiffness, positive)
    force = normal_stiffness * positive**1.5 + dash_pot * approach_rate
    force = np.where(overlap > 0.0, force, 0.0)
    return np.maximum(force, 0.0) if no_tension else force


def tangential_force_update(elastic_force, tangential_velocity, dt, tangential_stiffness,
                            damping_coeff, normal_force_magnitude, friction, coulomb_limit="total"):
    """One step of the incremental tangential force with a Coulomb limit (eq. 7).

    elastic_force: (n,3) elastic tangential force on body 1 from the previous
    step, N, already turned into the current tangent plane;
    tangential_velocity: (n,3) velocity of body 2 relative to body 1 at the
    contact point, tangential part, m/s; dt: s; tangential_stiffness: k_t,
    N/m; damping_coeff: c_t = c_n, N s/m; normal_force_magnitude: F_n, N
    (the bound is zero while F_n <= 0); friction: mu, - (inf: no slip while pressed).

    Returns (elastic_force, total_force, sliding): the new elastic force
    (stored for the next step), the tangential force on body 1, N, and a
    bool per contact.

    coulomb_limit="total": the contact slides when |elastic + c_t v_t|
    exceeds mu F_n; it then carries exactly mu F_n, all of it stored as
    elastic force (along the trial total), with no dash-pot.
    coulomb_limit="elastic" (Yade): only the elastic force is scaled back
    onto mu F_n; while it sticks, c_t v_t is added on top without limit.
    """
    if coulomb_limit not in ("total", "elastic"):
        raise ValueError(f"coulomb_limit must be 'total' or 'elastic', got {coulomb_limit!r}")
    tangential_velocity = np.asarray(tangential_velocity, dtype=float)
    elastic = elastic_force + (np.asarray(tangential_stiffness) * dt)[..., None] * tangential_velocity
    viscous = np.asarray(damping_coeff)[..., None] * tangential_velocity
    pressed = np.asarray(normal_force_magnitude) > 0.0
    with np.errstate(invalid="ignore"):  # mu = inf (no slip while pressed) times F_n = 0
        limit = np.where(pressed, np.asarray(friction) * np.where(pressed, normal_force_magnitude, 1.0), 0.0)
    checked = elastic + viscous if coulomb_limit == "total" else elastic
    magnitude = np.linalg.norm(checked, axis=-1)
    sliding = magnitude > limit
    scale = np.where(sliding, limit / np.where(magnitude > 0.0, magnitude, 1.0), 1.0)[..., None]
    elastic = np.where(sliding[..., None], checked * scale, elastic)
    total = np.where(sliding[..., None], elastic, elastic + viscous)
    return elastic, total, sliding


def bonded_layer_factor(chi, poisson_ratio):
    """F / F_Hertz (-) of a rigid sphere pressed into an elastic layer of thickness h bonded to a rigid base and
    unbounded sideways (Dimitriadis et al. 2002): 1 - 2 a0 chi / pi + 4 a0^2 chi^2 / pi^2 - 8 (a0^3 + 4 pi^2 b0 / 15)
    chi^3 / pi^3 - 16 a0 (a0^3 + 3 pi^2 b0 / 5) chi^4 / pi^4 with chi = sqrt(R delta) / h (the Hertz contact radius
    over the thickness, -, scalar or array; the series holds for chi up to about 1) and a0 = -(1.2876 - 1.4678 nu +
    1.3442 nu^2) / (1 - nu), b0 = (0.6387 - 1.0277 nu + 1.5164 nu^2) / (1 - nu). At nu = 1/2 it is their
    1 + 1.133 chi + 1.283 chi^2 + 0.769 chi^3 + 0.0975 chi^4."""
    nu = poisson_ratio
    a0 = -(1.2876 - 1.4678 * nu + 1.3442 * nu * nu) / (1.0 - nu)
    b0 = (0.6387 - 1.0277 * nu + 1.5164 * nu * nu) / (1.0 - nu)
    chi = np.asarray(chi, dtype=float)
    pi = math.pi
    return (1.0 - 2.0 * a0 / pi * chi + 4.0 * a0**2 / pi**2 * chi**2
            - 8.0 / pi**3 * (a0**3 + 4.0 * pi**2 / 15.0 * b0) * chi**3
            - 16.0 * a0 / pi**4 * (a0**3 + 3.0 * pi**2 / 5.0 * b0) * chi**4)
