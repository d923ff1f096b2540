"""orchestrator verify SUITE: a verification suite of the kinds against closed forms, series and measurements, and
the time-step sweep of a suite that has one."""

from __future__ import annotations

import json
import sys
from dataclasses import asdict
from pathlib import Path

from orchestrator.cli.common import check_options, jsonable
from orchestrator.errors import OrchestratorError
from orchestrator.workflows import verify
from orchestrator.workflows.base import json_rows
from orchestrator.workflows.timestep_study import format_sweep, plot_sweep, run_timestep_sweep


def add_parser(sub) -> None:
    suites = verify.suites()
    described = " ".join(f"verify {name}: {suite.declared.description}" for name, suite in suites.items())
    parser = sub.add_parser(
        "verify", help="verification suite: every scene on every installed engine against closed forms",
        description="Run every scene of a verification suite (the case files of the kinds that declare it, in "
        "cases/verification, the folder the suite's kind ships, or --cases) on every installed engine that runs "
        "it, compare each measured quantity with its closed form, series solution or measurement, print one table "
        "(scene, engine, quantity [SI unit], value, expected, rel_error = |value - expected| / |expected|, "
        "tolerance, passed) and save the suite's picture, verify_<suite>.png. Exit code 1 if any check fails. "
        + described)
    parser.add_argument("suite", choices=list(suites), help="which suite: " + "; ".join(
        f"{name} ({', '.join(sorted(suite.members))} scenes on {', '.join(suite.engines())})"
        for name, suite in suites.items()))
    parser.add_argument("--engine", dest="engines", action="append", metavar="NAME",
                        help="run on this engine only (repeatable; default: every installed engine of the suite)")
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                        help="override a value of every scene, SI units, e.g. --set numerics.timestep_factor=0.1")
    parser.add_argument("--preset", metavar="NAME", help="run every scene with its [presets.NAME] overrides (a scene "
                        "without that preset is an error naming it); every shipped scene has quick: the test "
                        "suite's shorter runs")
    parser.add_argument("--cases", metavar="DIR", help="directory of scenes (default: the suite's own, e.g. the shipped cases/verification)")
    parser.add_argument("--out", metavar="DIR",
                        help="run directories and the PNG (default: runs/verify-<suite>-<time>)")
    parser.add_argument("--workers", type=int, metavar="N", help="parallel runs (default: the number of cores)")
    parser.add_argument("--timeout", type=float, metavar="S", help="wall-time limit of each run, s (default: the "
                        "suite's, " + ", ".join(f"{s.declared.timeout_s:g} for {n}" for n, s in suites.items())
                        + "; a run stopped by it fails its checks, run.h5 keeps what it recorded)")
    parser.add_argument("--json", action="store_true",
                        help="print the rows as a JSON list of objects with the keys scene, engine, quantity, value, "
                        "expected, rel_error, tolerance, passed (SI units; null where not measured)")
    parser.add_argument("--timestep-factors", type=float, nargs="+", metavar="F",
                        help="speed against error instead (suites with a time-step factor: " + ", ".join(
                            f"{n}, {s.declared.timestep_key}" for n, s in suites.items() if s.declared.timestep_key)
                        + "): run the suite at each factor F (fraction of the critical step, e.g. 0.01 0.05 0.2 1) "
                        "and print, per engine and F, the worst relative error, the checks passed and the engine "
                        "compute time in s; saves timestep_sweep.png")
    parser.set_defaults(func=cmd_verify)


def cmd_verify(args) -> int:
    """Run the suite (or its time-step sweep), print the table or the JSON rows, draw its picture; exit 1 when a
    check fails."""
    check_options(args)
    out_dir = Path(args.out) if args.out else verify.default_out_dir(args.suite)
    if args.timestep_factors:
        return _verify_sweep(args, out_dir)

    def done(run, count, total):
        print(f"verify: {count}/{total} {run.scene} on {run.engine}: {run.status}", file=sys.stderr, flush=True)

    timeout = {} if args.timeout is None else {"timeout_s": args.timeout}
    runs = verify.run_verification(args.suite, engines=args.engines, out_dir=out_dir, cases_dir=args.cases,
                                   overrides=args.overrides, workers=args.workers, on_done=done, preset=args.preset,
                                   **timeout)
    png = verify.draw(args.suite, runs, out_dir / f"verify_{args.suite}.png")
    rows = json_rows(runs)
    failed = sum(not row["passed"] for row in rows)
    if args.json:
        print(json.dumps(rows))
    else:
        print(verify.format_table(runs, args.suite))
        engines = ", ".join(dict.fromkeys(run.engine for run in runs))
        print(f"{len(rows) - failed} of {len(rows)} checks passed ({len(runs)} runs on {engines})")
        print(f"picture      {png}")
        print(f"runs         {out_dir}")
    return 1 if failed else 0


def _verify_sweep(args, out_dir: Path) -> int:

    if any(not 0 < f <= 1 for f in args.timestep_factors):
        raise OrchestratorError("--timestep-factors: every factor must be in (0, 1] (a fraction of the critical step)")
    points, _ = run_timestep_sweep(args.suite, args.timestep_factors, engines=args.engines, out_dir=out_dir,
                                   cases_dir=args.cases, workers=args.workers)
    png = plot_sweep(points, out_dir / "timestep_sweep.png")
    if args.json:
        print(json.dumps([jsonable(asdict(p)) for p in points]))
    else:
        print(format_sweep(points))
        print(f"plot         {png}")
        print(f"runs         {out_dir}")
    return 0
