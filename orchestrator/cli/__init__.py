"""The `orchestrator` command line: one module per command, each with `add_parser(subparsers)` (its options,
help and `set_defaults(func=...)`) and its command function; this module assembles the parser in the order
of --help, runs the chosen command and turns errors and signals into messages and exit codes.

The command modules (and through them numpy, pydantic and the package) are a lazy registry, loaded by name once
the signal handlers are installed: a Ctrl-C during start-up is then a clean exit 130, never a traceback."""

from __future__ import annotations

import argparse
import importlib
import json
import sys
import tempfile
import traceback

from orchestrator import __version__, signals
from orchestrator.cli.common import jsonable
from orchestrator.errors import OrchestratorError
from orchestrator.kinds import kind_commands
from orchestrator.signals import Interrupted

# Modules under orchestrator.cli, in the order --help lists them; study registers study, status and report. The
# commands the kinds contribute (Kind.commands) follow the commands that loop over the kinds (verify, calibrate:
# a kind's 'calibrate <parameter>' is a parameter of calibrate).
KIND_COMMANDS = "<the kinds' own commands>"
COMMAND_MODULES = ("run", "analyze", "study", "verify", "calibrate", KIND_COMMANDS, "compare", "bench", "doctor",
                   "export")


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="orchestrator",
        description="Run particle simulations of machining and finishing processes on established engines "
        "(Yade and LIGGGHTS for DEM, our sph executable for SPH) and compare them with the papers and reference "
        "solvers. All quantities are SI (m, kg, s, N, Pa).",
    )
    parser.add_argument("--version", action="version", version=f"orchestrator {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMAND_MODULES:
        if name == KIND_COMMANDS:
            add_kind_commands(sub)
        else:
            importlib.import_module(f"orchestrator.cli.{name}").add_parser(sub)
    return parser


def add_kind_commands(sub) -> None:
    """A parser per command the kinds contribute (kinds.kind_commands), besides calibrate's parameters."""
    for name, command in kind_commands().items():
        if " " in name:  # 'calibrate <parameter>': cli/calibrate.py gathers them
            continue
        parser = sub.add_parser(name, help=command.help, description=command.description)
        command.add_arguments(parser)
        parser.set_defaults(func=command.run)


def main(argv=None) -> int:
    """Entry point of the console script; returns the exit code.

    SIGINT, SIGTERM and SIGHUP stop a running engine, keep what was measured in run.h5 (status terminated) and
    exit with 128 + the signal's number.
    """

    with signals.installed():
        try:
            code = _main(argv)
            signals.check()  # a signal that a library swallowed still ends the command
            return code
        except KeyboardInterrupt as exc:
            return _interrupted(exc)
        except Exception:  # a signal inside a C extension's import surfaces as ImportError("initialization failed")
            if signals.pending() is None:
                raise
            return _interrupted(Interrupted(signals.pending()))


def _main(argv) -> int:

    parser = _parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    try:
        return args.func(args)
    except OrchestratorError as exc:
        if getattr(args, "json", False) and exc.summary is not None:
            print(json.dumps(jsonable(exc.summary.as_dict())))
        print(f"error: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt as exc:
        if getattr(args, "json", False) and getattr(exc, "summary", None) is not None:
            print(json.dumps(jsonable(exc.summary.as_dict())))
        raise
    except Exception as exc:  # a bug of ours: keep the traceback in a file, show one line
        if signals.pending() is not None:  # unless a signal broke a library (an import fails on Ctrl-C)
            raise Interrupted(signals.pending()) from exc

        with tempfile.NamedTemporaryFile("w", prefix="orchestrator-crash-", suffix=".log", delete=False) as fh:
            traceback.print_exc(file=fh)
        print(f"error: internal error ({type(exc).__name__}: {exc}); this is a bug in orchestrator, "
              f"please report it with the traceback saved in {fh.name}", file=sys.stderr)
        return 70


def _interrupted(exc: KeyboardInterrupt) -> int:
    """Say what a signal stopped and what is on disk; the exit code is 128 + the signal's number."""

    how = exc.describe() if isinstance(exc, Interrupted) else "Ctrl-C (SIGINT)"
    kept = getattr(exc, "kept", None)
    if kept is not None:
        print(f"error: stopped by {how}; the engine was stopped and {kept}", file=sys.stderr)
    else:
        print(f"error: stopped by {how}; no run.h5 was written by this command", file=sys.stderr)
    return exc.exit_code if isinstance(exc, Interrupted) else 130
