"""Reductions of a run to the case's measured quantities, and comparison with references."""

from .drag_finishing import force_statistics, measure_drag_finishing
from .impact import measure_impact
from .sph import measure_sph_flow

MEASURES = {"drag_finishing": measure_drag_finishing, "impact": measure_impact, "sph_flow": measure_sph_flow}


def measure(case, result) -> dict[str, float]:
    """The case's measured quantities from a Result (empty if the run has too little data)."""
    return MEASURES[case.case.kind](case, result)


def remeasure(run: dict) -> dict[str, float]:
    """The measured quantities of a stored run (read_run's dict) recomputed with the current analysis
    code, so that a new measure needs no rerun; SI units as in measure()."""
    from ..backends.base import Result, Series
    from ..report import _loaded_case

    case = _loaded_case(run)
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


__all__ = ["MEASURES", "force_statistics", "measure", "remeasure"]
