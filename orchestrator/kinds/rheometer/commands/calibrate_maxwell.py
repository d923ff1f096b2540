"""`orchestrator calibrate maxwell`: N Maxwell modes fitted to measured moduli G'(omega), G''(omega) from a CSV
(calibration.py does the fit), written as a case-file fragment and drawn on request."""

from __future__ import annotations

import json
import sys

from orchestrator.cli.common import jsonable
from orchestrator.errors import OrchestratorError
from orchestrator.kinds.base import Command
from orchestrator.kinds.rheometer import calibration

FITS = ("storage", "loss", "both")


def add_arguments(parser) -> None:
    """The options of `calibrate maxwell` besides the shared --csv (the moduli) and --json."""
    parser.add_argument("--modes", type=int, metavar="N", help="number of Maxwell modes to fit (required)")
    parser.add_argument("--fit", choices=list(FITS), help="which moduli to fit: storage G' (Pa), loss G'' (Pa) "
                        "or both (default)")
    parser.add_argument("--plateau", action="store_true", help="also fit a constant storage plateau G_p (Pa)")
    parser.add_argument("--cross", action="store_true",
                        help="fit G'' (Pa) by a Cross viscosity law, G'' = omega eta(omega), instead of the modes; "
                        "the modes then come from G' alone (needs --fit both)")
    parser.add_argument("--out", metavar="TOML", help="write the modes as a case-file fragment ([[material.modes]] "
                        "relaxation_time s, viscosity Pa s; storage_plateau Pa)")
    parser.add_argument("--force", action="store_true", help="overwrite an existing --out file")
    parser.add_argument("--png", metavar="PNG", help="draw G' and G'' (Pa) of data and fit against omega (rad/s)")


def run(args) -> int:
    """Fit the modes, print them (or their JSON), write the fragment and the figure; exit 1 when the fit failed."""
    if args.csv is None:
        raise OrchestratorError("calibrate maxwell needs --csv FILE (the measured moduli)")
    if args.modes is None:
        raise OrchestratorError("calibrate maxwell needs --modes N (the number of Maxwell modes, 1 or more)")
    fit = args.fit or "both"
    if args.cross and fit != "both":
        raise OrchestratorError(f"--cross replaces the modes' G'' by a Cross law, so the modes come from G': "
                                f"use --fit both, not --fit {fit}")
    if args.plateau and fit == "loss":
        raise OrchestratorError("--plateau: G_p enters G' only; use --fit storage or --fit both")
    omega, storage, loss, result = calibration.calibrate(args.csv, args.modes, fit, args.plateau, args.cross)
    if args.json:
        print(json.dumps(jsonable(calibration.fit_as_dict(result))))
    else:
        print(calibration.format_fit(result))
    if args.out:
        path = calibration.write_fragment(result, args.out, args.csv, args.force)
        print(f"wrote {path}", file=sys.stderr if args.json else sys.stdout)
    if args.png:
        path = calibration.plot_fit(omega, storage, loss, result, args.png)
        print(f"wrote {path}", file=sys.stderr if args.json else sys.stdout)
    if not result.success:
        print(f"error: the fit failed: {result.message}", file=sys.stderr)
        return 1
    return 0


COMMAND = Command(
    help="Maxwell modes (lambda_i s, eta_i Pa s) from measured moduli G', G''",
    description="calibrate maxwell: fit N Maxwell modes (relaxation times lambda_i in s, viscosities eta_i in Pa s; "
    "optionally a storage plateau G_p in Pa and a Cross law for G'') to measured storage and loss moduli "
    "G'(omega), G''(omega) (Pa), as Nutto et al. did for the MF20 abrasive medium (Table III); --csv: a header "
    "naming omega_rad_s (angular frequency, rad/s) or f_Hz (frequency, Hz) and G_storage_Pa and/or G_loss_Pa, "
    "then rows of numbers ('#' lines are comments); --json: the modes (s, Pa s, Pa), G_p (Pa), residuals and "
    "errors.",
    add_arguments=add_arguments, run=run)
