"""orchestrator rheometry CASE [--frequencies ...]: a frequency sweep of the numerical rheometer."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from orchestrator.cli.common import check_options
from orchestrator.workflows.rheometry import format_sweep, json_sweep, plot_sweep, run_sweep


def add_parser(sub) -> None:
    p = sub.add_parser(
        "rheometry", help="frequency sweep of the numerical rheometer: G'(omega), G''(omega) against Maxwell",
        description="Run a rheometer case (kind rheometer: a Lees-Edwards SPH sample of a multi-mode PTT fluid in "
        "oscillatory shear gamma_A sin(omega t); Nutto et al.) at each angular frequency, in parallel on "
        "the sph executable; fit eq. 17, tau = G' gamma_A sin(omega t) + G'' gamma_A cos(omega t), over the cycles "
        "after the start-up; print omega (rad/s), G' and G'' (Pa) against the multi-mode Maxwell forms (eqs. "
        "18-19) with their relative errors, the sample's mass-scaled density (kg/m^3), step (s), steps and engine "
        "wall time (s); save rheometry.png (log axes, as the paper's Figs. 2-3). Exit code 1 if a run fails.")
    p.add_argument("case", type=Path, help="a rheometer case file (e.g. cases/rheometry/mf20_table3.toml)")
    p.add_argument("--frequencies", type=float, nargs="+", metavar="OMEGA",
                   help="angular frequencies, rad/s (default: the case's [sweep] frequencies, else shear.omega)")
    p.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                   help="override a case value at every frequency, SI units, e.g. --set numerics.quasi_static=40")
    p.add_argument("--out", metavar="DIR", help="run directories and the PNG (default: runs/rheometry-<time>)")
    p.add_argument("--workers", type=int, metavar="N", help="parallel runs (default: the number of cores)")
    p.add_argument("--timeout", type=float, metavar="SECONDS", help="wall-time limit of each run, s")
    p.add_argument("--json", action="store_true", help="print the points and the sweep's wall time as JSON "
                   "(SI units; null where not measured)")
    p.set_defaults(func=cmd_rheometry)


def cmd_rheometry(args) -> int:
    """Run the sweep, print its table (or JSON), write rheometry.png; exit 1 when a point failed."""
    check_options(args)

    def done(point, count, total):
        print(f"rheometry: {count}/{total} omega = {point.omega:g} rad/s: {point.status}", file=sys.stderr,
              flush=True)

    folder, points, wall = run_sweep(args.case, args.frequencies, args.out, args.overrides, args.workers,
                                     args.timeout, done)
    png = plot_sweep(args.case, points, folder / "rheometry.png", args.overrides)
    if args.json:
        print(json.dumps(json_sweep(points, wall)))
    else:
        print(format_sweep(points))
        print(f"sweep: {len(points)} frequencies in {wall:.1f} s of wall time")
        print(f"figure       {png}")
        print(f"runs         {folder}")
    return 0 if all(p.status == "ok" for p in points) else 1
