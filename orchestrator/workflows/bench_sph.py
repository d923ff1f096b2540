"""`orchestrator bench sph`: how fast the sph executable steps particles.

Particle-steps per second (particles x steps / the engine's loop wall time)
of a 2D dam break and a 3D dam break (a slab periodic across the flow), on
1 OpenMP thread and on 2, the 2-thread runs once with idle threads spinning
briefly (numerics.thread_wait = "spin", for an otherwise idle machine) and
once sleeping at once ("passive", the default, safe on shared cores), with
the mean number of neighbours per fluid particle; and, in the same run, the same 2D dam break in PySPH when PySPH is
importable, with the ratio of the two per core.

The 2D dam break is PySPH's own example (pysph/examples/dam_break_2d.py, its
default WCSPH scheme): a water column of 34 x 67 particles (1.02 m x 2.01 m)
at dx = 0.03 m in a 4 m tank held by four layers of boundary particles,
h = 1.3 dx (Wendland C2, support 2h), c0 = 10 sqrt(2 g 2 m), alpha = 0.1,
gravity. Our run goes through the sph_flow case and the sph adapter, with the
same dx, h, kernel, fluid particle count and number of steps. Both codes
evaluate the rates once per step (predict-evaluate-correct).

The material models side by side: one 2D Lees-Edwards shear cell (100 x 100
particles, steady shear) of a Newtonian fluid (Morris viscosity), a PTT
fluid of 1 mode and of 5 modes (the sph_flow kind's bench_scenes.py), the same
particles and step, on the same thread counts.

The periodic 3D block (the sph_flow kind's block_3d_case: 25,600 particles,
no walls, h = 1.5 dx, artificial viscosity, 2.5 x the 3D steps) on the same
thread counts, and, when LAMMPS is installed, LAMMPS SPH on one core on the
block and on the 3D dam break: the same cases, through LAMMPS's sph_flow
adapter, with the ratios per CPU second (bench_lammps).

Every run goes through `run_case`, the path of `orchestrator run` (case ->
scene -> the engine's adapter -> its input), and writes its run directory.
"""

from __future__ import annotations

import importlib.util
import json
import math
import os
import subprocess
import sys
from dataclasses import asdict
from importlib.metadata import version
from pathlib import Path

from orchestrator.engines import get_engine
from orchestrator.workflows import bench_lammps
from orchestrator.workflows.base import Workflow
from orchestrator.workflows.bench_lammps import is_lammps, report_lines
from orchestrator.workflows.bench_lammps import summary as lammps_summary
from orchestrator.workflows.bench_scenes import (  # noqa: F401 - the bench's public names
    BenchRow,
    bench_cases,
    mean_neighbours,
    run_bench_case,
)

THREADS = (1, 2)
#: How the 2-thread runs wait (numerics.thread_wait); a 1-thread run never waits.
WAITS = ("spin", "passive")


def _runs(threads) -> list[tuple[int, str]]:
    """(threads, thread_wait) of the timed runs of one scene: one thread, then each wait on more."""
    return [(n, w) for n in threads for w in (WAITS if n > 1 else ("-",))]


def pysph_available() -> bool:
    """True when PySPH imports in this Python (make pysph installs it into .venv)."""

    return importlib.util.find_spec("pysph") is not None


#: Runs PySPH's dam_break_2d application in a child Python and prints one JSON line: the solver loop's
#: wall and CPU time (s), particle counts and mean neighbours within 2h per fluid particle at the start.
_PYSPH_DRIVER = """
import json, sys, time
import numpy as np
from scipy.spatial import cKDTree
from pysph.examples.dam_break_2d import DamBreak2D
app = DamBreak2D()
app.setup(sys.argv[1:])
arrays = {pa.name: pa for pa in app.particles}
xy = np.vstack([np.column_stack([pa.x, pa.y]) for pa in app.particles])
fluid = np.column_stack([arrays["fluid"].x, arrays["fluid"].y])
support = 2.0 * float(arrays["fluid"].h[0])
neighbours = float(np.mean(cKDTree(xy).query_ball_point(fluid, support, return_length=True)) - 1.0)
wall, cpu = time.perf_counter(), time.process_time()
app.solver.solve(False)
wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
print("BENCH " + json.dumps({"wall_s": wall, "cpu_s": cpu, "steps": int(app.solver.count),
      "particles": int(len(xy)), "fluid": int(len(fluid)), "neighbours": neighbours}))
"""


