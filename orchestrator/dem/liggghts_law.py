"""The paper's contact law (Uhlmann et al. 2015, eqs. 1-10) on LIGGGHTS-PUBLIC 3.8.

What 3.8.0 runs with ``model hertz tangential history`` (pair_style gran and
fix wall/gran alike; read in its normal_model_hertz.h,
tangential_model_history.h and global_properties.cpp, and checked on the
installed build by tests/engines/test_liggghts_physics.py):

- normal force k_n delta with k_n = 4/3 Y* sqrt(R* delta), i.e. eq. 2's
  k_n0 delta^(3/2) with Y* = E_eq (eq. 3); against a wall R* = R, Hertz's
  sphere on a flat (no ``hertzian`` switch as in Yade);
- normal dash-pot gamma_n = 2 sqrt(5/6) beta sqrt(m* S_n), S_n = 2 Y* sqrt(R*
  delta), with beta = -ln e / sqrt(ln^2 e + pi^2) from the pair's
  ``coefficientRestitution`` e. That is Tsuji's c_n = alpha sqrt(m* k_n0)
  delta^(1/4) with alpha = sqrt(5) beta: LIGGGHTS's own reading of e is the
  paper's eq. 10 exactly. To run another alpha (model.damping = "exact")
  the deck gets the e* whose beta is alpha / sqrt(5);
- ``limitForce on``: the sum of spring and dash-pot is clipped at zero, so
  the normal force never pulls at the end of a contact. We choose it
  because the paper's engine (Yade) clips, the reference DEM clips, and
  model.damping = "exact" computes the alpha that rebounds at e_n *with* the
  clip (closed_form.alpha_from_restitution(e, no_tension=True)); without it
  LIGGGHTS would rebound lower than e_n (0.656 instead of 0.68 for the
  sphere drop's alpha) and the three engines would run three laws;
- tangential stiffness k_t = 8 G* sqrt(R* delta), 1/G* = (2 - nu_1)/G_1 +
  (2 - nu_2)/G_2 (Mindlin): eq. 5's 4 G_m / (2 - nu_m) for like materials and
  for a rigid wall, 24 % below eq. 5 for ceramic on steel (Yade's impact
  template sets eq. 5's value per contact; LIGGGHTS has no per-pair k_t);
- tangential dash-pot gamma_t = 2 sqrt(5/6) beta sqrt(m* k_t): c_t = c_n
  sqrt(k_t / S_n), e.g. 0.933 c_n for alumina on a rigid wall, where the
  paper has c_t = c_n (one beta per pair damps both directions);
- ``tangential history`` keeps the total tangential displacement s (grown by
  v_t dt, projected into the current tangent plane each step) and applies
  F_t = -k_t(delta) s with the *current* k_t. The paper (eq. 7) and Yade
  increment the force instead, F_t += -k_t v_t dt, so when the overlap
  changes while a contact sticks, LIGGGHTS's force follows the stiffness
  (it falls back as delta shrinks) where Yade's keeps what it built up;
- Coulomb: only the elastic part k_t |s| is compared with mu F_n; a sliding
  contact carries mu F_n (s is cut back to match) and no dash-pot, a
  sticking one gets the dash-pot on top: the "elastic" rule, as Yade's
  (model.coulomb_limit = "total" is noted as a deviation, as on Yade).

3.8.0 refuses coefficientRestitution <= 0.05, so beta <= 0.690 (alpha <=
1.54). A wall contact that needs more (e_n = 0.2 with model.damping =
"exact": alpha = 1.635) runs against N coincident copies of the wall, each of
a fictitious material that gives Y*/N and G*/N, each with beta/sqrt(N): the
copies carry equal shares of every force, so the sum is the law with beta,
and the no-tension clip and the Coulomb limit act on each share exactly as
on the whole. Sphere-sphere contacts have no such way out and are refused.

Drag finishing (no model.damping in its case): Yade's drag template gives
Yade its en/es, which Yade 2023 maps by Thornton et al.'s fit; the deck gets
the same alpha (yade_law.yade_native_alpha), so both engines run the same damping.
Yade's Cundall damping while the bed settles has no LIGGGHTS-PUBLIC command;
the deck applies the same force, -damping |F| sign(v) per component, with
fix addforce on per-atom variables (forces only: Yade also damps torques).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from orchestrator.dem import RIGID_POISSON, RIGID_STIFFNESS_FACTOR

#: LIGGGHTS 3.8 refuses coefficientRestitution <= 0.05; we stay above this value.
MIN_COEFFICIENT_RESTITUTION = 0.06


def liggghts_beta(alpha: float) -> float:
    """LIGGGHTS's damping ratio beta, -, for Tsuji's alpha (c_n = alpha sqrt(m k_n0) delta^(1/4)): alpha / sqrt(5)."""
    return alpha / math.sqrt(5.0)


def restitution_for_beta(beta: float) -> float:
    """The coefficientRestitution e, -, from which LIGGGHTS computes beta = -ln e / sqrt(ln^2 e + pi^2)."""
    if beta <= 0.0:
        return 1.0
    if beta >= 1.0:
        raise ValueError(f"beta = {beta} >= 1 has no coefficient of restitution")
    return math.exp(-math.pi * beta / math.sqrt(1.0 - beta * beta))


def beta_for_restitution(restitution: float) -> float:
    """LIGGGHTS's beta, -, for coefficientRestitution e (the inverse of restitution_for_beta)."""
    if restitution >= 1.0:
        return 0.0
    log_e = math.log(restitution)
    return -log_e / math.sqrt(log_e * log_e + math.pi**2)


