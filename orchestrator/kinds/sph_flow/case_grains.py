"""Rigid grains of an SPH case ([[grains]]): bodies made of the lattice's particles that the fluid drags
(engines/sph/README.md, "Rigid grains", eqs. G1-G5). The scene builder turns the fluid sites inside a grain's
shape into the grain's particles; the engine moves them as one rigid body whose force and torque are the sums of
the fluid's pair terms on them. 3D only. SI units (m, kg, s).

With ``physics.balance_mean_weight`` the box is periodic along the body force g and has no bottom: the mixture's
mean weight is carried by a mean pressure gradient rho_m g (rho_m the mean density of fluid and grains), so the
fluid takes the body force g (1 - rho_m / rho_f) and each grain g (1 - rho_m / rho_g), and the external forces
on the box sum to zero (the standard set-up of a settling array, e.g. Hasimoto 1959).
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from pydantic import Field

from orchestrator.case.common import Frozen, Name, Positive

Vector3 = tuple[float, float, float]

#: The particle kind of a grain's particles in the sph executable's input (engines/sph/src/physics_terms.h).
BODY = 4
#: The sph executable's Verlet skin as a fraction of the support 2h (engines/sph/src/parameters.h, neighbour_skin).
VERLET_SKIN = 0.1
#: The fewest time steps a grain contact (pi sqrt(m / k), undamped) may last: the spring-dashpot's restitution is
#: then within about 1 % of the set one (engines/sph/tests/test_grains.cpp runs its contacts over some 60 steps).
CONTACT_STEPS = 20


class Grain(Frozen):
    """One rigid grain: its shape, density and initial motion."""

    name: Name = Field(description="unique name (series grain_<name>_*)")
    shape: Literal["sphere"] = Field("sphere", description="the grain's shape: 'sphere' (the lattice sites within "
                                     "radius of centre become its particles)")
    radius: Positive = Field(description="radius of the sphere, m")
    density: Positive = Field(description="density of the grain, kg/m^3 (the fluid's: neutrally buoyant)")
    centre: Vector3 = Field(description="centre of the sphere, m")
    velocity: Vector3 = Field((0.0, 0.0, 0.0), description="initial velocity of the centre of mass, m/s")
    angular_velocity: Vector3 = Field((0.0, 0.0, 0.0), description="initial angular velocity, rad/s (world axes)")

    def inside(self, points: np.ndarray) -> np.ndarray:
        """Which of the points (n, 3) m lie inside the grain (bool mask)."""
        return np.linalg.norm(points - np.asarray(self.centre), axis=1) < self.radius

    def rigid_velocity(self, points: np.ndarray) -> np.ndarray:
        """V + omega x (x - centre), m/s, at points (n, 3) m."""
        arm = points - np.asarray(self.centre)
        return np.asarray(self.velocity) + np.cross(np.asarray(self.angular_velocity), arm)


class ContactWall(Frozen):
    """A plane the grains touch (engine eq. G7): a point on it and its normal into the fluid."""

    point: Vector3 = Field(description="a point of the plane, m")
    normal: Vector3 = Field(description="its normal, pointing into the fluid (any length but zero), -")

    def unit_normal(self) -> np.ndarray:
        """The normal scaled to length 1 (zero when it is zero)."""
        n = np.asarray(self.normal, dtype=float)
        length = float(np.linalg.norm(n))
        return n / length if length > 0.0 else n


class GrainContact(Frozen):
    """Grain contact (engine eqs. G6-G8): a linear spring-dashpot between the grains' spheres along the line of
    centres, and between a grain's sphere and each wall plane along its normal, in compression only and without
    friction; each sphere grain touches with its own radius. A grain touches a solid's particles through eq. G8
    (a spring on each particle's overlap with the grain's sphere), whether or not this table is given."""

    stiffness: Positive | None = Field(None, description="normal stiffness k of the grain-grain and grain-wall "
                                       "contact, N/m (none: the grains touch the solids only)")
    solid_stiffness_factor: float = Field(1.0, gt=0.0, le=20.0, description="the spring of a grain on each solid "
                                          "particle (eq. G8) over rho0 c_L^2 dx of the stiffest material, -")
    restitution: float = Field(1.0, gt=0.0, le=1.0, description="normal coefficient of restitution e of a head-on "
                               "collision, - (the damping c = 2 zeta sqrt(k m), zeta = -ln e / sqrt(pi^2 + ln^2 e))")
    walls: tuple[ContactWall, ...] = Field((), description="planes the grains touch (eq. G7; e.g. a channel's wall "
                                           "faces): [[grain_contact.walls]] tables of point and normal")

    def deck(self, solid_stiffness: float | None = None) -> dict:
        """The deck's grain_contact object (engines/sph/README.md), the normals of unit length; solid_stiffness:
        eq. G8's spring k_s (N/m) when the run has a solid."""
        out = {} if solid_stiffness is None else {"solid_stiffness": float(solid_stiffness)}
        if self.stiffness is None:
            return out
        out |= {"stiffness": float(self.stiffness), "restitution": float(self.restitution)}
        if self.walls:
            out["walls"] = [{"point": [float(c) for c in w.point], "normal": [float(c) for c in w.unit_normal()]}
                            for w in self.walls]
        return out


