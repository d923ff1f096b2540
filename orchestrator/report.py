"""`orchestrator analyze RUN_DIR`: the comparison table with the case's
references and the PNG plots (force series with bands, network rendering)."""

from __future__ import annotations

from pathlib import Path

from .errors import ReadError
from .runh5 import read_run, stored_case




def _loaded_case(run: dict):
    """The case model stored in a run (runh5.stored_case; ReadError when run.h5 has none)."""
    return stored_case(run, "run.h5")


def analyze_run(run_dir, render: bool = True) -> dict:
    """Print the comparison table and write forces.png (and network.png); returns {name: path}."""
    from .analysis.drag_finishing import comparison_table
    from .plots import plot_drag_finishing_forces

    run_dir = Path(run_dir)
    run = read_run(run_dir)
    case = stored_case(run, run_dir)
    attrs = run["attrs"]
    missing = [key for key in ("status", "engine", "engine_version", "n_particles", "n_steps", "wall_time_s")
               if key not in attrs]
    if missing:
        raise ReadError(f"{run_dir}: run.h5 lacks the attribute {missing[0]!r}; it was not written by "
                        "'orchestrator run' (or is damaged)")
    if case.case.kind == "impact":
        return analyze_impact_run(run_dir, run, case)
    if case.case.kind == "sph_flow":
        from .analysis.sph import analyze_sph_run

        return analyze_sph_run(run_dir, run, case, render)
    measured = run.get("measured", {}).get("attrs", {})
    print(f"run {run_dir}: status {attrs['status']}, {attrs['engine']} {attrs['engine_version']}, "
          f"{attrs['n_particles']} particles, {attrs['n_steps']} steps, {attrs['wall_time_s']:.1f} s")
    if "bed_height" in measured:
        print(f"settled bed height {1e3 * measured['bed_height']:.1f} mm (case: {1e3 * case.media.fill_height:.1f} mm)")
    print(comparison_table(case, measured))
    outputs = {}
    if "workpiece_force" not in run.get("series", {}):
        raise ReadError(f"{run_dir} holds no force series; the run ended before recording (status {attrs['status']})")
    outputs["forces"] = plot_drag_finishing_forces(run, case, run_dir / "forces.png")
    if render and run.get("contacts", {}).keys() - {"attrs"}:
        from .plots import render_network

        outputs["network"] = render_network(run, run_dir / "network.png")
    from .plots_chains import report_chains  # contact chains and the rod's contact intensity (issue 16)

    outputs.update(report_chains(run_dir, run, case, render))
    for name, path in outputs.items():
        print(f"{name:<8} {path}")
    return outputs


def analyze_impact_run(run_dir: Path, run: dict, case) -> dict:
    """Print an impact run's checks (measured against expected, SI units) and write forces.png."""
    import numpy as np

    from .analysis.impact import QUANTITIES, evaluate_checks
    from .verify import SceneRun, plot_force_curves

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
    scene = SceneRun(case.case.name, attrs["engine"], attrs["status"], attrs.get("message", ""), run_dir)
    series, events = run.get("series", {}), run.get("events", {})
    if "normal_force" in series:
        scene.time, scene.normal_force = series["time"], series["normal_force"]
    if "peak_time" in events:
        scene.peaks = np.column_stack([events["peak_time"], events["peak_normal_force"]])
    path = plot_force_curves([scene], run_dir / "forces.png")
    print(f"forces   {path}")
    return {"forces": path}
