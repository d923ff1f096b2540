"""Oblique impact of a sphere on an immovable plane with Coulomb friction.

Two references:

- oblique_impact_rebound: Walton's rigid-body theory. The sphere either
  sticks (its contact point leaves with u' = -beta_0 u, beta_0 the
  tangential restitution) or slides throughout (tangential impulse
  mu (1 + e_n) m v_n).
- oblique_impact_mindlin: the impact under the paper's law itself (Hertz,
  Tsuji damping, Mindlin no-slip spring with c_t = c_n, incremental, with
  the Coulomb limit on the total tangential force, contact.tangential_force_update),
  integrated in dimensionless form with scipy, stick and slip phases joined
  at events. It covers the mixed regime (stick, then slip near the end of
  the contact, Maw et al. 1976) that rigid-body theory cannot, and gives the
  beta_0 of this law (no_slip_tangential_restitution). It follows the DEM's
  default coulomb_limit="total", not Yade's "elastic".

Sign convention: the sphere moves along +t; its spin omega is positive when
it rolls along +t, so the contact-point velocity is u = v_t - R omega.
Velocities in m/s; in the dimensionless functions they are in units of the
normal impact speed v_n (and R omega / v_n for the spin).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

from orchestrator.reference.closed_form import (
    TOLERANCES,
    dimensionless_normal_force,
    finish_with_tension,
    normal_force_zero_event,
)
from orchestrator.reference.contact import SOLID_SPHERE_GYRATION


@dataclass(frozen=True)
class ObliqueRebound:
    """Rebound from the plane: tangential_velocity of the centre (m/s), spin (rad/s),
    contact_point_velocity u' (m/s); sliding: True if the sphere slid throughout."""

    tangential_velocity: float
    spin: float
    contact_point_velocity: float
    sliding: bool


def oblique_impact_rebound(normal_speed, tangential_speed, radius, friction, restitution,
                           tangential_restitution=0.0, spin=0.0, gyration=SOLID_SPHERE_GYRATION):
    """Walton's rigid-body theory of an oblique impact with Coulomb friction.

    normal_speed: impact speed towards the plane, m/s (> 0);
    tangential_speed: of the centre, m/s; radius: m; friction: mu, -;
    restitution: e_n, -; tangential_restitution: beta_0, - (0: the sphere
    leaves rolling; no_slip_tangential_restitution gives this law's);
    spin: initial, rad/s; gyration: I / (m R^2), - (2/5 solid sphere).

    With u = v_t - R omega and k = 1 + 1/gyration, the tangential impulse per
    unit mass is J = (1 + beta_0) u / k if that is below mu (1 + e_n) v_n
    (sticking), else mu (1 + e_n) v_n sign(u) (sliding throughout); then
    v_t' = v_t - J, omega' = omega + J / (gyration R), u' = u - k J.
    """
    slip = tangential_speed - radius * spin
    spin_factor = 1.0 + 1.0 / gyration
    sticking_impulse = (1.0 + tangential_restitution) * slip / spin_factor
    sliding_impulse = friction * (1.0 + restitution) * normal_speed * math.copysign(1.0, slip)
    sliding = abs(sticking_impulse) > abs(sliding_impulse)
    impulse = sliding_impulse if sliding else sticking_impulse
    new_tangential = tangential_speed - impulse
    new_spin = spin + impulse / (gyration * radius)
    return ObliqueRebound(new_tangential, new_spin, new_tangential - radius * new_spin, sliding)


def sliding_incidence_threshold(friction, restitution, tangential_restitution=0.0, gyration=SOLID_SPHERE_GYRATION):
    """tan(theta), theta from the normal, above which a non-spinning sphere slides throughout
    in rigid-body theory: (1 + 1/gyration) mu (1 + e_n) / (1 + beta_0).

    Under the Mindlin spring the contact point only slides throughout when
    tan(theta) > (1 + 1/gyration) mu (1 + e_n) (i.e. beta_0 = 0 here): it
    would otherwise stop slipping before the end of the contact.
    """
    return (1.0 + 1.0 / gyration) * friction * (1.0 + restitution) / (1.0 + tangential_restitution)


#: |s| (over v_n) below which a contact point at the limit is treated as pinned to it:
#: the discrete law's slide-one-step-then-stick cycles there have a vanishing period.
_PINNED_SPEED = 1e-6
_MAX_SWITCHES = 20000


@dataclass(frozen=True)
class MindlinObliqueImpact:
    """Dimensionless rebound under the paper's law (velocities over the normal impact speed).

    restitution: e_n; tangential_velocity: v_t' / v_n; spin: R omega' / v_n;
    contact_point_velocity: u' / v_n; slid: the contact slipped at some time.
    """

    restitution: float
    tangential_velocity: float
    spin: float
    contact_point_velocity: float
    slid: bool


STICK, SLIP, PINNED = "stick", "slip", "pinned"


def _event(function, direction: int = 0):
    """function as a terminal solve_ivp event that fires when it crosses zero in direction (0: either way)."""
    function.terminal, function.direction = True, direction
    return function


