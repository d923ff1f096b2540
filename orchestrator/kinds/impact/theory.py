"""Closed forms an impact case can name in its [[expected]] table.

Each closed form computes one measured quantity (QUANTITIES, below)
from the case itself, with the functions of orchestrator.reference
(closed_form, oblique, contact). They apply to the canonical scenes:
one sphere against the plane, or two spheres colliding (normal impacts
only for the latter). SI units.

The "damped" forms use the case's damping constant alpha (model.damping =
"exact" or "eq10"; see orchestrator.kinds.impact.physics.damping_alpha_for).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from orchestrator.kinds.impact.physics import (
    STANDARD_GRAVITY,
    damping_alpha_for,
    effective_young,
    poisson_ratio,
    sphere_mass,
    young_modulus,
)
from orchestrator.reference import closed_form, contact, oblique


@dataclass(frozen=True)
class ClosedForm:
    """A named closed form: the quantity it predicts, whether it needs alpha, the function (case -> value)."""

    quantity: str
    needs_alpha: bool
    function: Callable
    description: str
    needs_total_limit: bool = False


@dataclass(frozen=True)
class FirstImpact:
    """The first impact of a canonical scene, in SI units.

    effective_m: m_eq, kg; effective_radius: R_eq, m; effective_young: E_eq,
    Pa; normal_speed: closing speed along the normal at first touch, m/s;
    tangential_speed: of the sphere's centre along the wall (0 for two
    spheres), m/s; spin: about n x t (t: the tangential direction), rad/s;
    radius: of the (first) sphere, m; restitution, friction: the pair's e_n,
    mu; alpha: eq. 9's constant (None for model.damping = engine); stiffness_ratio: k_t0 / k_n, -.
    """

    effective_m: float
    effective_radius: float
    effective_young: float
    normal_speed: float
    tangential_speed: float
    spin: float
    radius: float
    restitution: float
    friction: float
    alpha: float | None
    stiffness_ratio: float
    drop_height: float
    gravity: float


class NotApplicable(ValueError):
    """A closed form was asked of a scene it does not describe."""


def first_impact(case) -> FirstImpact:
    """The canonical first impact of the case (raises NotApplicable for other scenes)."""

    g = STANDARD_GRAVITY if case.simulation.gravity else 0.0
    if len(case.spheres) == 1 and case.plane is not None:
        sphere = case.spheres[0]
        a, b = sphere.material, case.plane.material
        normal = np.array(case.plane.unit_normal)
        velocity = np.array(sphere.velocity, float)
        height = float((np.array(sphere.position) - np.array(case.plane.point)) @ normal) - sphere.radius
        approach = -float(velocity @ normal)
        gravity_along = g * max(normal[2], 0.0)
        if gravity_along > 0.0:  # energy: falling through the gap adds 2 g h to v_n^2 (gravity along the normal)
            approach = math.sqrt(approach**2 + 2.0 * gravity_along * height)
        tangential = velocity - (velocity @ normal) * normal
        speed_t = float(np.linalg.norm(tangential))
        direction = tangential / speed_t if speed_t > 0 else np.zeros(3)
        spin = float(np.array(sphere.angular_velocity) @ np.cross(normal, direction)) if speed_t > 0 else 0.0
        m_eq, r_eq = sphere_mass(case, 0), sphere.radius
        radius = sphere.radius
    elif len(case.spheres) == 2 and case.plane is None:
        s1, s2 = case.spheres
        a, b = s1.material, s2.material
        branch = np.array(s2.position, float) - np.array(s1.position, float)
        normal = branch / np.linalg.norm(branch)
        relative = np.array(s2.velocity, float) - np.array(s1.velocity, float)
        approach = -float(relative @ normal)
        if np.linalg.norm(relative + approach * normal) > 1e-9 * max(abs(approach), 1e-300):
            raise NotApplicable("the two spheres do not collide head-on; only normal sphere-sphere impacts have a "
                                "closed form here")
        speed_t, spin, height = 0.0, 0.0, 0.0
        m1, m2 = sphere_mass(case, 0), sphere_mass(case, 1)
        m_eq, r_eq = m1 * m2 / (m1 + m2), s1.radius * s2.radius / (s1.radius + s2.radius)
        radius = s1.radius
    else:
        raise NotApplicable("closed forms apply to one sphere with a plane, or two spheres without one; this case has "
                            f"{len(case.spheres)} sphere(s) and {'a' if case.plane else 'no'} plane")
    if approach <= 0:
        raise NotApplicable("the bodies do not approach each other, so there is no impact")
    pair = case.contact(a, b)
    e_eq = effective_young(case, a, b)
    k_t0 = contact.mindlin_stiffness_coefficient(r_eq, young_modulus(case, a), poisson_ratio(case, a),
                                                 young_modulus(case, b), poisson_ratio(case, b))
    ratio = float(k_t0 / contact.hertz_stiffness(e_eq, r_eq))
    return FirstImpact(m_eq, r_eq, e_eq, approach, speed_t, spin, radius, pair.restitution, pair.friction,
                       damping_alpha_for(case, pair.restitution), ratio, height, g)


def _alpha(impact: FirstImpact) -> float:
    if impact.alpha is None:
        raise NotApplicable("this closed form needs model.damping = 'exact' or 'eq10'")
    return impact.alpha


def _hertz(function_name):
    def compute(case):

        i = first_impact(case)
        return float(getattr(closed_form, function_name)(i.effective_m, i.effective_radius, i.effective_young,
                                                         i.normal_speed))
    return compute


def _damped(ratio_name, function_name):
    def compute(case):

        i = first_impact(case)
        ratio = getattr(closed_form.damped_hertz_impact(_alpha(i), True), ratio_name)
        return ratio * float(getattr(closed_form, function_name)(i.effective_m, i.effective_radius,
                                                                 i.effective_young, i.normal_speed))
    return compute


def effective_restitution(impact: FirstImpact) -> float:
    """Rebound over impact normal speed of the damped Hertz impact with the case's alpha, - (no tension)."""

    return float(closed_form.restitution_from_alpha(_alpha(impact), True))


