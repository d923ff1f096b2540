"""orchestrator calibrate PARAMETER: fit a model parameter to measured or simulated data. The parameters are what
the kinds contribute (Kind.commands named 'calibrate <parameter>', e.g. restitution from a sphere drop, Maxwell
modes from measured moduli); this module adds the shared options (--csv, --json), gives each parameter's own
options a group, and refuses an option of one parameter given to another."""

from __future__ import annotations

from orchestrator.errors import OrchestratorError
from orchestrator.kinds import kind_commands

PREFIX = "calibrate "


def calibrations() -> dict:
    """{parameter: kinds.base.Command} of every kind's 'calibrate <parameter>' command, by parameter."""
    return {name.removeprefix(PREFIX): command for name, command in kind_commands().items()
            if name.startswith(PREFIX)}


def add_parser(sub) -> None:
    fits = calibrations()
    calibrate = sub.add_parser(
        "calibrate", help=f"fit a model parameter to measured or simulated data ({', '.join(fits)})",
        description=" ".join(command.description for command in fits.values()))
    calibrate.add_argument("parameter", choices=list(fits), help="what to fit: " + "; ".join(
        f"{name} ({command.help})" for name, command in fits.items()))
    calibrate.add_argument("--csv", metavar="FILE", help="the measured data as a CSV (its columns: see PARAMETER)")
    calibrate.add_argument("--json", action="store_true", help="print one JSON object instead of the table")
    own = {}
    for name, command in fits.items():
        before = set(id(action) for action in calibrate._actions)  # argparse lists no options per group
        command.add_arguments(calibrate.add_argument_group(f"{name} only"))
        own[name] = [action for action in calibrate._actions if id(action) not in before]
    calibrate.set_defaults(func=lambda args: cmd_calibrate(args, fits, own))


def cmd_calibrate(args, fits: dict, own: dict) -> int:
    """Refuse the options of the other parameters, then run the chosen parameter's calibration."""
    for other, actions in own.items():
        if other == args.parameter:
            continue
        given = [action.option_strings[0] for action in actions
                 if getattr(args, action.dest) not in (None, False, action.default)]
        if given:
            raise OrchestratorError(f"calibrate {args.parameter}: {', '.join(given)} belong(s) to calibrate "
                                    f"{other}; leave {'it' if len(given) == 1 else 'them'} out")
    return fits[args.parameter].run(args)
