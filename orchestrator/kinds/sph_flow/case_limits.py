"""What an SPH flow case may ask of a machine: its particles' memory, its step and record counts, and probes,
inlets, outlets and flow planes inside the domain box (the limits of orchestrator.case.limits applied to the sph_flow
keys; a fixed step numerics.dt also bounds the record intervals from below)."""

from __future__ import annotations

import math

from orchestrator.case.limits import MAX_FRAMES, check_interval, check_memory, check_steps

#: Memory one SPH particle takes during a run, bytes: the orchestrator's arrays (positions, velocities, masses,
#: densities, kinds, with the copies made while building the lattice), the engine's state and its neighbour
#: lists (about 70 neighbours in 3D at h = 1.3 dx), rounded up.
BYTES_PER_SPH_PARTICLE = 1024


def sph_timestep(case, c0: float | None = None, viscosity: float | None = None) -> float:
    """The fixed step numerics.dt, or the adaptive step at rest (the largest it takes), s: cfl h / c0, limited
    by the viscous (factor h^2 / nu) and body-force (factor sqrt(h / |g|)) bounds. c0 (m/s) and viscosity
    (kinematic, m^2/s) default to [fluid]'s; a case with several materials passes their largest, as the engine
    takes them."""
    numerics, h = case.numerics, case.numerics.h
    c0 = case.fluid.c0 if c0 is None else c0
    viscosity = case.fluid.viscosity if viscosity is None else viscosity
    if numerics.dt is not None:
        return numerics.dt
    dt = numerics.adaptive["cfl"] * h / c0
    if viscosity is not None:
        dt = min(dt, numerics.adaptive["viscous"] * h * h / viscosity)
    force = case.physics.body_force
    if force is not None and any(force):
        dt = min(dt, numerics.adaptive["force"] * math.sqrt(h / math.sqrt(sum(c * c for c in force))))
    return dt


def sph_particle_estimate(case) -> float:
    """Upper bound of the particles the blocks put on the lattice (overlaps counted twice), as a float (it may
    be far beyond any integer a machine holds)."""
    dx = case.numerics.dx
    total = 0.0
    for block in case.blocks:
        total += math.prod(max(1.0, round((hi - lo) / dx)) for lo, hi in zip(block.lo, block.hi))
    return total


def check_sph(case, c0: float | None = None, viscosity: float | None = None) -> None:
    """Memory of the particles, step and record counts, and probes/patches inside the domain of an SPH case
    (c0, viscosity: see sph_timestep)."""
    check_memory(f"numerics.dx = {case.numerics.dx:g} m over the blocks", sph_particle_estimate(case),
                 BYTES_PER_SPH_PARTICLE, "a larger dx or smaller blocks")
    duration = case.simulation.duration
    dt = sph_timestep(case, c0, viscosity)
    fixed = case.numerics.dt is not None
    step_key = "numerics.dt" if fixed else "the adaptive step at rest (cfl h / c0 and the viscous and force bounds)"
    if case.numerics.max_steps is None:  # a cap (at most MAX_STEPS) ends the run before the duration
        check_steps("simulation.duration", duration, step_key, dt)
    check_interval("output.frame_interval", case.output.frame_interval, "simulation.duration", duration,
                   step_key if fixed else None, dt if fixed else None, most=MAX_FRAMES, what="particle frames")
    if case.output.series_interval is not None:
        check_interval("output.series_interval", case.output.series_interval, "simulation.duration", duration,
                       step_key if fixed else None, dt if fixed else None)
    _check_inside(case)


def _check_inside(case) -> None:
    """Probes, inlets, outlets and flow planes lie in the domain box (to a millionth of its size)."""
    domain = case.domain
    margin = 1e-6 * max(hi - lo for lo, hi in zip(domain.lo, domain.hi))
    box = f"[{list(domain.lo)}, {list(domain.hi)}]"
    points = [(f"output.probes[{i}].point", p.point) for i, p in enumerate(case.output.probes)]
    for group, items in (("inlets", case.inlets), ("outlets", case.outlets),
                         ("output.flow_planes", case.output.flow_planes)):
        points += [(f"{group}[{i}].center", p.center) for i, p in enumerate(items)]
    for key, point in points:
        if len(point) == domain.dimension and not domain.contains(point, margin):
            raise ValueError(f"{key} = {list(point)} lies outside the domain box {box}; allowed: a point inside it "
                             "(outside there is no fluid to measure)")
