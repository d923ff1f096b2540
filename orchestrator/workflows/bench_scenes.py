"""What the SPH benchmarks share (ours and the peers'): the case builders a kind declares for a bench, the
neighbour count, one result row, and one timed run of a bench case on an engine through `run_case` (the path of
`orchestrator run`: case -> scene -> the engine's adapter)."""

from __future__ import annotations

import importlib
import math
import resource
from dataclasses import dataclass
from pathlib import Path

from orchestrator.case import load_case
from orchestrator.case.loader import to_toml
from orchestrator.errors import OrchestratorError
from orchestrator.kinds import build_scene, get_kind, kind_names
from orchestrator.run import run_case
from orchestrator.runh5 import read_run


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
    ranks: int = 1  # MPI ranks of the engine (LAMMPS), each on `threads` threads


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


def run_bench_case(case_dict: dict, out_dir: Path, engine: str | None = None,
                   mpi_ranks: int | None = None) -> BenchRow:
    """Run one bench case (a case dict) on an engine (default its case.engine) through its adapter; its BenchRow.

    Wall time: the engine's own timer (run.h5 engine_wall_time_s, s: the sph executable's from before its set-up,
    about 14 ms on 25 000 particles, to its end; LAMMPS's its run loop). CPU time: the engine's loop CPU
    time when its reader reports one (engine_cpu_time_s, s: LAMMPS's), else the CPU time of the child processes
    of the run (s). mpi_ranks: for engines that take them (LAMMPS).
    """
    out_dir.mkdir(parents=True, exist_ok=True)
    case_file = out_dir / "case.toml"
    case_file.write_text(to_toml(case_dict))
    loaded = load_case(case_file)
    case = loaded.model
    engine = engine or case.case.engine
    scene = build_scene(case)
    box = [case.domain.hi[a] - case.domain.lo[a] if a in case.domain.periodic else 0.0
           for a in range(case.dimension)]
    neighbours = mean_neighbours(scene.positions, scene.kind, 2.0 * scene.h, box)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    status, note = "ok", ""
    try:
        run_case(loaded, engine=engine, out_dir=out_dir / "run", progress=False, force=True, mpi_ranks=mpi_ranks)
    except OrchestratorError as exc:
        status, note = getattr(getattr(exc, "summary", None), "status", "failed"), str(exc).splitlines()[0]
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    children = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    try:
        attrs = read_run(out_dir / "run")["attrs"]
    except (OSError, KeyError, OrchestratorError):
        attrs = {}
        status = "failed" if status == "ok" else status
    steps = int(attrs.get("n_steps", 0))
    wall = float(attrs.get("engine_wall_time_s", math.nan))
    cpu = float(attrs.get("engine_cpu_time_s", children))
    work = scene.n_particles * steps
    threads = case.numerics.threads
    return BenchRow(case.case.name, f"{engine} {attrs.get('engine_version', '')}".strip(), threads,
                    scene.n_particles, scene.n_fluid, steps, neighbours, wall, cpu,
                    work / wall if wall > 0 else math.nan, work / cpu if cpu > 0 else math.nan, status, note,
                    case.numerics.thread_wait if threads > 1 else "-", ranks=mpi_ranks or 1)
