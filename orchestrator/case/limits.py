"""What a case may ask of a machine: step counts, records and particle memory.

These checks run at validation, before any scene is built or engine started; each kind's case model calls them
with its own keys (kinds/<kind>/case*.py). Each raises ValueError (which the loader turns into a CaseError) naming
the keys, their values and what is allowed:

- the time steps of a run: at most MAX_STEPS (a smaller step, or a longer run, overflows the engines' step
  counters or runs for centuries);
- records of a series (an output interval): at most MAX_RECORDS, and never more often than the time step when
  the caller passes it; particle frames: at most MAX_FRAMES; checkpoints: at most MAX_CHECKPOINTS;
- a scene's particles: at most what the machine's memory holds (check_memory), estimated before anything is
  allocated.
"""

from __future__ import annotations

import math
import os

from orchestrator.humanize import byte_size

#: Most time steps a run may plan, -.
MAX_STEPS = 1_000_000_000
#: Most records of a time series (output.record_interval, output.series_interval), -.
MAX_RECORDS = 10_000_000
#: Most particle frames of a run (output.frame_interval), -.
MAX_FRAMES = 100_000
#: Most checkpoints of a run (output.checkpoint_interval; each saves the whole scene), -.
MAX_CHECKPOINTS = 10_000


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
