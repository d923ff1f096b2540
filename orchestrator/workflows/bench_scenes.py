"""What the SPH benchmarks share (ours and the peers'): the case builders a kind declares for a bench, the
neighbour count, one result row."""

from __future__ import annotations

import importlib
from dataclasses import dataclass

from orchestrator.errors import OrchestratorError
from orchestrator.kinds import get_kind, kind_names


@dataclass
class BenchRow:
    """One timed run. particle_steps_per_s: all particles x steps / loop wall time (1/s);
    per_core: the same over CPU time (1/s); neighbours: mean neighbours within 2h per fluid particle."""

    scene: str
    engine: str
    threads: int
    particles: int
    fluid: int
    steps: int
    neighbours: float
    wall_s: float
    cpu_s: float
    particle_steps_per_s: float
    per_core: float
    status: str = "ok"
    note: str = ""
    wait: str = "-"  # numerics.thread_wait of a run on several threads
    repeats: int = 1  # the row is the fastest of this many runs


def mean_neighbours(positions, kind, support: float, periodic_box=None) -> float:
    """Mean number of particles (fluid or boundary, self excluded) within `support` (m) of a fluid particle.

    periodic_box: per-axis period in m (None or 0 for a non-periodic axis).
    """
    import numpy as np
    from scipy.spatial import cKDTree

    positions = np.asarray(positions, dtype=float)
    boxsize = None
    if periodic_box is not None and any(periodic_box):
        # cKDTree wants every coordinate inside [0, L) on a periodic axis and a huge L elsewhere
        lo = positions.min(axis=0)
        positions = positions - lo
        span = positions.max(axis=0) + 2 * support
        boxsize = np.array([p if p else 10 * s for p, s in zip(periodic_box, span)])
        positions = np.mod(positions, boxsize)
    tree = cKDTree(positions, boxsize=boxsize)
    fluid = positions[np.asarray(kind) == 0]
    counts = tree.query_ball_point(fluid, support, return_length=True)
    return float(np.mean(counts) - 1.0)



def bench_cases(engine: str):
    """The module of case builders that `orchestrator bench <engine>` runs (e.g. dam_break_2d_case(steps, threads,
    thread_wait=...) -> a case dict), from the registered kind that declares it (Kind.benches); OrchestratorError
    when none does."""
    for name in kind_names():
        module = get_kind(name).benches.get(engine)
        if module:
            return importlib.import_module(module)
    raise OrchestratorError(f"bench {engine}: no registered kind declares its scenes (Kind.benches)")