class _ObliqueLaw:
    """The right-hand sides and events of oblique_impact_mindlin's phases (its docstring has the equations).

    q = (x, x', v, w, phi); direction: the sign of the limited force while a phase rides the Coulomb limit.
    """

    def __init__(self, friction, stiffness_ratio, alpha, no_tension, gyration, overlap_over_radius):
        self.lam, self.mu, self.eps = float(stiffness_ratio), float(friction), float(overlap_over_radius)
        self.alpha, self.no_tension, self.gyration = alpha, no_tension, gyration
        self.direction = 0.0

    def normal(self, x, y):
        force = dimensionless_normal_force(x, y, self.alpha)
        return max(force, 0.0) if self.no_tension else force

    def viscous(self, x, s):
        return self.alpha * max(x, 0.0) ** 0.25 * s

    def arm(self, x):
        return 1.0 - 0.5 * self.eps * x

    def contact_point(self, q):
        return q[2] - self.arm(q[0]) * q[3]

    def limit(self, q):
        """mu F_n, the Coulomb limit of the tangential force."""
        return self.mu * max(self.normal(q[0], q[1]), 0.0)

    def motion(self, q, f):
        return [q[1], -self.normal(q[0], q[1]), f, -self.arm(q[0]) * f / self.gyration]

    def stick_rhs(self, _, q):
        s = self.contact_point(q)
        return self.motion(q, q[4] - self.viscous(q[0], s)) + [-self.lam * math.sqrt(max(q[0], 0.0)) * s]

    def limited_rhs(self, _, q):
        return self.motion(q, self.direction * self.limit(q)) + [0.0]

    def sticking_keeps_up(self, _, q):
        """d|f|/dtau if it stuck now, minus d(mu F_n)/dtau: sticking resumes when this is >= 0."""
        x, y, s = max(q[0], 1e-300), q[1], abs(self.contact_point(q))
        alpha, mu = self.alpha, self.mu
        force = max(self.normal(x, y), 0.0)
        spin_factor = 1.0 + self.arm(x) ** 2 / self.gyration
        d_force = 1.5 * math.sqrt(x) * y + alpha * (0.25 * x**-0.75 * y * y - x**0.25 * force)
        d_margin = self.lam * math.sqrt(x) * s + alpha * (0.25 * x**-0.75 * y * s + x**0.25 * spin_factor * mu * force)
        return d_margin + mu * d_force

    def phase_events(self) -> dict[str, list]:
        """The events that end each phase (the contact's end comes first, separately)."""
        starts_slipping = _event(lambda _, q: abs(q[4] - self.viscous(q[0], self.contact_point(q))) - self.limit(q),
                                 direction=1)
        contact_point_stops = _event(lambda _, q: self.contact_point(q))
        contact_point_moves = _event(lambda _, q: abs(self.contact_point(q)) - _PINNED_SPEED, direction=1)
        # undamped: a step slides while lambda sqrt(x) |s| > mu dF_n/dtau = 1.5 mu sqrt(x) x'
        limit_outgrows_spring = _event(lambda _, q: self.lam * abs(self.contact_point(q)) - 1.5 * self.mu * q[1],
                                       direction=-1)
        return {
            STICK: [starts_slipping] if math.isfinite(self.mu) else [],
            SLIP: [contact_point_stops] + ([] if self.alpha > 0 else [limit_outgrows_spring]),
            PINNED: [_event(lambda tau, q: self.sticking_keeps_up(tau, q), direction=1), contact_point_moves],
        }

    def first_phase(self, q) -> str:
        """The phase at first touch (and the direction of the limited force if it slips)."""
        slip0 = self.contact_point(q)
        # first instant: F_n ~ alpha x^(1/4), f ~ alpha x^(1/4) s (or, undamped, both ~ x^(3/2))
        initial_demand = abs(slip0) if self.alpha > 0 else 2.0 / 3.0 * self.lam * abs(slip0)
        if initial_demand > self.mu:
            self.direction = -math.copysign(1.0, slip0)
            return SLIP
        self.direction = 0.0
        return STICK

    def leave_stick(self, q) -> str:
        """The phase after |f| reached the limit while sticking (q at the event; phi may jump)."""
        s = self.contact_point(q)
        self.direction = math.copysign(1.0, q[4] - self.viscous(q[0], s))
        if self.direction * s < -_PINNED_SPEED:  # at s ~ 0 the force itself sets where s goes: along f
            return SLIP
        if self.alpha > 0 and abs(s) >= _PINNED_SPEED:
            q[4] = self.direction * self.limit(q)  # one sliding step, then the dash-pot keeps |f| below the limit
            return STICK
        return PINNED

    def leave_limit(self, phase, which, tau, q) -> str:
        """The phase after the event `which` (1-based among the phase's) ended slip or pinned (phi set in q).

        Back to sticking: from slip, or from pinned once sticking keeps up, with f continuous (phi = f + alpha
        x^(1/4) s); from pinned once s is off zero, as after a sliding step (phi = f, so the dash-pot now lowers
        |f| below the limit).
        """
        keeps_up = phase == PINNED and which == 1
        q[4] = self.direction * self.limit(q) + (self.viscous(q[0], self.contact_point(q)) if keeps_up else 0.0)
        if phase == SLIP and self.alpha > 0 and self.sticking_keeps_up(tau, q) < 0:
            # s = 0 with f at a falling limit: sticking cannot hold it, so ride the limit
            return PINNED
        self.direction = 0.0
        return STICK


