"""orchestrator calibrate restitution: fit e_n to a sphere drop's first impacts (a CSV trace or a run)."""

from __future__ import annotations

import json
import sys
from dataclasses import asdict

from orchestrator.case import load_case
from orchestrator.cli.common import jsonable
from orchestrator.workflows.calibrate import (
    drop_case_path,
    fit_restitution,
    format_fit,
    observations_from_csv,
    observations_from_run,
)


def add_parser(sub) -> None:
    calibrate = sub.add_parser(
        "calibrate", help="fit a model parameter to measured or simulated data (restitution from a sphere drop)",
        description="calibrate restitution: fit the normal coefficient of restitution e_n (-) to the first three "
        "impacts of a sphere drop, as Uhlmann et al. 2015 did: from the peak-force ratios F2/F1, F3/F1 and the times "
        "since the first impact t2-t1, t3-t1 (s), with the drop case's damped Hertz closed forms as the model.")
    calibrate.add_argument("parameter", choices=["restitution"], help="what to fit: restitution (e_n, -)")
    source = calibrate.add_mutually_exclusive_group(required=True)
    source.add_argument("--csv", metavar="FILE", help="force-sensor trace: a header line, then rows time_s,force_N")
    source.add_argument("--run", metavar="RUN_DIR", help="a simulated drop (its run.h5 contact events and case)")
    calibrate.add_argument("--case", metavar="CASE",
                           help="the drop's case file for --csv (sphere, plate, drop height; default: "
                           "cases/verification/uhlmann2015_sphere_drop.toml, the paper's 10 mm drop)")
    calibrate.add_argument("--json", action="store_true",
                           help="print one JSON object: restitution, residuals, observed and model peaks (N) and "
                           "peak times (s)")
    calibrate.set_defaults(func=cmd_calibrate)


def cmd_calibrate(args) -> int:

    if args.run:
        observed, case = observations_from_run(args.run)
        if args.case:
            case = load_case(args.case).model
        source = f"run {args.run}"
    else:
        observed = observations_from_csv(args.csv)
        case = load_case(args.case or drop_case_path()).model
        source = f"CSV {args.csv}"
    fit = fit_restitution(case, observed, source)
    if args.json:
        print(json.dumps(jsonable(asdict(fit))))
    else:
        print(format_fit(fit))
    if fit.failure:
        print(f"error: the fit failed: {fit.failure}", file=sys.stderr)
        return 1
    return 0
