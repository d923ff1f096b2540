"""`orchestrator analyze` on a drag-finishing run: bed height, forces against the paper's bands, the network, contact
chains and the rod's contact intensity."""

from __future__ import annotations

from pathlib import Path

from orchestrator.errors import ReadError
from orchestrator.kinds.drag_finishing.analysis import comparison_table
from orchestrator.kinds.drag_finishing.plots import plot_drag_finishing_forces, render_network
from orchestrator.kinds.drag_finishing.plots_chains import report_chains
from orchestrator.kinds.drag_finishing.plots_impacts import report_impacts


def analyze_drag_finishing_run(run_dir: Path, run: dict, case, render: bool = True) -> dict:
    """Print the comparison table and write forces.png, network.png and the chain and intensity pictures;
    returns {name: path}."""
    attrs = run["attrs"]
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
        outputs["network"] = render_network(run, run_dir / "network.png")
    outputs.update(report_chains(run_dir, run, case, render))
    outputs.update(report_impacts(run_dir, run, case, render))
    for name, path in outputs.items():
        print(f"{name:<8} {path}")
    return outputs
