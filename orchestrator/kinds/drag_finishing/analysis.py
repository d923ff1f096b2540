"""Drag finishing: mean +- standard deviation of the force on the rod after
the start-up transient, next to the paper's simulated and measured values;
`orchestrator analyze` of a run (the table, the forces, the network, the contact
chains and the rod's contact intensity).

Transient criterion: the first ``analysis.transient_time`` seconds of the
process phase are discarded (the case file gives the value and its reason).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.errors import ReadError
from orchestrator.kinds.drag_finishing.forces import (contact_force_peaks, force_statistics, process_series,
                                                      standard_error)
from orchestrator.kinds.drag_finishing.plots import plot_drag_finishing_forces, render_network
from orchestrator.kinds.drag_finishing.plots_chains import report_chains
from orchestrator.kinds.drag_finishing.plots_impacts import report_impacts

#: The measured quantities (measure_drag_finishing): name -> (SI unit, meaning).
QUANTITIES: dict[str, tuple[str, str]] = {
    **{f"{c}_{stat}": ("N", f"F_{c[1]} on the rod after the transient, {what}")
       for c in ("fn", "ft", "fv") for stat, what in (("mean", "mean"), ("std", "standard deviation"))},
    "fn_sem": ("N", "standard error of fn_mean (block averages)"),
    "fn_peak": ("N", "the F_n sample of largest magnitude after the transient"),
    "contact_fn_max": ("N", "largest normal contact force of the last network snapshot"),
    "contact_fn_p99": ("N", "99th percentile of the normal contact forces of the last network snapshot"),
    "bed_height": ("m", "height of the settled bed"),
    "n_samples": ("-", "force samples after the transient"),
    "process_time_simulated": ("s", "process time the run reached"),
}


def measure_drag_finishing(case, result) -> dict[str, float]:
    """fn/ft/fv mean and std (N) after the transient, fn_sem (block-averaged standard error of fn_mean,
    N), fn_peak (the F_n sample of largest magnitude, N), the peak contact forces of the last network
    snapshot (contact_fn_max, contact_fn_p99, N), the settled bed height (m) and the sample count."""
    out: dict[str, float] = {}
    if "bed_height" in result.attrs:
        out["bed_height"] = float(result.attrs["bed_height"])
    if result.time is None or "workpiece_force" not in result.series:
        return out
    start = result.attrs.get("process_start_time", math.nan)
    if start is None or not np.isfinite(start):
        return out
    t, f = process_series(result.time, result.series["phase"].values, result.series["workpiece_force"].values, start)
    out.update(force_statistics(t, f, case.analysis.transient_time))
    keep = (t >= case.analysis.transient_time) & np.isfinite(f[:, 0])
    out["fn_sem"] = standard_error(f[keep, 0])
    out["fn_peak"] = float(f[keep, 0][np.argmax(np.abs(f[keep, 0]))]) if keep.any() else math.nan
    out["process_time_simulated"] = float(t.max()) if t.size else 0.0
    out.update(contact_force_peaks(result.contacts))
    return out


def comparison_rows(case, measured: dict) -> list[dict]:
    """Rows [source, F_n mean, F_n std, F_t mean, F_t std] (N) for this run and the case's references."""
    rows = [
        {
            "source": "this run",
            "fn_mean": measured.get("fn_mean", math.nan),
            "fn_std": measured.get("fn_std", math.nan),
            "ft_mean": measured.get("ft_mean", math.nan),
            "ft_std": measured.get("ft_std", math.nan),
        }
    ]
    for ref in case.reference:
        rows.append({"source": ref.label, "fn_mean": ref.fn_mean, "fn_std": ref.fn_std, "ft_mean": math.nan, "ft_std": math.nan})
    return rows


def comparison_table(case, measured: dict) -> str:
    """A plain-text table of this run's forces against the references, with relative differences of mean F_n."""
    rows = comparison_rows(case, measured)
    ours = rows[0]["fn_mean"]
    fmt = lambda v: "   -   " if not np.isfinite(v) else f"{v:7.3f}"  # noqa: E731
    lines = [
        f"force on the rod after the {case.analysis.transient_time:g} s transient "
        f"({measured.get('n_samples', 0)} samples, mean +- std, N)",
        f"{'source':<28} {'F_n mean':>8} {'F_n std':>8} {'F_t mean':>8} {'F_t std':>8}  {'ours vs F_n':>11}",
    ]
    for row in rows:
        rel = "" if row["source"] == "this run" or not np.isfinite(ours) else f"{100 * (ours - row['fn_mean']) / abs(row['fn_mean']):+10.1f}%"
        lines.append(
            f"{row['source']:<28} {fmt(row['fn_mean']):>8} {fmt(row['fn_std']):>8} "
            f"{fmt(row['ft_mean']):>8} {fmt(row['ft_std']):>8}  {rel:>11}"
        )
    return "\n".join(lines)


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


def reference_table(case, runs: list[tuple[str, dict]]):
    """`compare`'s table of the force on the rod: per engine that ran (runs: [(engine, measured)]) F_n and F_t
    mean and std and fn_sem (N), and against each of the case's references the relative difference of its mean F_n
    and whether it lies in the reference's band (mean +- std); then the references. Returns (title, header, cells,
    rows); rows are the JSON objects (source, fn_mean, fn_std, fn_sem, ft_mean, ft_std, and against: [{reference,
    fn_rel_difference, in_band}] for an engine)."""
    references = comparison_rows(case, {})[1:]
    rows = []
    for engine, measured in runs:
        row = {**comparison_rows(case, measured)[0], "source": engine,
               "fn_sem": _number(measured.get("fn_sem")), "against": []}
        for ref in references:
            rel = (row["fn_mean"] - ref["fn_mean"]) / abs(ref["fn_mean"]) if ref["fn_mean"] else math.nan
            row["against"].append({"reference": ref["source"], "fn_rel_difference": rel,
                                   "in_band": bool(abs(row["fn_mean"] - ref["fn_mean"]) <= ref["fn_std"])})
        rows.append(row)
    rows += [{**ref, "fn_sem": math.nan} for ref in references]
    header = ["source", "F_n mean", "F_n std", "F_n sem", "F_t mean", "F_t std"] + [
        f"F_n vs {ref['source']}" for ref in references]
    cells = []
    for row in rows:
        line = [row["source"]] + [_cell(row[k]) for k in ("fn_mean", "fn_std", "fn_sem", "ft_mean", "ft_std")]
        for against in row.get("against", []):
            line.append(f"{_signed_percent(against['fn_rel_difference'])} "
                        f"({'in band' if against['in_band'] else 'outside band'})")
        cells.append(line + [""] * (len(header) - len(line)))
    title = (f"force on the rod after the {case.analysis.transient_time:g} s transient, N (mean, standard deviation, "
             "standard error of the mean), engines and the case's references")
    return title, header, cells, rows


def _number(value) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        return math.nan


def _cell(value) -> str:
    return "-" if not math.isfinite(value) else format(value, ".4g")


def _signed_percent(fraction: float) -> str:
    return "-" if not math.isfinite(fraction) else f"{100.0 * fraction:+.2g} %"
