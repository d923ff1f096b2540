"""Reductions of a run to the case's measured quantities, and comparison with references."""

from .drag_finishing import force_statistics, measure_drag_finishing
from .impact import measure_impact

MEASURES = {"drag_finishing": measure_drag_finishing, "impact": measure_impact}


def measure(case, result) -> dict[str, float]:
    """The case's measured quantities from a Result (empty if the run has too little data)."""
    return MEASURES[case.case.kind](case, result)


__all__ = ["MEASURES", "force_statistics", "measure"]