def _restitution(case):
    return effective_restitution(first_impact(case))


def _input_restitution(case):
    return first_impact(case).restitution


def _oblique(case):
    i = first_impact(case)
    if i.tangential_speed == 0.0:
        raise NotApplicable("the sphere has no tangential velocity along the plane: not an oblique impact")
    return i


def _walton(case):
    """Walton's rigid-body rebound: sliding throughout when the contact point's slip exceeds what friction can
    stop, |u| > (1 + 1/gyration) mu (1 + e_n) v_n (the threshold under the Mindlin spring, beta_0 = 0; see
    oblique.sliding_incidence_threshold); sticking otherwise, with this law's beta_0 (exact only without slip)."""

    i = _oblique(case)
    restitution = effective_restitution(i)
    slip = i.tangential_speed - i.radius * i.spin
    threshold = oblique.sliding_incidence_threshold(i.friction, restitution)
    if abs(slip) > threshold * i.normal_speed:
        return i, oblique.oblique_impact_rebound(i.normal_speed, i.tangential_speed, i.radius, i.friction,
                                                 restitution, tangential_restitution=0.0, spin=i.spin)
    beta_0 = oblique.no_slip_tangential_restitution(i.stiffness_ratio, _alpha(i), True,
                                                    contact.SOLID_SPHERE_GYRATION)
    return i, oblique.oblique_impact_rebound(i.normal_speed, i.tangential_speed, i.radius, math.inf, restitution,
                                             tangential_restitution=beta_0, spin=i.spin)


def _mindlin(case):

    i = _oblique(case)
    k_n = contact.hertz_stiffness(i.effective_young, i.effective_radius)
    scale = (i.effective_m * i.normal_speed**2 / k_n) ** 0.4
    result = oblique.oblique_impact_mindlin(i.tangential_speed / i.normal_speed, i.friction, i.stiffness_ratio,
                                            _alpha(i), True, spin=i.radius * i.spin / i.normal_speed,
                                            overlap_over_radius=float(scale / i.radius))
    return i, result


def _bounces(case):
    """Impact speeds (m/s) of the first three impacts of a sphere dropped onto the plane."""

    i = first_impact(case)
    if i.gravity == 0.0 or case.plane is None:
        raise NotApplicable("the bounce sequence needs gravity and a plane")
    speeds, _ = closed_form.bounce_sequence(1.0, effective_restitution(i), i.gravity, 3)
    return i, speeds / speeds[0] * i.normal_speed


def _time_between(k):
    def compute(case):

        i, speeds = _bounces(case)
        duration = closed_form.hertz_contact_duration(i.effective_m, i.effective_radius, i.effective_young, speeds[k])
        duration *= closed_form.damped_hertz_impact(_alpha(i), True).duration_ratio
        return float(duration + 2.0 * effective_restitution(i) * speeds[k] / i.gravity)
    return compute


def _peak(k):
    def compute(case):

        i, speeds = _bounces(case)
        return float(closed_form.damped_hertz_peak_force(i.effective_m, i.effective_radius, i.effective_young,
                                                         speeds[k], _alpha(i)))
    return compute


