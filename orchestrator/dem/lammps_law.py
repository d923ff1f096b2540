"""The paper's contact law (Uhlmann et al. 2015, eqs. 1-10) on LAMMPS's GRANULAR package (22 Jul 2025).

Every contact, sphere-sphere (``pair_style granular``, one ``pair_coeff i j`` per type pair, never mixed) and
sphere-wall (``fix wall/gran/region granular``, one fix per sphere type), runs

    hertz/material E_f e* nu_f  damping coeff_restitution  tangential mindlin/force k_t x_gammat mu  limit_damping

read in LAMMPS's gran_sub_mod_normal.cpp, gran_sub_mod_damping.cpp, gran_sub_mod_tangential.cpp and
granular_model.cpp, and checked on the installed build by tests/kinds/impact/test_lammps_impact.py:

- normal force 4/3 E* a delta with a = sqrt(R* delta): eq. 2's k_n0 delta^(3/2). ``hertz/material`` turns
  its E_f, nu_f into E* = E_f / (2 (1 - nu_f^2)) both for a pair given explicitly and for a wall (it takes
  the wall for a body of the sphere's own material), so the deck gets E_f = 2 (1 - nu_f^2) E* of the
  pair (hertz_material_young): for like spheres that is their own E and nu, for a sphere on the rigid
  wall twice the sphere's E. Against a wall R* = R (Hertz's sphere on a flat);
- ``damping coeff_restitution``: c_n = damp sqrt(m* F_n,el / delta) with damp = sqrt(3/2) 2 sqrt(5/6)
  beta, beta = -ln e* / sqrt(ln^2 e* + pi^2). That is Tsuji's c_n = alpha sqrt(m* k_n0) delta^(1/4) with
  alpha = sqrt(5) beta, the form of eq. 9, and for every alpha below sqrt(5) one e* gives it exactly
  (coefficient_of_restitution). It is the one damping option of pair granular whose e* reading is
  exact for Hertz (eq. 10, Antypov & Elliott, without the no-tension clip); ``tsuji`` reads e* through
  Marshall's polynomial fit, and ``viscoelastic`` and ``mass_velocity`` are not Tsuji's form. The deck
  gets the e* of the case's alpha (model.damping "exact" or "eq10"); model.damping "engine" passes e_n
  itself, which is LAMMPS's own reading: eq. 10, the same as "eq10";
- ``limit_damping``: the sum of spring and dash-pot is clipped at zero, so the normal force never pulls
  (Yade, LIGGGHTS with limitForce, the reference DEM); the "exact" alpha assumes that clip;
- ``tangential mindlin/force``: the tangential force is incremented, F_t += -k_t a v_t dt, and turned
  into each step's tangent plane, as eq. 7, Yade and the reference do (``mindlin`` would keep the
  displacement and multiply it by the current stiffness, as LIGGGHTS does). k_t is given, not derived
  from E_f: eq. 5's 4 G_m / (2 - nu_m) per pair (Mindlin's 8 G / (2 - nu) against the rigid wall),
  the reference's mindlin_stiffness_coefficient;
- tangential dash-pot x_gammat c_n: x_gammat = 1 is the paper's c_t = c_n (model.damping "engine" with
  its own e_t: beta(e_t) / beta(e_n));
- Coulomb: the total tangential force (spring plus dash-pot) is bounded by mu F_n with F_n the clipped
  total normal force: model.coulomb_limit = "total", the reference's default. A sliding contact keeps
  mu F_n minus the dash-pot as its spring force (the reference keeps all of mu F_n), so a contact that
  slides and sticks again starts from less: at 10 degrees (Chung & Ooi's test 4) the rebound spin is
  2.8 % lower than with the reference's rule, converged in the step;
- the relative tangential velocity uses the radii R as lever arms, and so does a wall contact's torque
  (a sphere pair's torque: R - delta / 2); the reference uses R - delta / 2 throughout: 0.4 % less spin
  at 10 degrees;
- no rolling or twisting resistance (as the paper).

coeff_restitution cannot reach alpha >= sqrt(5) (e* -> 0): the "exact" alpha of e_n below 0.14 on a
no-tension contact. Such a scene is refused (run it on yade or reference).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from orchestrator.dem.liggghts_law import beta_for_restitution, restitution_for_beta

#: LAMMPS's damp / beta for coeff_restitution with a Hertz normal model: sqrt(3/2) 2 sqrt(5/6) = sqrt(5), -.
ALPHA_PER_BETA = math.sqrt(5.0)
#: Largest Tsuji alpha given to coeff_restitution, -: beta = 0.999 (e* = 4e-31); beta = 1 would need e* = 0.
MAX_ALPHA = 0.999 * ALPHA_PER_BETA


def coefficient_of_restitution(alpha: float) -> float:
    """The e*, -, that makes ``damping coeff_restitution`` run Tsuji's alpha (c_n = alpha sqrt(m* k_n0)
    delta^(1/4)) with a Hertz normal model: beta = alpha / sqrt(5). ValueError beyond MAX_ALPHA."""
    if not 0.0 <= alpha <= MAX_ALPHA:
        raise ValueError(f"alpha = {alpha:.6g}: LAMMPS's coeff_restitution damping reaches 0 <= alpha <= "
                         f"{MAX_ALPHA:.6g}")
    return restitution_for_beta(alpha / ALPHA_PER_BETA)


def lammps_alpha(restitution: float) -> float:
    """Tsuji's alpha, -, that LAMMPS runs for ``coeff_restitution`` e* = restitution: sqrt(5) beta(e*)."""
    return ALPHA_PER_BETA * beta_for_restitution(restitution)


