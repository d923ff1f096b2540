"""The impact kind's part of `verify dem`: a scene's check rows from its [[expected]] table against the closed forms
(analysis.evaluate_checks), and the suite's picture, the normal force of every engine per scene (plots.py)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from orchestrator.kinds.impact.analysis import evaluate_checks
from orchestrator.kinds.impact.plots import ForceCurve, plot_force_curves


def check_run(case, engine: str, run: dict) -> tuple[list[dict], dict]:
    """The check rows of one scene's run (run: runh5.read_run's dict; measured quantities from its /measured) and
    what the suite's picture draws of it: the normal-force series (s, N) and each contact's peak (s, N). A check
    that fails on an engine whose run.h5 names a known deviation carries it as its note."""
    measured = run.get("measured", {}).get("attrs", {})
    deviation = run.get("attrs", {}).get("deviation", "")
    rows = []
    for check in evaluate_checks(case, measured):
        note = check.note or (f"{engine}: {deviation}" if not check.passed and deviation else "")
        rows.append({"scene": case.case.name, "engine": engine, "quantity": check.quantity, "value": check.value,
                     "expected": check.expected, "rel_error": check.rel_error, "tolerance": check.tolerance,
                     "passed": bool(check.passed), "source": check.source, "note": note})
    picture = {}
    series, events = run.get("series", {}), run.get("events", {})
    if "normal_force" in series:
        picture["time"], picture["normal_force"] = series["time"], series["normal_force"]
    if "peak_time" in events:
        picture["peaks"] = np.column_stack([events["peak_time"], events["peak_normal_force"]])
    return rows, picture


def plot_suite(runs: list, path: Path) -> Path:
    """verify_dem.png: one panel per scene, the normal force (N) against time (ms) of every engine, peaks marked.
    runs: workflows.base.CheckedRun with the picture of check_run."""
    return plot_force_curves([ForceCurve(run.scene, run.engine, run.status, **run.picture) for run in runs], path)
