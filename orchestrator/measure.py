"""Measured quantities of a stored run recomputed with the current analysis code (a new measure needs no rerun)."""

from __future__ import annotations

import sys
import tempfile
import traceback
from pathlib import Path

from orchestrator.engines.base import Result, Series
from orchestrator.kinds import measure
from orchestrator.runh5 import stored_case


def remeasure(run: dict) -> dict[str, float]:
    """The measured quantities of a stored run (read_run's dict) recomputed with the current analysis
    code, so that a new measure needs no rerun; SI units as in measure()."""
    case = stored_case(run, "run.h5")
    series = run.get("series", {})
    result = Result(status=run["attrs"].get("status", "ok"), attrs=dict(run["attrs"]), time=series.get("time"))
    result.series = {k: Series(v, "") for k, v in series.items() if k not in ("attrs", "time")}
    result.events = {k: Series(v, "") for k, v in run.get("events", {}).items() if k != "attrs"}
    for group, target in (("contacts", result.contacts), ("frames", result.frames)):
        entries = run.get(group, {})
        for key in sorted((k for k in entries if k != "attrs"), key=int):
            arrays = {k: v for k, v in entries[key].items() if k != "attrs"}
            arrays.update({k: v for k, v in entries[key]["attrs"].items() if k != "time"})
            target.append((float(entries[key]["attrs"]["time"]), arrays))
    return measure(case, result)


def measure_or_warn(case, result: Result, run_dir: Path) -> dict[str, float]:
    """measure(case, result); a measurement that fails (a bug in a kind's analysis) measures nothing and says so
    in one warning line naming a file with its traceback, so that run.h5 is still written with everything the
    engine computed (`orchestrator analyze` measures it again with the mended code)."""
    try:
        return measure(case, result)
    except Exception as exc:  # noqa: BLE001 - whatever the analysis raises, the engine's output is kept
        with tempfile.NamedTemporaryFile("w", prefix="orchestrator-measure-", suffix=".log", delete=False) as log:
            traceback.print_exc(file=log)
        print(f"warning: measuring the run failed ({type(exc).__name__}: {exc}; traceback in {log.name}); run.h5 "
              f"in {run_dir} keeps the engine's output without measured quantities", file=sys.stderr)
        return {}