def hertz_material_young(effective_young: float, poisson: float) -> float:
    """E, Pa, to give ``hertz/material`` with Poisson's ratio poisson (-) so that it runs E* = effective_young
    (Pa): 2 (1 - nu^2) E*, for a type pair set explicitly and for a wall alike."""
    return 2.0 * (1.0 - poisson * poisson) * effective_young


def tangential_damping_scale(alpha_normal: float, alpha_tangential: float) -> float:
    """x_gammat, -: c_t / c_n, 1 when the normal direction has no damping to scale."""
    return alpha_tangential / alpha_normal if alpha_normal > 0.0 else 1.0


@dataclass(frozen=True)
class GranularLaw:
    """One contact's coefficients in the deck's order (SI): hertz/material E (Pa), e* (-), nu (-);
    mindlin/force k_t (Pa: k_t a is the tangential stiffness, N/m), x_gammat (-), mu (-)."""

    young: float
    restitution: float
    poisson: float
    shear_stiffness: float
    tangential_damping: float
    friction: float

    def words(self) -> str:
        """The coefficients of pair_coeff and fix wall/gran/region, numbers as repr."""
        return (f"hertz/material {self.young!r} {self.restitution!r} {self.poisson!r} damping coeff_restitution "
                f"tangential mindlin/force {self.shear_stiffness!r} {self.tangential_damping!r} {self.friction!r} "
                "limit_damping")


def granular_law(effective_young: float, poisson: float, shear_coefficient: float, friction: float,
                 alpha: float | None, restitution: float, tangential_restitution: float) -> GranularLaw:
    """The law of one contact pair: E* (Pa) and a Poisson's ratio (-) for hertz/material, eq. 5's k_t0 /
    sqrt(R*) (Pa), mu (-), and the damping: Tsuji's alpha (-), or None for the engine's own reading of
    e_n and e_t (-)."""
    if alpha is None:
        e_star = restitution
        scale = tangential_damping_scale(lammps_alpha(restitution), lammps_alpha(tangential_restitution))
    else:
        e_star, scale = coefficient_of_restitution(alpha), 1.0
    return GranularLaw(hertz_material_young(effective_young, poisson), e_star, poisson, shear_coefficient, scale,
                       friction)