#: Largest beta LIGGGHTS 3.8 accepts (with our margin on its 0.05 floor), -.
MAX_BETA = beta_for_restitution(MIN_COEFFICIENT_RESTITUTION)


def wall_copies(beta: float) -> int:
    """Coincident wall copies needed so that each copy's beta / sqrt(N) stays within MAX_BETA."""
    return max(1, math.ceil((beta / MAX_BETA) ** 2 - 1e-12))


def tangential_damping_ratio(young_1, poisson_1, young_2, poisson_2) -> float:
    """c_t / c_n on LIGGGHTS, -: sqrt(8 G* / (2 Y*)) (the paper has 1); a rigid partner has E = inf."""
    def compliance(e, nu, factor):
        return 0.0 if math.isinf(e) else factor(nu) / e

    y = 1.0 / (compliance(young_1, poisson_1, lambda nu: 1 - nu * nu)
               + compliance(young_2, poisson_2, lambda nu: 1 - nu * nu))
    g = 1.0 / (compliance(young_1, poisson_1, lambda nu: 2 * (2 - nu) * (1 + nu))
               + compliance(young_2, poisson_2, lambda nu: 2 * (2 - nu) * (1 + nu)))
    return math.sqrt(8.0 * g / (2.0 * y))


@dataclass(frozen=True)
class WallMaterial:
    """The material a wall's mesh type gets in the deck: E (Pa), nu (-), and how many copies of the wall."""

    young: float
    poisson: float
    copies: int = 1


def wall_material(sphere_young: float, sphere_poisson: float, wall_young: float, wall_poisson: float,
                  copies: int = 1, rigid_young: float | None = None) -> WallMaterial:
    """The wall material that makes N coincident copies of a wall act as one wall of (wall_young,
    wall_poisson) against a sphere of (sphere_young, sphere_poisson): each copy gives Y*/N and G*/N.

    wall_young = inf is a rigid wall; with one copy it gets rigid_young (default
    RIGID_STIFFNESS_FACTOR x sphere_young), Pa.
    """
    rigid = math.isinf(wall_young)
    if copies == 1:
        if rigid:
            return WallMaterial(rigid_young or RIGID_STIFFNESS_FACTOR * sphere_young, RIGID_POISSON, 1)
        return WallMaterial(wall_young, wall_poisson, 1)
    a_sphere = (1 - sphere_poisson**2) / sphere_young
    b_sphere = 2 * (2 - sphere_poisson) * (1 + sphere_poisson) / sphere_young
    a_wall = 0.0 if rigid else (1 - wall_poisson**2) / wall_young
    b_wall = 0.0 if rigid else 2 * (2 - wall_poisson) * (1 + wall_poisson) / wall_young
    a = (copies - 1) * a_sphere + copies * a_wall
    b = (copies - 1) * b_sphere + copies * b_wall
    ratio = b / (2 * a)  # (2 - nu) / (1 - nu) of the copy material, in [2, 3] for nu in [0, 0.5]
    poisson = (ratio - 2) / (ratio - 1)
    return WallMaterial((1 - poisson**2) / a, poisson, copies)