def check_grains(case) -> None:
    """ValueError naming the key unless the grains are 3D, uniquely named, inside the domain, smaller than it, apart,
    within fluid.max_speed, and a balanced mean weight has what it needs."""
    grains = case.grains
    if case.physics.balance_mean_weight:
        if not grains:
            raise ValueError("physics.balance_mean_weight balances the weight of [[grains]]; the case has none")
        if case.physics.body_force is None or "body_force" not in case.physics.terms:
            raise ValueError("physics.balance_mean_weight needs physics.body_force and 'body_force' in physics.terms "
                             "(the weight it balances)")
        if len(case.materials) > 1:
            raise ValueError("physics.balance_mean_weight needs one fluid material (one fluid density)")
        if case.physics.body_force_on != "all":
            raise ValueError("physics.balance_mean_weight balances a weight on fluid and grains alike; it cannot go "
                             "with physics.body_force_on = 'fluids'")
    # In a Lees-Edwards cell no pair of a grain's particle may cross the sheared faces (y = lo, hi): the support 2h
    # and the engine's Verlet skin (0.1 of it) inside them.
    sheared_margin = 2.0 * case.numerics.h_over_dx * case.numerics.dx * (1.0 + VERLET_SKIN)
    if case.grain_contact is not None and (not grains or case.lees_edwards is not None):
        raise ValueError("grain_contact needs [[grains]]" if not grains else
                         "grain_contact cannot act in a Lees-Edwards cell ([lees_edwards]); remove one of them")
    if case.grain_contact is not None:
        contact = case.grain_contact
        if contact.stiffness is None and (contact.walls or contact.given(("restitution",))):
            raise ValueError("grain_contact.restitution and grain_contact.walls need grain_contact.stiffness (the "
                             "grain-grain and grain-wall spring, N/m)")
        if contact.stiffness is None and not has_solid(case):
            raise ValueError("grain_contact.stiffness is missing: without it the grains touch only a solid (eq. G8), "
                             "and the case has no johnson_cook material; give the grain-grain spring in N/m")
        _check_contact(case)
    names: set[str] = set()
    lo, hi = np.asarray(case.domain.lo), np.asarray(case.domain.hi)
    for i, g in enumerate(grains):
        if case.dimension != 3:
            raise ValueError(f"grains[{i}]: grains act in 3D only (domain.dimension = {case.dimension})")
        if g.name in names:
            raise ValueError(f"grains[{i}].name = {g.name!r} is used twice; names must be unique")
        names.add(g.name)
        size = float((hi - lo).min())
        if 2.0 * g.radius >= size:
            raise ValueError(f"grains[{i}].radius = {g.radius:g} m: the grain ({2 * g.radius:g} m across) is larger "
                             f"than the domain box ({size:g} m along its shortest side)")
        centre = np.asarray(g.centre)
        if np.any(centre - g.radius < lo) or np.any(centre + g.radius > hi):
            raise ValueError(f"grains[{i}].centre = {list(g.centre)}: the grain (radius {g.radius:g} m) reaches "
                             f"outside the domain box [{list(case.domain.lo)}, {list(case.domain.hi)}]")
        if case.lees_edwards is not None and (centre[1] - g.radius - lo[1] < sheared_margin
                                              or hi[1] - centre[1] - g.radius < sheared_margin):
            raise ValueError(f"grains[{i}].centre = {list(g.centre)}: in a Lees-Edwards cell the grain must stay "
                             f"{sheared_margin:.4g} m (the support 2h and the neighbour list's skin) inside the sheared "
                             f"faces y = {lo[1]:g} and {hi[1]:g} m")
        speed = math.hypot(*g.velocity) + math.hypot(*g.angular_velocity) * g.radius
        if speed > case.fluid.max_speed:
            raise ValueError(f"grains[{i}]: its surface moves at up to {speed:g} m/s (velocity and angular_velocity), "
                             f"above fluid.max_speed = {case.fluid.max_speed} m/s")
        for j, other in enumerate(grains[:i]):
            gap = float(np.linalg.norm(centre - np.asarray(other.centre))) - g.radius - other.radius
            if gap < 0.0:
                raise ValueError(f"grains[{i}].centre: grain {g.name!r} overlaps grains[{j}] ({other.name!r}) by "
                                 f"{-gap:.4g} m")