def run_pysph(steps: int, out_dir: Path, timeout_s: float = 1800.0) -> BenchRow:
    """PySPH's dam_break_2d for `steps` steps on one core (no OpenMP), output disabled.

    Timed around its solver loop only (wall and CPU time of the child
    process); the set-up, which compiles the kernels on a first run and
    caches them under ~/.pysph, is left out.
    """

    out_dir.mkdir(parents=True, exist_ok=True)
    command = [sys.executable, "-c", _PYSPH_DRIVER, "--max-steps", str(steps), "--disable-output", "--no-openmp",
               "-q", "-d", str(out_dir / "output")]
    env = {**os.environ, "OMP_NUM_THREADS": "1"}
    try:
        proc = subprocess.run(command, capture_output=True, text=True, env=env, timeout=timeout_s, cwd=out_dir)
    except subprocess.TimeoutExpired:
        return _failed_pysph(steps, f"PySPH did not finish within {timeout_s:g} s")
    (out_dir / "pysph.log").write_text(proc.stdout + proc.stderr)
    line = next((ln for ln in proc.stdout.splitlines() if ln.startswith("BENCH ")), None)
    if proc.returncode != 0 or line is None:
        last = (proc.stderr or proc.stdout).strip().splitlines()[-1:] or ["no output"]
        return _failed_pysph(steps, f"PySPH exited with code {proc.returncode}: {last[0]} (log: {out_dir}/pysph.log)")
    got = json.loads(line.removeprefix("BENCH "))
    work = got["particles"] * got["steps"]
    return BenchRow("pysph_dam_break_2d", f"pysph {_pysph_version()}", 1, got["particles"], got["fluid"],
                    got["steps"], got["neighbours"], got["wall_s"], got["cpu_s"], work / got["wall_s"],
                    work / got["cpu_s"])


def _failed_pysph(steps: int, note: str) -> BenchRow:
    nan = math.nan
    return BenchRow("pysph_dam_break_2d", "pysph", 1, 0, 0, steps, nan, nan, nan, nan, nan, "failed", note)


def _pysph_version() -> str:
    try:

        return version("pysph")
    except Exception:  # noqa: BLE001 - a version is only a label here
        return ""


