"""orchestrator calibrate restitution: fit e_n to a sphere drop's first impacts (a CSV trace or a run);
orchestrator calibrate maxwell: fit Maxwell modes to measured moduli G'(omega), G''(omega) (a CSV)."""

from __future__ import annotations

import json
import sys
from dataclasses import asdict

from orchestrator.case import load_case
from orchestrator.cli.common import jsonable
from orchestrator.errors import OrchestratorError
from orchestrator.workflows import calibrate_maxwell
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
        "since the first impact t2-t1, t3-t1 (s), with the drop case's damped Hertz closed forms as the model. "
        "calibrate maxwell: fit N Maxwell modes (relaxation times lambda_i in s, viscosities eta_i in Pa s; "
        "optionally a storage plateau G_p in Pa and a Cross law for G'') to measured storage and loss moduli "
        "G'(omega), G''(omega) (Pa), as Nutto et al. did for the MF20 abrasive medium (Table III).")
    calibrate.add_argument("parameter", choices=["restitution", "maxwell"],
                           help="what to fit: restitution (e_n, -) or maxwell (lambda_i s, eta_i Pa s, G_p Pa)")
    source = calibrate.add_mutually_exclusive_group(required=True)
    source.add_argument("--csv", metavar="FILE", help="force-sensor trace: a header line, then rows time_s,force_N; for maxwell: moduli, a header "
                        "naming omega_rad_s (angular frequency, rad/s) or f_Hz (frequency, Hz) and G_storage_Pa "
                        "and/or G_loss_Pa (Pa), then rows of numbers ('#' lines are comments)")
    source.add_argument("--run", metavar="RUN_DIR", help="a simulated drop (its run.h5 contact events and case)")
    calibrate.add_argument("--case", metavar="CASE",
                           help="the drop's case file for --csv (sphere, plate, drop height; default: "
                           "cases/verification/uhlmann2015_sphere_drop.toml, the paper's 10 mm drop)")
    calibrate.add_argument("--json", action="store_true",
                           help="print one JSON object: restitution, residuals, observed and model peaks (N) and "
                           "peak times (s); for maxwell: the modes (s, Pa s, Pa), G_p (Pa), residuals and errors")
    maxwell = calibrate.add_argument_group("maxwell only")
    maxwell.add_argument("--modes", type=int, metavar="N", help="number of Maxwell modes to fit (required)")
    maxwell.add_argument("--fit", choices=list(FITS), help="which moduli to fit: storage G' (Pa), loss G'' (Pa) "
                         "or both (default)")
    maxwell.add_argument("--plateau", action="store_true", help="also fit a constant storage plateau G_p (Pa)")
    maxwell.add_argument("--cross", action="store_true",
                         help="fit G'' (Pa) by a Cross viscosity law, G'' = omega eta(omega), instead of the modes; "
                         "the modes then come from G' alone (needs --fit both)")
    maxwell.add_argument("--out", metavar="TOML", help="write the modes as a case-file fragment ([[material.modes]] "
                         "relaxation_time s, viscosity Pa s; storage_plateau Pa)")
    maxwell.add_argument("--force", action="store_true", help="overwrite an existing --out file")
    maxwell.add_argument("--png", metavar="PNG", help="draw G' and G'' (Pa) of data and fit against omega (rad/s)")
    calibrate.set_defaults(func=cmd_calibrate)


FITS = ("storage", "loss", "both")
RESTITUTION_ONLY = ("run", "case")
MAXWELL_ONLY = ("modes", "fit", "plateau", "cross", "out", "force", "png")


def cmd_calibrate(args) -> int:

    other = MAXWELL_ONLY if args.parameter == "restitution" else RESTITUTION_ONLY
    given = [f"--{name}" for name in other if getattr(args, name) not in (None, False)]
    if given:
        raise OrchestratorError(f"calibrate {args.parameter}: {', '.join(given)} belong(s) to calibrate "
                                f"{'maxwell' if args.parameter == 'restitution' else 'restitution'}; leave "
                                f"{'it' if len(given) == 1 else 'them'} out")
    if args.parameter == "maxwell":
        return cmd_maxwell(args)
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


def cmd_maxwell(args) -> int:
    if args.modes is None:
        raise OrchestratorError("calibrate maxwell needs --modes N (the number of Maxwell modes, 1 or more)")
    fit = args.fit or "both"
    if args.cross and fit != "both":
        raise OrchestratorError(f"--cross replaces the modes' G'' by a Cross law, so the modes come from G': "
                                f"use --fit both, not --fit {fit}")
    if args.plateau and fit == "loss":
        raise OrchestratorError("--plateau: G_p enters G' only; use --fit storage or --fit both")
    omega, storage, loss, result = calibrate_maxwell.calibrate(args.csv, args.modes, fit, args.plateau, args.cross)
    if args.json:
        print(json.dumps(jsonable(calibrate_maxwell.fit_as_dict(result))))
    else:
        print(calibrate_maxwell.format_fit(result))
    if args.out:
        path = calibrate_maxwell.write_fragment(result, args.out, args.csv, args.force)
        print(f"wrote {path}", file=sys.stderr if args.json else sys.stdout)
    if args.png:
        path = calibrate_maxwell.plot_fit(omega, storage, loss, result, args.png)
        print(f"wrote {path}", file=sys.stderr if args.json else sys.stdout)
    if not result.success:
        print(f"error: the fit failed: {result.message}", file=sys.stderr)
        return 1
    return 0