def _check_contact(case) -> None:
    """The contact walls: a normal, across a bounded axis, clear of every grain at the start."""
    contact, periodic = case.grain_contact, set(case.domain.periodic)
    for j, wall in enumerate(contact.walls):
        n = wall.unit_normal()
        if not np.any(n):
            raise ValueError(f"grain_contact.walls[{j}].normal = {list(wall.normal)}: must not be zero")
        across = [axis for axis in periodic if abs(n[axis]) > 1e-9]
        if across:
            raise ValueError(f"grain_contact.walls[{j}].normal = {list(wall.normal)} has a component along the "
                             f"periodic axis {across[0]}: a wall plane must lie along the periodic axes")
        for i, g in enumerate(case.grains):
            distance = float((np.asarray(g.centre) - np.asarray(wall.point)) @ n)
            if distance < g.radius:
                raise ValueError(f"grains[{i}].centre = {list(g.centre)}: grain {g.name!r} (radius {g.radius:g} m) "
                                 f"lies {distance:.4g} m from grain_contact.walls[{j}] (on its side of the normal), "
                                 "overlapping it; move the grain or the wall")


def check_contact_duration(case, grain: np.ndarray, dt: float) -> None:
    """ValueError naming grain_contact.stiffness when a contact, pi sqrt(m / k) with m the reduced mass of a grain
    pair or a grain's mass on a wall (kg, as the engine counts them: rho_k N_k dx^D from the carved lattice, grain
    (n,) the particles' grain index), lasts fewer than CONTACT_STEPS of the run's largest step dt (s)."""
    contact = case.grain_contact
    if contact is None or contact.stiffness is None:
        return
    masses = [g.density * np.count_nonzero(grain == k) * case.numerics.dx ** case.dimension
              for k, g in enumerate(case.grains)]
    pairs = [a * b / (a + b) for i, a in enumerate(masses) for b in masses[:i]]
    lightest = min(pairs + (masses if contact.walls else []), default=None)
    if lightest is None:
        return
    duration = math.pi * math.sqrt(lightest / contact.stiffness)
    if duration < CONTACT_STEPS * dt:
        raise ValueError(f"grain_contact.stiffness = {contact.stiffness:g} N/m makes a contact of pi sqrt(m / k) = "
                         f"{duration:.3g} s (m = {lightest:.3g} kg), {duration / dt:.3g} steps of the run's largest "
                         f"step {dt:.3g} s; the contact needs at least {CONTACT_STEPS}: at most "
                         f"{math.pi ** 2 * lightest / (CONTACT_STEPS * dt) ** 2:.3g} N/m")


