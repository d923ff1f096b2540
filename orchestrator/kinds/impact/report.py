"""`orchestrator analyze` on an impact run: measured quantities, checks against expected values, forces.png."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from orchestrator.kinds.impact.analysis import evaluate_checks
from orchestrator.kinds.impact.theory import QUANTITIES
from orchestrator.kinds.impact.plots import ForceCurve, plot_force_curves


def analyze_impact_run(run_dir: Path, run: dict, case, render: bool = True) -> dict:
    """Print an impact run's checks (measured against expected, SI units) and write forces.png."""
    attrs = run["attrs"]
    measured = run.get("measured", {}).get("attrs", {})
    spheres = f"{attrs['n_particles']} sphere{'s' if attrs['n_particles'] != 1 else ''}"
    print(f"run {run_dir}: status {attrs['status']}, {attrs['engine']} {attrs['engine_version']}, {spheres}, "
          f"{attrs['n_steps']} steps, {attrs['wall_time_s']:.1f} s")
    if attrs.get("deviation"):
        print(f"note: {attrs['deviation']}")
    for name, (unit, meaning) in QUANTITIES.items():
        if name in measured:
            print(f"{name:<28} {measured[name]:<12.6g} {unit:<6} {meaning}")
    for row in evaluate_checks(case, measured):
        verdict = "pass" if row.passed else "FAIL"
        print(f"check {row.quantity:<28} expected {row.expected:<12.6g} ({row.source}) rel_error {row.rel_error:.2e} "
              f"tolerance {row.tolerance:g} {verdict}" + (f" ({row.note})" if row.note else ""))
    scene = ForceCurve(case.case.name, attrs["engine"], attrs["status"])
    series, events = run.get("series", {}), run.get("events", {})
    if "normal_force" in series:
        scene.time, scene.normal_force = series["time"], series["normal_force"]
    if "peak_time" in events:
        scene.peaks = np.column_stack([events["peak_time"], events["peak_normal_force"]])
    path = plot_force_curves([scene], run_dir / "forces.png")
    print(f"forces   {path}")
    return {"forces": path}