CLOSED_FORMS: dict[str, ClosedForm] = {
    "hertz_max_force": ClosedForm("max_normal_force", False, _hertz("hertz_max_force"),
                                  "undamped Hertz: k_n delta_max^(3/2), N"),
    "hertz_max_overlap": ClosedForm("max_overlap", False, _hertz("hertz_max_overlap"),
                                    "undamped Hertz: (15 m v^2 / (16 E_eq sqrt(R_eq)))^(2/5), m"),
    "hertz_contact_duration": ClosedForm("contact_duration", False, _hertz("hertz_contact_duration"),
                                         "undamped Hertz: 2.9433 delta_max / v, s"),
    "damped_hertz_max_force": ClosedForm("max_normal_force", True, _damped("peak_force_ratio", "hertz_max_force"),
                                         "Tsuji-damped Hertz impact (integrated), N"),
    "damped_hertz_max_overlap": ClosedForm("max_overlap", True, _damped("peak_overlap_ratio", "hertz_max_overlap"),
                                           "Tsuji-damped Hertz impact (integrated), m"),
    "damped_hertz_contact_duration": ClosedForm("contact_duration", True,
                                                _damped("duration_ratio", "hertz_contact_duration"),
                                                "Tsuji-damped Hertz impact (integrated), s"),
    "damped_hertz_restitution": ClosedForm("restitution", True, _restitution,
                                           "rebound of the damped impact with the case's alpha (no tension), -"),
    "input_restitution": ClosedForm("restitution", False, _input_restitution, "the pair's e_n as given, -"),
    "walton_rebound_tangential_velocity": ClosedForm(
        "rebound_tangential_velocity", True, lambda case: float(_walton(case)[1].tangential_velocity),
        "rigid-body theory (Walton) with this law's beta_0, m/s"),
    "walton_rebound_spin": ClosedForm("rebound_spin", True, lambda case: float(_walton(case)[1].spin),
                                      "rigid-body theory (Walton) with this law's beta_0, rad/s"),
    "mindlin_rebound_tangential_velocity": ClosedForm(
        "rebound_tangential_velocity", True,
        lambda case: (lambda i, r: float(r.tangential_velocity * i.normal_speed))(*_mindlin(case)),
        "the paper's law integrated through the impact (stick, slip), m/s", needs_total_limit=True),
    "mindlin_rebound_spin": ClosedForm(
        "rebound_spin", True, lambda case: (lambda i, r: float(r.spin * i.normal_speed / i.radius))(*_mindlin(case)),
        "the paper's law integrated through the impact (stick, slip), rad/s", needs_total_limit=True),
    "ballistic_time_between_impacts_1": ClosedForm("time_between_impacts_1", True, _time_between(0),
                                                   "damped contact duration + 2 e v_1 / g, s"),
    "ballistic_time_between_impacts_2": ClosedForm("time_between_impacts_2", True, _time_between(1),
                                                   "damped contact duration + 2 e v_2 / g, s"),
    "damped_hertz_peak_force_1": ClosedForm("peak_force_1", True, _peak(0), "damped Hertz at the 1st impact speed, N"),
    "damped_hertz_peak_force_2": ClosedForm("peak_force_2", True, _peak(1), "damped Hertz at the 2nd impact speed, N"),
    "damped_hertz_peak_force_3": ClosedForm("peak_force_3", True, _peak(2), "damped Hertz at the 3rd impact speed, N"),
}


def expected_value(case, check) -> float:
    """The expected value of a check: its value, or its closed form evaluated on the case (raises NotApplicable)."""
    if check.value is not None:
        return float(check.value)
    return float(CLOSED_FORMS[check.closed_form].function(case))


#: Every quantity an impact run measures: name -> (SI unit, meaning).
QUANTITIES: dict[str, tuple[str, str]] = {
    "max_normal_force": ("N", "peak normal force of the first contact"),
    "max_overlap": ("m", "largest overlap of the first contact"),
    "contact_duration": ("s", "first contact, first touch to separation"),
    "restitution": ("-", "first contact: normal rebound speed / normal impact speed"),
    "rebound_tangential_velocity": ("m/s", "after the first wall contact: centre velocity along the incoming "
                                           "tangential direction t"),
    "rebound_spin": ("rad/s", "after the first wall contact: angular velocity about n x t (rolling along +t is > 0)"),
    "peak_force_1": ("N", "peak normal force of the 1st contact"),
    "peak_force_2": ("N", "peak normal force of the 2nd contact"),
    "peak_force_3": ("N", "peak normal force of the 3rd contact"),
    "time_between_impacts_1": ("s", "start of the 2nd contact minus start of the 1st"),
    "time_between_impacts_2": ("s", "start of the 3rd contact minus start of the 2nd"),
    "n_contacts": ("-", "number of contacts (closed or still open at the end)"),
}