def run_bench(out_dir: Path | None = None, steps_2d: int = 2000, steps_3d: int = 200, threads=THREADS,
              with_pysph: bool | None = None, on_done=None, repeats: int = 1,
              with_lammps: bool | None = None, steps_shear: int = 300) -> list[BenchRow]:
    """Every timed run: 2D and 3D dam breaks on one thread and on each larger thread count with each
    wait (WAITS), then PySPH's 2D dam break if importable.

    repeats: each run is made this many times, the rounds one after the other (so a slow spell of a
    shared or virtual machine hits every configuration alike), and the fastest of each is kept, as
    timeit does (its `repeats` field says of how many). steps_shear: steps of the shear-cell rows (Newtonian,
    PTT 1 mode, PTT 5 modes). with_pysph: None = when importable;
    on_done(row) is called after each run. with_lammps: our 3D block (bench_lammps) always, LAMMPS on
    the block and the 3D dam break when True (None = when installed; False = neither, nor our block).
    """

    if with_pysph is None:
        with_pysph = pysph_available()
    configs: list = []  # one timed run each: a function of nothing that returns its BenchRow

    def jobs(folder: Path):
        get_engine("sph").check_available()  # EngineNotFound, with what to do, before anything runs (after a bad --out)
        cases = bench_cases("sph")
        for name, make, steps in (("2d", cases.dam_break_2d_case, steps_2d), ("3d", cases.dam_break_3d_case, steps_3d)):
            for n, wait in _runs(threads):
                case = make(steps, n, thread_wait=wait if n > 1 else "passive")
                path = folder / f"dam_break_{name}_{n}t{'' if n == 1 else '_' + wait}"
                configs.append(lambda case=case, path=path: run_bench_case(case, path))
        for model in cases.SHEAR_CELL_MODELS:
            for n, wait in _runs(threads):
                case = cases.shear_cell_case(steps_shear, n, model, thread_wait=wait if n > 1 else "passive")
                path = folder / f"shear_cell_{model}_{n}t{'' if n == 1 else '_' + wait}"
                configs.append(lambda case=case, path=path: run_bench_case(case, path))
        if with_pysph:
            configs.append(lambda: run_pysph(steps_2d, folder / "pysph_dam_break_2d"))
        if with_lammps is not False:
            use = bench_lammps.lammps_available() if with_lammps is None else with_lammps
            configs.extend(bench_lammps.jobs(folder, steps_3d, _runs(threads), use))
        # the rounds one after the other: every configuration once per round
        return [(_timed, (config,)) for _ in range(max(1, repeats)) for config in configs]

    def done(row, _done, _total):
        if on_done is not None:
            on_done(row)

    _, rows = Workflow("bench-sph", jobs, parallel=False).run(out_dir, on_done=done)
    best: list[BenchRow | None] = [None] * len(configs)
    for k, row in enumerate(rows):
        k %= len(configs)
        if best[k] is None or _faster(row, best[k]):
            row.repeats = (best[k].repeats if best[k] else 0) + 1
            best[k] = row
        else:
            best[k].repeats += 1
    return best


def _timed(config) -> BenchRow:
    """One timed run (config() -> its BenchRow)."""
    return config()


def _faster(row: BenchRow, than: BenchRow) -> bool:
    """row ran, and faster than `than` (or `than` failed)."""
    if row.status != "ok":
        return False
    return than.status != "ok" or row.particle_steps_per_s > than.particle_steps_per_s


def summary(rows: list[BenchRow]) -> dict:
    """Ratios: 2 threads over 1 per scene (wall-time speed-up; speedup_2_threads_<scene> with spinning
    threads, speedup_2_threads_passive_<scene> with passive ones), and ours over PySPH on the 2D dam break.

    ratio_per_core: our 1-thread particle-steps per CPU second over PySPH's (CPU time is the steadier
    measure on a shared machine); ratio_wall: the same over loop wall time; *_fluid: counting fluid
    particles only (the two codes' wall layers differ).
    """
    out: dict = {}
    by = {(r.scene, r.threads, r.wait): r for r in rows if r.status == "ok" and not is_lammps(r)}
    for scene in dict.fromkeys(r.scene for r in rows if r.engine.startswith("sph")):
        one = by.get((scene, 1, "-"))
        for wait, key in (("spin", f"speedup_2_threads_{scene}"), ("passive", f"speedup_2_threads_passive_{scene}")):
            two = by.get((scene, 2, wait))
            if one and two:
                out[key] = two.particle_steps_per_s / one.particle_steps_per_s
    ours, theirs = by.get(("bench_dam_break_2d", 1, "-")), by.get(("pysph_dam_break_2d", 1, "-"))
    if ours and theirs:
        fluid = (ours.fluid / ours.particles) / (theirs.fluid / theirs.particles)
        out["ratio_per_core"] = ours.per_core / theirs.per_core
        out["ratio_per_core_fluid"] = out["ratio_per_core"] * fluid
        out["ratio_wall"] = ours.particle_steps_per_s / theirs.particle_steps_per_s
        out["ratio_wall_fluid"] = out["ratio_wall"] * fluid

    newtonian = by.get(("bench_shear_cell_newtonian", 1, "-"))
    for model in bench_cases("sph").SHEAR_CELL_MODELS:
        row = by.get((f"bench_shear_cell_{model}", 1, "-"))
        if newtonian and row and model != "newtonian":
            out[f"shear_cell_{model}_over_newtonian"] = row.particle_steps_per_s / newtonian.particle_steps_per_s

    out.update(lammps_summary(rows))
    return out


