"""What a case may ask of a machine: step counts, records, particle memory and where probes may sit.

These checks run at validation, before any scene is built or engine started. Each raises ValueError
(which the loader turns into a CaseError) naming the keys, their values and what is allowed:

- the time steps of a run: at most MAX_STEPS (a smaller step, or a longer run, overflows the engines' step
  counters or runs for centuries);
- records of a series (an output interval): at most MAX_RECORDS, and for SPH never more often than a fixed
  step numerics.dt (the DEM engines record every step when asked for less, and a step derived from the
  physics is not the user's to compare with); particle frames: at most MAX_FRAMES;
- an SPH scene's particles (from the blocks and dx) and a drag-finishing bed's balls: at most what the
  machine's memory holds, estimated before anything is allocated;
- SPH probes, inlets, outlets and flow planes: inside the domain box.
"""

from __future__ import annotations

import math
import os

from orchestrator.case.common import rayleigh_timestep
from orchestrator.humanize import byte_size

#: Most time steps a run may plan, -.
MAX_STEPS = 1_000_000_000
#: Most records of a time series (output.record_interval, output.series_interval), -.
MAX_RECORDS = 10_000_000
#: Most particle frames of a run (output.frame_interval), -.
MAX_FRAMES = 100_000
#: Most checkpoints of a run (output.checkpoint_interval; each saves the whole scene), -.
MAX_CHECKPOINTS = 10_000
#: Memory one SPH particle takes during a run, bytes: the orchestrator's arrays (positions, velocities, masses,
#: densities, kinds, with the copies made while building the lattice), the engine's state and its neighbour
#: lists (about 70 neighbours in 3D at h = 1.3 dx), rounded up.
BYTES_PER_SPH_PARTICLE = 1024
#: Memory one DEM ball takes in an engine (Yade's body, state and shape objects with about six interactions,
#: LIGGGHTS's per-atom arrays and contact history), rounded up, bytes.
BYTES_PER_DEM_PARTICLE = 4096


def machine_memory() -> int | None:
    """Physical memory of this machine, bytes (os.sysconf), or None where it is not known."""
    try:
        pages, size = os.sysconf("SC_PHYS_PAGES"), os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None
    return pages * size if pages > 0 and size > 0 else None


def check_memory(key: str, particles: float, per_particle: int, allowed: str) -> None:
    """Refuse a scene whose particles (at per_particle bytes each) need more than this machine's memory."""

    memory = machine_memory()
    need = particles * per_particle
    if memory is not None and need > memory:
        raise ValueError(f"{key} gives about {particles:.3g} particles, which need about {byte_size(need)} (at "
                         f"{per_particle} B each) while this machine has {byte_size(memory)} of memory; allowed: "
                         f"{allowed}")


def check_steps(duration_key: str, duration: float, step_key: str, step: float) -> None:
    """Refuse a run of duration (s) in steps of step (s) that needs more than MAX_STEPS steps."""
    steps = duration / step
    if not steps <= MAX_STEPS:
        raise ValueError(f"{duration_key} = {duration:g} s in steps of {step_key} = {step:.6g} s is "
                         f"{_count(steps)} time steps; allowed: at most {MAX_STEPS:.0e} (a longer step or a shorter run)")


def check_interval(key: str, interval: float, duration_key: str, duration: float, step_key: str | None = None,
                   step: float | None = None, most: int = MAX_RECORDS, what: str = "records") -> None:
    """Refuse an output interval (s) that gives more than `most` records over duration (s), or one below the
    time step (s; when step is given)."""
    count = duration / interval
    if not count <= most:
        raise ValueError(f"{key} = {interval:g} s over {duration_key} = {duration:g} s is {_count(count)} {what}; "
                         f"allowed: at most {most:.0e}, i.e. {key} >= {duration / most:.3g} s")
    if step is not None and interval < step * (1 - 1e-9):
        raise ValueError(f"{key} = {interval:g} s is below the time step ({step_key} = {step:.6g} s); allowed: "
                         f"{key} >= {step_key} (nothing happens between two steps)")


def _count(value: float) -> str:
    return f"{value:.3g}" if math.isfinite(value) else "more than 1e308"


# ---------------------------------------------------------------------------------------------------- DEM
def check_drag_finishing(case) -> None:
    """Memory of the bed, step counts and the record interval of a drag-finishing case."""

    check_memory(f"media.count = {case.media.count}", case.media.count, BYTES_PER_DEM_PARTICLE, "fewer balls")

    media = case.media
    r_min = media.radius - (2.0 if media.distribution == "normal" else 1.0) * media.radius_spread
    material = case.materials[media.material]
    step = case.numerics.timestep_factor * rayleigh_timestep(r_min, material, case.numerics.stiffness_scale)
    settle = case.settling_timestep_factor * rayleigh_timestep(r_min, material, case.settling_stiffness_scale)
    step_key = "the time step (numerics.timestep_factor x the Rayleigh step of the smallest ball)"
    check_steps("process.duration", case.process.duration, step_key, step)
    check_interval("output.record_interval", case.output.record_interval, "process.duration", case.process.duration,
                   "numerics.timestep_factor x the Rayleigh step", step)
    checkpoints = getattr(case.output, "checkpoint_interval", None)
    if checkpoints is not None:  # each writes the whole scene: a few thousand at most
        check_interval("output.checkpoint_interval", checkpoints, "process.duration", case.process.duration,
                       most=MAX_CHECKPOINTS, what="checkpoints")
    settle_time = case.settling.max_time + case.settling.relax_time + case.settling.stiffen_time
    check_steps("settling.max_time + relax_time + stiffen_time", settle_time,
                "the settling time step (settling.timestep_factor x the Rayleigh step at settling.stiffness_scale)",
                settle)


# ---------------------------------------------------------------------------------------------------- SPH
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
