"""`orchestrator calibrate restitution`: the normal coefficient of restitution e_n fitted to the first three impacts
of a sphere drop, from a force-sensor trace (--csv) or a simulated run (--run) (calibration.py does the fit)."""

from __future__ import annotations

import json
import sys
from dataclasses import asdict

from orchestrator.case import load_case
from orchestrator.cli.common import jsonable
from orchestrator.errors import OrchestratorError
from orchestrator.kinds.base import Command
from orchestrator.kinds.impact.calibration import (
    drop_case_path,
    fit_restitution,
    format_fit,
    observations_from_csv,
    observations_from_run,
)


def add_arguments(parser) -> None:
    """The options of `calibrate restitution` besides the shared --csv (a force-sensor trace) and --json."""
    parser.add_argument("--run", metavar="RUN_DIR", help="a simulated drop (its run.h5 contact events and case) "
                        "instead of --csv")
    parser.add_argument("--case", metavar="CASE",
                        help="the drop's case file for --csv (sphere, plate, drop height; default: "
                        "cases/verification/uhlmann2015_sphere_drop.toml, the paper's 10 mm drop)")


def run(args) -> int:
    """Fit e_n, print the fit (or its JSON); exit 1 when the fit is not to be trusted."""
    if (args.csv is None) == (args.run is None):
        raise OrchestratorError("calibrate restitution: give one of --csv FILE (a force-sensor trace: time_s,force_N)"
                                " and --run RUN_DIR (a simulated drop)")
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


COMMAND = Command(
    help="restitution e_n (-) from a sphere drop's first three impacts",
    description="calibrate restitution: fit the normal coefficient of restitution e_n (-) to the first three "
    "impacts of a sphere drop, as Uhlmann et al. 2015 did: from the peak-force ratios F2/F1, F3/F1 and the times "
    "since the first impact t2-t1, t3-t1 (s), with the drop case's damped Hertz closed forms as the model; --csv: a "
    "force-sensor trace, a header line, then rows time_s,force_N; --json: one object with restitution, residuals, "
    "observed and model peaks (N) and peak times (s).",
    add_arguments=add_arguments, run=run)
