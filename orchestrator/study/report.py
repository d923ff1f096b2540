"""`orchestrator report STUDY_DIR`: a self-contained HTML page (images
embedded as data URIs) with the study's table, wall time against error with
the Pareto front marked, and each run's force plot."""

from __future__ import annotations

import base64
import io
import json
import math
import tempfile
from pathlib import Path

from orchestrator import __version__
from orchestrator.errors import OrchestratorError
from orchestrator.kinds.drag_finishing.plots import plot_drag_finishing_forces
from orchestrator.runh5 import read_run, stored_case
from orchestrator.study.core import INDEX_NAME, STUDY_INFO, read_index_rows
from orchestrator.templating import render

#: Quantities plotted against wall time when the index has them: (column, its error column, label with units).
TRADE_OFF_QUANTITIES = (
    ("fn_mean", "fn_sem", "mean F_n on the rod [N]"),
    ("fn_std", None, "std of F_n [N]"),
    ("contact_fn_max", None, "largest contact force [N]"),
    ("contact_fn_p99", None, "99th percentile contact force [N]"),
)


def pareto_front(costs: list[float], errors: list[float]) -> list[bool]:
    """True for points no other point beats in both cost and error (ties count as not beaten)."""
    flags = []
    for i, (c, e) in enumerate(zip(costs, errors)):
        dominated = any(
            (c2 <= c and e2 <= e) and (c2 < c or e2 < e) for j, (c2, e2) in enumerate(zip(costs, errors)) if j != i
        )
        flags.append(not dominated)
    return flags


def relative_errors(values: list[float], reference: float) -> list[float]:
    """|v - ref| / |ref| for each value (nan where a value is missing)."""
    return [abs(v - reference) / abs(reference) if math.isfinite(v) else math.nan for v in values]


def _float(value) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        return math.nan


def _png(fig) -> str:
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=110)
    return base64.b64encode(buffer.getvalue()).decode()


def write_study_report(study_dir, quantity: str = "fn_mean", reference: str = "finest", tolerance: float = 0.05,
                       path=None) -> Path:
    """Write STUDY_DIR/report.html; returns its path.

    quantity: a measured column of index.csv (e.g. fn_mean, N). reference:
    'finest' (the ok run with the smallest time step, then the longest wall
    time), a run_id prefix, or a number (a closed form or a paper's value).
    The recommendation is the cheapest run whose error is within `tolerance`.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    study_dir = Path(study_dir)
    index = study_dir / INDEX_NAME
    rows = read_index_rows(study_dir)
    ok = [r for r in rows if r.get("status") == "ok" and math.isfinite(_float(r.get(quantity)))]
    if not ok:
        raise OrchestratorError(f"{study_dir}: no finished run has the quantity {quantity!r}")
    ref_row = None
    try:
        ref_value, reference_label = float(reference), f"the value {reference}"
    except ValueError:
        if reference == "finest":
            ref_row = min(ok, key=lambda r: (_float(r.get("dt")), -_float(r.get("wall_time_s"))))
        else:
            matches = [r for r in ok if r["run_id"].startswith(reference)]
            if not matches:
                raise OrchestratorError(f"no finished run's id starts with {reference!r}; use 'finest', an id or a number")
            ref_row = matches[0]
        ref_value = _float(ref_row[quantity])
        reference_label = f"run {ref_row['run_id'][:12]} ({quantity} = {ref_value:.4g})"
    if not math.isfinite(ref_value) or ref_value == 0:
        raise OrchestratorError(f"--reference {reference}: the reference {quantity} is {ref_value:g}; relative errors "
                                "need a finite, non-zero reference ('finest', a run id or a number such as 1.8)")
    walls = [_float(r["wall_time_s"]) for r in ok]
    errors = relative_errors([_float(r[quantity]) for r in ok], ref_value)
    front = pareto_front(walls, errors)

    fig = Figure(figsize=(7, 4.5), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    ax.scatter(walls, [max(e, 1e-6) for e in errors], c=["tab:green" if f else "tab:gray" for f in front])
    pts = sorted((w, max(e, 1e-6)) for w, e, f in zip(walls, errors, front) if f)
    ax.step([p[0] for p in pts], [p[1] for p in pts], where="post", color="tab:green", label="Pareto front")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time [s]")
    ax.set_ylabel(f"relative error of {quantity} [-]")
    ax.axhline(tolerance, color="tab:red", ls="--", label=f"tolerance {tolerance:g}")
    ax.legend()
    pareto_png = _png(fig)

    varied = [k for k in rows[0] if k.startswith("param:") and len({r.get(k) for r in rows}) > 1]
    candidates = [(w, e, r) for w, e, r in zip(walls, errors, ok) if e <= tolerance and r is not ref_row]
    recommendation = ""
    if candidates:
        wall, err, best = min(candidates, key=lambda item: item[0])
        recommendation = (f"{_label(best, varied or None)} on {best['engine']}: {quantity} within {100 * tolerance:g} % "
                          f"of the reference ({100 * err:.1f} %) in {wall:.1f} s")
        if ref_row is not None:
            recommendation += f", {_float(ref_row['wall_time_s']) / wall:.0f} x faster than the reference run"
    elif ok:
        recommendation = f"no run other than the reference is within {100 * tolerance:g} % of it"
    noise = _noise_note(ref_row, quantity, tolerance)
    quantities_png = _quantities_plot(ok, varied)
    info_path = study_dir / STUDY_INFO
    description = json.loads(info_path.read_text()).get("description", "") if info_path.is_file() else ""
    params = [k for k in rows[0] if k.startswith("param:")]
    header = [p.removeprefix("param:") for p in params] + ["engine", "status", "wall time [s]", quantity,
                                                           "rel. error", "run"]
    by_id = {r["run_id"]: (e, f) for r, e, f in zip(ok, errors, front)}
    table = []
    for r in rows:
        err, on_front = by_id.get(r["run_id"], (math.nan, False))
        cells = [r.get(p, "") for p in params] + [r.get("engine", ""), r.get("status", ""),
                                                  f"{_float(r.get('wall_time_s')):.1f}", f"{_float(r.get(quantity)):.4g}",
                                                  "" if math.isnan(err) else f"{err:.3g}", r["run_id"][:12]]
        table.append({"cells": cells, "pareto": on_front})
    run_plots = _run_plots(rows)
    html = render("report/study.html.j2", {
        "name": study_dir.name, "runs": rows, "quantity": quantity, "reference_label": reference_label,
        "version": __version__, "index_path": str(index), "recommendation": recommendation,
        "pareto_png": pareto_png, "header": header, "table": table, "run_plots": run_plots,
        "description": description, "noise": noise, "quantities_png": quantities_png,
    })
    out = Path(path) if path is not None else study_dir / "report.html"
    out.write_text(html)
    return out


def _run_plots(rows: list[dict]) -> list[dict]:
    """Each finished drag-finishing run's force plot, as base64 PNG."""

    plots = []
    for r in rows:
        h5 = Path(r["run_dir"]) / "run.h5"
        if r.get("status") != "ok" or not h5.is_file():
            continue
        run = read_run(h5)
        if "workpiece_force" not in run.get("series", {}):
            continue
        with tempfile.TemporaryDirectory() as tmp:
            png = plot_drag_finishing_forces(run, stored_case(run, "run.h5"), Path(tmp) / "f.png")
            data = base64.b64encode(png.read_bytes()).decode()
        title = ", ".join(f"{k.removeprefix('param:')} = {v}" for k, v in r.items() if k.startswith("param:"))
        plots.append({"title": f"{title} ({r['engine']})", "png": data})
    return plots


