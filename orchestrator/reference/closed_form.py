"""Closed-form (and exactly integrated) solutions of single impacts under the
contact law of orchestrator.reference.contact. SI units (m, kg, s, N, Pa).

- Hertz impact without damping: maximum overlap, maximum force, duration.
- Hertz impact with Tsuji damping (eq. 9): restitution, peak force and
  duration depend on alpha alone; we integrate the dimensionless equation
  with scipy at tight tolerances (and invert it for alpha(e_n)).
- (Oblique impacts with friction are in orchestrator.reference.oblique.)
- Ballistic bounce sequence of a dropped sphere.

The dimensionless impact: overlap delta = d* x, time t = T tau with
d* = (m_eq v^2 / k_n)^(2/5) and T = d*/v, so that
x'' = -(x^(3/2) + alpha x^(1/4) x') with x(0) = 0, x'(0) = 1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from orchestrator.reference.contact import damping_alpha

#: t_c = HERTZ_DURATION_FACTOR * delta_max / v: 2 int_0^1 dx / sqrt(1 - x^(5/2)) = (4/5) B(2/5, 1/2).
HERTZ_DURATION_FACTOR = 0.8 * math.gamma(0.4) * math.gamma(0.5) / math.gamma(0.9)  # 2.943275... (B(a, b) by Gamma)
#: Maximum dimensionless overlap of the undamped impact, (5/4)^(2/5).
_UNDAMPED_PEAK_OVERLAP = 1.25**0.4
TOLERANCES = dict(rtol=1e-11, atol=1e-13, method="DOP853")


def hertz_max_overlap(effective_m, effective_rad, effective_young, impact_speed):
    """delta_max = (15 m_eq v^2 / (16 E_eq sqrt(R_eq)))^(2/5), m (undamped Hertz impact).

    effective_m: kg; effective_rad: m; effective_young: Pa; impact_speed:
    normal relative speed, m/s.
    """
    return (15.0 * effective_m * impact_speed**2 / (16.0 * effective_young * np.sqrt(effective_rad))) ** 0.4


def hertz_max_force(effective_m, effective_rad, effective_young, impact_speed):
    """F_max = k_n delta_max^(3/2), N, with k_n = 4/3 E_eq sqrt(R_eq) (undamped)."""
    overlap = hertz_max_overlap(effective_m, effective_rad, effective_young, impact_speed)
    return 4.0 / 3.0 * effective_young * np.sqrt(effective_rad) * overlap**1.5


def hertz_contact_duration(effective_m, effective_rad, effective_young, impact_speed):
    """t_c = (4/5) B(2/5, 1/2) delta_max / v = 2.8683 (m_eq^2 / (R_eq E_eq^2 v))^(1/5), s (undamped)."""
    overlap = hertz_max_overlap(effective_m, effective_rad, effective_young, impact_speed)
    return HERTZ_DURATION_FACTOR * overlap / impact_speed


@dataclass(frozen=True)
class DampedHertzImpact:
    """A Tsuji-damped Hertz impact, each quantity relative to the undamped
    impact at the same speed (so 1, 1, 1, 1 for alpha = 0).

    restitution: rebound / impact normal speed; peak_force_ratio,
    peak_overlap_ratio, duration_ratio: over hertz_max_force,
    hertz_max_overlap, hertz_contact_duration (duration: until the overlap
    is zero again). tangential_restitution: beta_0 = -(rebound contact-point
    tangential velocity) / (impact one) of a sphere sticking on a wall
    (nan unless asked for).
    """

    alpha: float
    no_tension: bool
    restitution: float
    peak_force_ratio: float
    peak_overlap_ratio: float
    duration_ratio: float


def dimensionless_normal_force(x, y, alpha):
    """F_n / (k_n d*^(3/2)) before clipping."""
    xp = max(x, 0.0)
    return xp**1.5 + alpha * xp**0.25 * y


@lru_cache(maxsize=256)
def damped_hertz_impact(alpha: float, no_tension: bool = True) -> DampedHertzImpact:
    """Integrate the dimensionless damped Hertz impact (alpha >= 0, dimensionless)."""
    from scipy.optimize import minimize_scalar
    from scipy.integrate import solve_ivp

    if alpha < 0:
        raise ValueError(f"damping alpha must be >= 0, got {alpha}")

    def rhs(_, state):
        force = dimensionless_normal_force(state[0], state[1], alpha)
        return [state[1], -max(force, 0.0) if no_tension else -force]

    x0 = 1e-14  # the equation is singular in x^(1/4) at 0; start a hair inside
    solution = solve_ivp(rhs, (0.0, 100.0), [x0, 1.0], events=[normal_force_zero_event(alpha), _deepest],
                         dense_output=True, **TOLERANCES)
    if solution.status != 1:
        raise RuntimeError(f"damped Hertz impact with alpha={alpha} did not end: {solution.message}")
    tau_end = solution.t_events[0][0]
    x_end, y_end = solution.y_events[0][0]
    peak_overlap = solution.y_events[1][0][0] if len(solution.t_events[1]) else x_end

    if no_tension or x_end <= 0.0:
        # no force acts after F_n = 0: the bodies fly apart at the speed they have
        rebound_speed, tau_sep = -y_end, tau_end + max(x_end, 0.0) / max(-y_end, 1e-300)
    else:
        rebound_speed, tau_sep = finish_with_tension(alpha, tau_end, x_end, y_end)

    grid = np.linspace(0.0, tau_end, 4001)
    forces = np.array([dimensionless_normal_force(x, y, alpha) for x, y in solution.sol(grid).T])
    k = int(np.argmax(forces))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    best = minimize_scalar(lambda t: -dimensionless_normal_force(*solution.sol(t), alpha), bounds=(lo, hi),
                           method="bounded", options={"xatol": 1e-13})
    peak_force = max(-best.fun, forces[k])

    undamped_force = _UNDAMPED_PEAK_OVERLAP**1.5
    undamped_duration = HERTZ_DURATION_FACTOR * _UNDAMPED_PEAK_OVERLAP
    return DampedHertzImpact(
        alpha=float(alpha), no_tension=bool(no_tension), restitution=float(rebound_speed),
        peak_force_ratio=float(peak_force / undamped_force),
        peak_overlap_ratio=float(peak_overlap / _UNDAMPED_PEAK_OVERLAP),
        duration_ratio=float((tau_sep + x0) / undamped_duration),
    )


def normal_force_zero_event(alpha):
    """solve_ivp event (terminal, falling) at F_n = 0 for a state starting (x, x', ...)."""

    def event(_, state):
        # F_n = x^(1/4) (x^(5/4) + alpha x'): its sign is that of the bracket
        # (signed power so that alpha = 0 crosses zero at separation).
        return math.copysign(abs(state[0]) ** 1.25, state[0]) + alpha * state[1]

    event.terminal, event.direction = True, -1
    return event


def _deepest(_, state):
    return state[1]


def finish_with_tension(alpha, tau_start, x_start, y_start):
    """Carry on past F_n = 0 with the viscous term pulling, until the overlap is zero."""
    from scipy.integrate import solve_ivp

    def rhs(_, state):
        return [state[1], -dimensionless_normal_force(state[0], state[1], alpha)]

    def separated(_, state):
        return state[0]

    separated.terminal, separated.direction = True, -1
    solution = solve_ivp(rhs, (tau_start, tau_start + 100.0), [x_start, y_start], events=separated, **TOLERANCES)
    return -solution.y_events[0][0][1], solution.t_events[0][0]


def restitution_from_alpha(alpha: float, no_tension: bool = True) -> float:
    """Coefficient of restitution, -, produced by the damping constant alpha of eq. 9
    (a function of alpha alone for Tsuji's form); no_tension as in contact.normal_force."""
    return damped_hertz_impact(float(alpha), bool(no_tension)).restitution


@lru_cache(maxsize=256)
def alpha_from_restitution(restitution: float, no_tension: bool = True) -> float:
    """The alpha of eq. 9, -, that gives the rebound e_n exactly (root of restitution_from_alpha).

    Use it instead of eq. 10 when the normal force is clipped at zero (the
    default): eq. 10 then overshoots the rebound (e.g. 0.70 for e_n = 0.68).
    Without the clip eq. 10 is exact, and so is this root.
    """
    from scipy.optimize import brentq

    if not 0.0 < restitution <= 1.0:
        raise ValueError(f"restitution must be in (0, 1], got {restitution}")
    if restitution == 1.0:
        return 0.0
    # eq. 10 gives this rebound exactly when the dash-pot may pull; clipping the pull
    # only raises the rebound, so the root lies at or above eq. 10's alpha
    lower = 0.999 * float(damping_alpha(restitution))
    upper = 1.2 * lower
    while restitution_from_alpha(upper, no_tension) > restitution:
        lower, upper = upper, 1.5 * upper
        if upper > 1e4:
            raise ValueError(f"restitution {restitution} is too small to reach with Tsuji damping")
    return brentq(lambda a: restitution_from_alpha(a, no_tension) - restitution, lower, upper, xtol=1e-12, rtol=1e-12)


def damped_hertz_peak_force(effective_m, effective_rad, effective_young, impact_speed, alpha, no_tension=True):
    """Peak normal force, N, of a Tsuji-damped Hertz impact at impact_speed (m/s)."""
    ratio = damped_hertz_impact(float(alpha), bool(no_tension)).peak_force_ratio
    return ratio * hertz_max_force(effective_m, effective_rad, effective_young, impact_speed)


def bounce_sequence(drop_height, restitution, gravity=9.81, impacts=3):
    """Impact speeds (m/s) and impact times (s, from release) of a sphere dropped
    from drop_height (gap, m) onto a flat, bouncing ballistically with
    v_rebound = e_n v_impact and instantaneous impacts."""
    speeds = [math.sqrt(2.0 * gravity * drop_height)]
    times = [speeds[0] / gravity]
    for _ in range(impacts - 1):
        rebound = restitution * speeds[-1]
        times.append(times[-1] + 2.0 * rebound / gravity)
        speeds.append(rebound)
    return np.array(speeds), np.array(times)