def has_solid(case) -> bool:
    """Whether a material of the case is a solid (johnson_cook), which the grains touch through eq. G8."""
    return any(m.model == "johnson_cook" for m in case.materials)


def grain_contact_deck(case, scale: float) -> dict | None:
    """The deck's grain_contact object (None: no contact): the case's [grain_contact] and, with grains beside a
    solid, eq. G8's spring solid_stiffness_factor x scale (scale: rho0 c_L^2 dx of the stiffest material, N/m)."""
    contact = case.grain_contact or GrainContact()
    solid = contact.solid_stiffness_factor * scale if case.grains and has_solid(case) else None
    deck = contact.deck(solid)
    return deck or None


def carve_grains(grains, positions: np.ndarray, kind: np.ndarray, velocities: np.ndarray, dx: float):
    """The fluid sites (kind 0) inside each grain become its particles: returns (kind, velocities, grain index (n,)
    int32, -1 for the others). ValueError naming the grain when it holds no fluid site."""
    kind, velocities = kind.copy(), velocities.copy()
    grain = np.full(len(kind), -1, dtype=np.int32)
    for i, g in enumerate(grains):
        mine = g.inside(positions) & (kind == 0)
        if not mine.any():
            raise ValueError(f"grains[{i}] ({g.name!r}): no fluid site of the lattice (dx = {dx:g} m) lies inside "
                             f"it; the grain must sit in the fluid and be wider than dx")
        kind[mine] = BODY
        grain[mine] = i
        velocities[mine] = g.rigid_velocity(positions[mine])
    return kind, velocities, grain


def grain_decks(case, masses: np.ndarray, kind: np.ndarray, grain: np.ndarray, rho_fluid: float):
    """(the fluid's body force m/s^2 or None, the deck's grain objects). Without a balanced mean weight each grain
    takes the case's body force; with it the fluid takes g (1 - rho_m / rho_f) and grain k g (1 - rho_m / rho_k),
    rho_m = (M_f + sum M_k) / (V_f + sum V_k) from the particles (M_k = rho_k N_k dx^3 as the engine counts it)."""
    on = case.physics.body_force is not None and "body_force" in case.physics.terms
    g = np.asarray(case.physics.body_force, dtype=float) if on else None
    fluid_force = None if g is None else g
    forces = [np.zeros(3) if g is None or case.physics.body_force_on == "fluids" else g for _ in case.grains]
    if case.physics.balance_mean_weight:
        fluid_mass = float(masses[kind == 0].sum())
        volume = fluid_mass / rho_fluid
        mass = fluid_mass
        for k, gr in enumerate(case.grains):
            v = float(masses[grain == k].sum()) / rho_fluid  # the grain's particles carry the fluid's mass
            volume, mass = volume + v, mass + gr.density * v
        rho_m = mass / volume
        fluid_force = g * (1.0 - rho_m / rho_fluid)
        forces = [g * (1.0 - rho_m / gr.density) for gr in case.grains]
    decks = [{"name": gr.name, "density": float(gr.density), "velocity": [float(c) for c in gr.velocity],
              "angular_velocity": [float(c) for c in gr.angular_velocity], "body_force": [float(c) for c in f]}
             | ({"contact_radius": float(gr.radius)} if case.grain_contact is not None or has_solid(case) else {})
             for gr, f in zip(case.grains, forces)]
    return (None if fluid_force is None else tuple(float(c) for c in fluid_force)), decks