def _integrate(law: _ObliqueLaw, q: list) -> tuple[float, list, bool]:
    """Run the contact from first touch (state q) to its end: (tau, q at the end, whether it slid)."""
    from scipy.integrate import solve_ivp

    end = normal_force_zero_event(law.alpha)
    events = law.phase_events()
    phase = law.first_phase(q)
    tau, slid = 0.0, phase == SLIP
    for _ in range(_MAX_SWITCHES):
        rhs = law.stick_rhs if phase == STICK else law.limited_rhs
        solution = solve_ivp(rhs, (tau, tau + 100.0), q, events=[end] + events[phase], **TOLERANCES)
        fired = [i for i, times in enumerate(solution.t_events) if len(times)]
        if solution.status != 1 or not fired:
            raise RuntimeError(f"oblique impact did not end: {solution.message}")
        which = min(fired, key=lambda i: solution.t_events[i][0])
        tau, q = solution.t_events[which][0], list(solution.y_events[which][0])
        if which == 0:
            return tau, q, slid
        if phase == STICK:
            slid = True
            phase = law.leave_stick(q)
        else:
            phase = law.leave_limit(phase, which, tau, q)
        tau += 1e-15  # step off the event so it does not fire again at once
    raise RuntimeError(f"oblique impact switched between stick and slip more than {_MAX_SWITCHES} times")


@lru_cache(maxsize=512)
def oblique_impact_mindlin(tangent_of_incidence: float, friction: float, stiffness_ratio: float, alpha: float,
                           no_tension: bool = True, gyration: float = SOLID_SPHERE_GYRATION, spin: float = 0.0,
                           overlap_over_radius: float = 0.0) -> MindlinObliqueImpact:
    """Integrate one oblique impact under the paper's law (dimensionless).

    tangent_of_incidence: v_t / v_n of the centre; friction: mu (inf for no
    slip); stiffness_ratio: k_t0 / k_n (contact.mindlin_stiffness_coefficient
    over contact.hertz_stiffness; 3 (1 - nu) / (2 - nu) on a wall of the
    sphere's material); alpha: damping constant; spin: R omega / v_n before;
    overlap_over_radius: d*/R with d* = (m v_n^2 / k_n)^(2/5). The contact
    point sits at R (1 - (d*/R) x / 2) from the centre, as in Yade and our
    DEM (the middle of the overlap); 0 puts it at R, as rigid-body theory does.

    State (x, x', v, w, phi): overlap and its rate as in closed_form, centre
    tangential velocity v, spin w = R omega (both over v_n), elastic
    tangential force phi (unit m v_n / T). With the arm b = 1 - eps x / 2,
    the contact-point velocity is s = v - b w; v' = f, w' = -b f / gyration.
    Three phases, joined at events, follow contact.tangential_force_update
    ("total") in the limit of small steps:

    - stick: phi' = -lambda sqrt(x) s, f = phi - alpha x^(1/4) s, while |f| <= mu F_n;
    - slip (f opposes s): f = -mu F_n sign(s), stored as phi, until s is zero
      (without damping also until the limit grows faster than the spring loads);
    - pinned (f along s, at s ~ 0 while F_n falls): the spring unloads slower
      than the limit drops, so f rides on mu F_n until sticking keeps up or
      s is off zero. From then on, each time |f| reaches the limit the
      discrete law slides one step (phi set to the limit) and sticks again
      because the dash-pot lowers |f|; we do that step as a jump.

    The tangential force ends with F_n (mu F_n = 0); the normal motion does
    not feel it.
    """
    law = _ObliqueLaw(friction, stiffness_ratio, alpha, no_tension, gyration, overlap_over_radius)
    tau, q, slid = _integrate(law, [1e-14, 1.0, float(tangent_of_incidence), float(spin), 0.0])
    x_end, y_end, v_end, w_end, _ = q
    if no_tension or x_end <= 0.0:
        restitution = -y_end
    else:
        restitution = finish_with_tension(alpha, tau, x_end, y_end)[0]
    return MindlinObliqueImpact(restitution=float(restitution), tangential_velocity=float(v_end),
                                spin=float(w_end), contact_point_velocity=float(v_end - w_end), slid=slid)


def no_slip_tangential_restitution(stiffness_ratio, alpha, no_tension=True, gyration=SOLID_SPHERE_GYRATION):
    """beta_0 = -u'/u of the paper's law without slip (mu = inf), -; a function of
    k_t0 / k_n, alpha and the gyration only. Use it in oblique_impact_rebound."""
    impact = oblique_impact_mindlin(1.0, math.inf, float(stiffness_ratio), float(alpha), bool(no_tension), gyration)
    return -impact.contact_point_velocity
