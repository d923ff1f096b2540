"""The kind's entry points by [scene] area: the paper's two areas (build.py, analysis.py, report.py) or the feed
(feed_build.py, feed_analysis.py, feed_report.py)."""

from __future__ import annotations

from orchestrator.kinds.ejector_drill.analysis import measure_drill
from orchestrator.kinds.ejector_drill.build import build_drill_scene
from orchestrator.kinds.ejector_drill.feed_analysis import measure_feed
from orchestrator.kinds.ejector_drill.feed_build import build_feed_scene
from orchestrator.kinds.ejector_drill.feed_report import analyze_feed_run
from orchestrator.kinds.ejector_drill.report import analyze_drill_run


def build_scene(case):
    """The SPH scene of an EjectorDrillCase (a DrillSphScene)."""
    return build_feed_scene(case) if case.scene.area == "feed" else build_drill_scene(case)


def measure(case, result) -> dict[str, float]:
    """The run's measured quantities (SI units; analysis.measure_drill, feed_analysis.measure_feed)."""
    return measure_feed(case, result) if case.scene.area == "feed" else measure_drill(case, result)


def analyze(run_dir, run: dict, case, render: bool = True) -> dict:
    """`orchestrator analyze` of a run (report.analyze_drill_run, feed_report.analyze_feed_run); {name: path}."""
    if case.scene.area == "feed":
        return analyze_feed_run(run_dir, run, case, render)
    return analyze_drill_run(run_dir, run, case, render)
