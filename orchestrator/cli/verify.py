"""orchestrator verify dem|sph: the verification suites against closed forms, and the time-step sweep."""

from __future__ import annotations

import json
import sys
from dataclasses import asdict
from pathlib import Path

from orchestrator.cli.common import check_options, jsonable
from orchestrator.errors import OrchestratorError
from orchestrator.kinds.impact.plots import plot_force_curves
from orchestrator.workflows import verify as dem
from orchestrator.workflows import verify_sph as sph
from orchestrator.workflows.base import format_table as base_table
from orchestrator.workflows.base import json_rows
from orchestrator.workflows.timestep_study import format_sweep, plot_sweep, run_timestep_sweep
from orchestrator.workflows.verify import format_table
from orchestrator.workflows.verify_sph import plot_scenes, unit_of


def add_parser(sub) -> None:
    verify = sub.add_parser(
        "verify", help="verification suite: every scene on every installed engine against closed forms",
        description="Run every verification scene (cases/verification/*.toml: Chung & Ooi 2011 tests 1-4 and the "
        "sphere drop of Uhlmann et al. 2015) on every installed DEM engine and on the reference DEM, compare each "
        "measured quantity with its closed form, print one table (scene, engine, quantity [SI unit], value, "
        "expected, rel_error = |value - expected| / |expected|, tolerance, passed) and save verify_dem.png (normal "
        "force in N against time in ms, engines overlaid per scene). Exit code 1 if any check fails. "
        "verify sph: the SPH scenes (cases/verification/sph_*.toml: Poiseuille and Couette start-up against the "
        "series of Morris et al. 1997, a hydrostatic tank, the 2D dam break against Koshizuka & Oka 1996 and "
        "Martin & Moyce 1952, penalty walls against eq. 14) on the sph executable, the same table and JSON rows, "
        "and verify_sph.png (profiles, pressure, surge front, wall forces).")
    verify.add_argument("suite", choices=["dem", "sph"],
                        help="which suite: dem (discrete element impacts) or sph (SPH flows on the sph executable)")
    verify.add_argument("--engine", dest="engines", action="append", metavar="NAME",
                        help="run on this engine only (repeatable; default: every installed DEM engine and the "
                        "reference)")
    verify.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                        help="override a value of every scene, SI units, e.g. --set numerics.timestep_factor=0.1")
    verify.add_argument("--cases", metavar="DIR", help="directory of scenes (default: the shipped cases/verification)")
    verify.add_argument("--out", metavar="DIR", help="run directories and the PNG (default: runs/verify-<suite>-<time>)")
    verify.add_argument("--workers", type=int, metavar="N", help="parallel runs (default: the number of cores)")
    verify.add_argument("--timeout", type=float, metavar="S",
                        help="wall-time limit of each run, s (default 3600 for sph: its 3D annulus takes ~750 s on "
                        "one core; 600 for dem; a run stopped by it fails its checks, run.h5 keeps what it recorded)")
    verify.add_argument("--json", action="store_true",
                        help="print the rows as a JSON list of objects with the keys scene, engine, quantity, value, "
                        "expected, rel_error, tolerance, passed (SI units; null where not measured)")
    verify.add_argument("--timestep-factors", type=float, nargs="+", metavar="F",
                        help="speed against error instead: run the suite at each numerics.timestep_factor F (fraction "
                        "of the critical step, e.g. 0.01 0.05 0.2 1) and print, per engine and F, the worst relative "
                        "error, the checks passed and the engine compute time in s; saves timestep_sweep.png")
    verify.set_defaults(func=cmd_verify)


def _timeout(args) -> dict:
    """{'timeout_s': --timeout} when given (the suites' own defaults otherwise)."""
    return {} if args.timeout is None else {"timeout_s": args.timeout}


def cmd_verify(args) -> int:

    check_options(args)
    if args.suite == "sph":
        return _verify_sph(args)
    out_dir = args.out or dem.default_out_dir()
    if args.timestep_factors:
        return _verify_sweep(args, Path(out_dir))
    def done(run, count, total):
        print(f"verify: {count}/{total} {run.scene} on {run.engine}: {run.status}", file=sys.stderr, flush=True)

    runs = dem.run_verification(engines=args.engines, out_dir=out_dir, cases_dir=args.cases, overrides=args.overrides,
                                workers=args.workers, on_done=done, **_timeout(args))
    png = plot_force_curves(runs, Path(out_dir) / "verify_dem.png")
    rows = json_rows(runs)
    failed = sum(not row["passed"] for row in rows)
    if args.json:
        print(json.dumps(rows))
    else:
        print(format_table(runs))
        engines = ", ".join(dict.fromkeys(run.engine for run in runs))
        print(f"{len(rows) - failed} of {len(rows)} checks passed ({len(runs)} runs on {engines})")
        print(f"curves       {png}")
        print(f"runs         {out_dir}")
    return 1 if failed else 0


def _verify_sph(args) -> int:

    if args.timestep_factors:
        raise OrchestratorError("--timestep-factors is for 'verify dem' only")
    if args.engines and set(args.engines) != {"sph"}:
        raise OrchestratorError(f"verify sph runs on the sph engine only, not {', '.join(args.engines)}")
    out_dir = Path(args.out) if args.out else sph.default_out_dir()

    def done(run, count, total):
        print(f"verify: {count}/{total} {run.scene} on {run.engine}: {run.status}", file=sys.stderr, flush=True)

    runs = sph.run_verification(out_dir=out_dir, cases_dir=args.cases, overrides=args.overrides, workers=args.workers,
                                on_done=done, **_timeout(args))
    png = plot_scenes(runs, out_dir / "verify_sph.png")
    rows = json_rows(runs)
    failed = sum(not row["passed"] for row in rows)
    if args.json:
        print(json.dumps(rows))
    else:
        print(base_table(runs, unit_of))
        print(f"{len(rows) - failed} of {len(rows)} checks passed ({len(runs)} scenes on sph)")
        print(f"plots        {png}")
        print(f"runs         {out_dir}")
    return 1 if failed else 0


def _verify_sweep(args, out_dir: Path) -> int:

    if any(not 0 < f <= 1 for f in args.timestep_factors):
        raise OrchestratorError("--timestep-factors: every factor must be in (0, 1] (a fraction of the critical step)")
    points, _ = run_timestep_sweep(args.timestep_factors, engines=args.engines, out_dir=out_dir,
                                   cases_dir=args.cases, workers=args.workers)
    png = plot_sweep(points, out_dir / "timestep_sweep.png")
    if args.json:
        print(json.dumps([jsonable(asdict(p)) for p in points]))
    else:
        print(format_sweep(points))
        print(f"plot         {png}")
        print(f"runs         {out_dir}")
    return 0
