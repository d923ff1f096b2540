"""orchestrator bench sph: particle-steps per second of the sph executable and its peers (PySPH, LAMMPS SPH)."""

from __future__ import annotations

import json
import sys

from orchestrator.cli.common import check_options
from orchestrator.errors import OrchestratorError
from orchestrator.workflows.bench_sph import format_report, json_report, run_bench


def add_parser(sub) -> None:
    bench = sub.add_parser(
        "bench", help="speed of an engine: particle-steps per second on standard scenes",
        description="bench sph: particle-steps per second (particles x steps / wall s of the engine's run, "
        "its set-up included, and per CPU second) of the sph executable on these scenes, each on 1 thread and "
        "on 2 threads (idle threads spinning briefly, numerics.thread_wait = spin, and sleeping at once, passive): "
        "a 2D dam break (PySPH's dam_break_2d: 2278 fluid particles in a walled tank, dx = 0.03 m, h = 1.3 dx, "
        "--steps-2d steps); a 3D dam break (a slab periodic across the flow, 25 360 particles, dx = 0.02 m, "
        "h = 1.3 dx, fixed dt = 0.25 h / c0, --steps-3d steps); a periodic 3D block without walls (40 x 40 x 16 "
        "particles at dx = 1 mm, h = 1.5 dx, Tait EOS c0 = 10 m/s, artificial viscosity alpha = 0.1, dt = 2 us, "
        "a stepped sine shear flow of 1 m/s, 2.5 x --steps-3d steps); "
        "and the material models side by side, a 2D Lees-Edwards shear cell (100 x 100 particles, dx = 0.01 m, "
        "shear rate 1/s, 300 steps) of a Newtonian fluid and of a PTT fluid with 1 and 5 modes. Peers on one "
        "core when installed ('make peers' puts them in .venv; a missing peer is skipped with that hint): "
        "PySPH on the 2D dam break, "
        "LAMMPS SPH on the 3D block and the 3D dam break: the same sph_flow cases, each engine's input written by "
        "its adapter as for 'orchestrator run CASE --engine sph|lammps'. Prints a "
        "row per run (the fastest of --repeat rounds) with wall and CPU s, particle-steps per second (M = 10^6 "
        "per s) and mean neighbours within 2h per fluid particle, then the 2-thread speed-ups (wall-time "
        "ratios), the PTT / Newtonian cost ratios and the ratios sph / peer per CPU second and per wall second. "
        "Run it on an otherwise idle machine: spinning threads on shared cores run many times slower.")
    bench.add_argument("suite", choices=["sph"], help="which engine: sph")
    bench.add_argument("--steps-2d", type=int, default=2000, metavar="N", help="steps of the 2D runs (default 2000)")
    bench.add_argument("--steps-3d", type=int, default=200, metavar="N", help="steps of the 3D dam break (default 200; the 3D block runs 2.5 x as many)")
    bench.add_argument("--repeat", type=int, default=3, metavar="N",
                       help="make every run N times, round after round, and keep the fastest of each (default 3)")
    bench.add_argument("--no-pysph", action="store_true", help="skip PySPH even when it is installed")
    bench.add_argument("--out", metavar="DIR", help="run directories (default: runs/bench-sph-<time>)")
    bench.add_argument("--json", action="store_true",
                       help="print one JSON object: rows (scene, engine, threads, particles, fluid, steps, neighbours, "
                       "wall_s, cpu_s, particle_steps_per_s, per_core, status, note, wait, repeats) and summary (speed-ups, "
                       "ratios)")
    bench.set_defaults(func=cmd_bench)


def cmd_bench(args) -> int:

    for option, value, most in (("--steps-2d", args.steps_2d, 10**9), ("--steps-3d", args.steps_3d, 10**9),
                                ("--repeat", args.repeat, 1000)):
        if not 1 <= value <= most:
            raise OrchestratorError(f"{option} {value}: allowed: 1 to {most}")
    check_options(args)

    def done(row):
        wait = f" ({row.wait})" if row.wait != "-" else ""
        print(f"bench: {row.scene} on {row.engine}, {row.threads} thread(s){wait}: {row.status}", file=sys.stderr,
              flush=True)

    rows = run_bench(args.out, steps_2d=args.steps_2d, steps_3d=args.steps_3d,
                     with_pysph=False if args.no_pysph else None, on_done=done, repeats=args.repeat)
    if args.json:
        print(json.dumps(json_report(rows)))
    else:
        print(format_report(rows))
    return 0 if all(row.status == "ok" for row in rows) else 1