def json_report(rows: list[BenchRow]) -> dict:
    """{"rows": [...], "summary": {...}} with NaN as None (what --json prints)."""
    def clean(value):
        return None if isinstance(value, float) and not math.isfinite(value) else value

    return {"rows": [{k: clean(v) for k, v in asdict(r).items()} for r in rows],
            "summary": {k: clean(v) for k, v in summary(rows).items()}}


def format_report(rows: list[BenchRow]) -> str:
    """Plain-text table of the runs (each the fastest of `best of` runs) and the ratios."""
    header = ("scene", "engine", "threads", "wait", "particles", "fluid", "steps", "neighbours", "wall_s", "cpu_s",
              "particle-steps/s", "per core (cpu)", "best of", "status")
    table = [[r.scene, r.engine, str(r.threads) + (f" x {r.ranks} ranks" if r.ranks > 1 else ""), r.wait, str(r.particles), str(r.fluid), str(r.steps),
              _fmt(r.neighbours, ".1f"), _fmt(r.wall_s, ".2f"), _fmt(r.cpu_s, ".2f"), _rate(r.particle_steps_per_s),
              _rate(r.per_core), str(r.repeats), r.status] for r in rows]
    widths = [max(len(h), *(len(t[i]) for t in table)) if table else len(h) for i, h in enumerate(header)]
    lines = ["  ".join(h.ljust(w) for h, w in zip(header, widths))]
    lines += ["  ".join(c.ljust(w) for c, w in zip(t, widths)) for t in table]
    lines += [f"note: {r.scene} ({r.engine}, {r.threads} thread): {r.note}" for r in rows if r.note]
    s = summary(rows)
    for key, value in s.items():
        if key.startswith("speedup_2_threads_passive_"):
            lines.append(f"{key.removeprefix('speedup_2_threads_passive_')}: 2 threads sleeping when idle (passive, "
                         f"for shared cores) run {value:.2f} x as fast as 1")
        elif key.startswith("speedup"):
            lines.append(f"{key.removeprefix('speedup_2_threads_')}: 2 threads spinning briefly when idle (spin, "
                         f"for an otherwise idle machine) run {value:.2f} x as fast as 1")
    for model in bench_cases("sph").SHEAR_CELL_MODELS:
        if f"shear_cell_{model}_over_newtonian" in s:
            lines.append(f"shear cell, 1 thread: {model.replace('_', ' ')} runs {s[f'shear_cell_{model}_over_newtonian']:.2f} "
                         "x the particle-steps/s of the Newtonian fluid (same particles and step)")
    if "ratio_per_core" in s:
        lines.append(f"2D dam break, 1 thread, sph / PySPH: {s['ratio_per_core']:.2f} per CPU second "
                     f"({s['ratio_per_core_fluid']:.2f} counting fluid particles only), {s['ratio_wall']:.2f} per "
                     "wall second; both codes evaluate the rates once per step")
    elif not any(r.engine.startswith("pysph") for r in rows):
        lines.append("PySPH is not installed in this Python ('make pysph' installs it into .venv): no side-by-side")

    lines += report_lines(rows, s)
    return "\n".join(lines)


def _fmt(value, spec: str) -> str:
    return "-" if value is None or (isinstance(value, float) and not math.isfinite(value)) else format(value, spec)


def _rate(value) -> str:
    return "-" if value is None or not math.isfinite(value) else f"{value / 1e6:.2f} M"
