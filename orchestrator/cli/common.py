"""Helpers shared by the commands: JSON without NaN/inf, option checks, plain text tables."""

from __future__ import annotations

import math

from orchestrator.errors import OrchestratorError
from orchestrator.humanize import check_out_dir


def jsonable(value):
    """`value` with every non-finite float replaced by None (JSON has no NaN or inf), dicts and lists walked."""
    if isinstance(value, dict):
        return {k: jsonable(v) for k, v in value.items()}
    if isinstance(value, list):
        return [jsonable(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def check_options(args) -> None:
    """Refuse option values no command can use: a wall-time limit or tolerance that is not a finite positive
    number, fewer than one worker or MPI rank, an --out that cannot be a folder (OrchestratorError, exit 2)."""

    for option in ("timeout", "tolerance"):
        value = getattr(args, option, None)
        if value is not None and not (math.isfinite(value) and value > 0):
            unit = " s" if option == "timeout" else ""
            raise OrchestratorError(f"--{option} {value:g}: allowed: a finite number above 0{unit}"
                                    + (" (leave --timeout out for no limit)" if option == "timeout" else ""))
    for option in ("workers", "mpi"):
        value = getattr(args, option, None)
        if value is not None and value < 1:
            raise OrchestratorError(f"--{option} {value}: allowed: 1 or more")
    if getattr(args, "out", None) is not None:
        check_out_dir(args.out)


def print_table(header: list[str], table: list[list[str]]) -> None:
    """Columns of strings, left-aligned, two spaces apart, under a header line."""
    widths = [max(len(h), *(len(r[i]) for r in table)) for i, h in enumerate(header)]
    print("  ".join(h.ljust(w) for h, w in zip(header, widths)))
    for r in table:
        print("  ".join(c.ljust(w) for c, w in zip(r, widths)))