def _label(row: dict, varied: list[str] | None) -> str:
    """'key = value, ...' of a row's parameters (only the varied ones when given)."""
    keys = varied if varied is not None else [k for k in row if k.startswith("param:")]
    return ", ".join(f"{k.removeprefix('param:')} = {row.get(k)}" for k in keys)


def _noise_note(ref_row: dict | None, quantity: str, tolerance: float) -> str:
    """How the reference's own statistical error compares with the tolerance (drag-finishing fn_mean)."""
    if ref_row is None or quantity != "fn_mean" or not math.isfinite(_float(ref_row.get("fn_sem"))):
        return ""
    sem, value = _float(ref_row["fn_sem"]), _float(ref_row["fn_mean"])
    rel = abs(sem / value)
    # the difference of two runs' means has about sqrt(2) times one run's error; two of those is what resolves
    resolvable = 2 * math.sqrt(2) * rel
    verdict = ("differences larger than the tolerance are resolved" if resolvable < tolerance else
               f"differences below about {100 * resolvable:.0f} % are within the noise, so the tolerance of "
               f"{100 * tolerance:g} % cannot be resolved with runs this short")
    return (f"The reference's mean F_n has a standard error of {sem:.3g} N ({100 * rel:.1f} %, block averaging "
            f"over 10 blocks; an underestimate when a block is shorter than the force's correlation time); "
            f"{verdict}.")


def _quantities_plot(ok: list[dict], varied: list[str]) -> str:
    """Base64 PNG: each TRADE_OFF_QUANTITIES column present in the index against wall time, one panel each."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    present = [q for q in TRADE_OFF_QUANTITIES if any(math.isfinite(_float(r.get(q[0]))) for r in ok)]
    if not present:
        return ""
    fig = Figure(figsize=(7, 2.6 * len(present)), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(len(present), 1, sharex=True, squeeze=False)[:, 0]
    walls = [_float(r["wall_time_s"]) for r in ok]
    for ax, (column, error_column, label) in zip(axes, present):
        values = [_float(r.get(column)) for r in ok]
        errors = [_float(r.get(error_column)) if error_column else 0.0 for r in ok]
        ax.errorbar(walls, values, yerr=[e if math.isfinite(e) else 0.0 for e in errors], fmt="o", capsize=3)
        for w, v, r in zip(walls, values, ok):
            ax.annotate(_label(r, varied).replace("numerics.", ""), (w, v), fontsize=6, xytext=(3, 3),
                        textcoords="offset points")
        ax.set_ylabel(label, fontsize=8)
        ax.set_xscale("log")
    axes[-1].set_xlabel("wall time [s]")
    return _png(fig)
