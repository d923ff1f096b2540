"""A drag-finishing study's own report sections: the force statistics against wall time (with what the reference's
noise can resolve) and each finished run's force plot (Kind.study_pictures)."""

from __future__ import annotations

import math
import tempfile
from pathlib import Path

from orchestrator.errors import ReadError
from orchestrator.kinds.drag_finishing.plots import plot_drag_finishing_forces
from orchestrator.plots import figure_png, number_or_nan, parameter_label, place_point_labels, plain_log_ticks
from orchestrator.runh5 import read_run, stored_case

#: Quantities plotted against wall time when the index has them: (column, its error column, label with units).
TRADE_OFF_QUANTITIES = (
    ("fn_mean", "fn_sem", "mean F_n on the rod [N]"),
    ("fn_std", None, "std of F_n [N]"),
    ("contact_fn_max", None, "largest contact force [N]"),
    ("contact_fn_p99", None, "99th percentile contact force [N]"),
)
#: Resolution of the study pictures, dots per inch (the figure is laid out and saved at the same one).
DPI = 110
#: Force plots drawn per report (about 100 kB each, embedded in the page); the table lists every run.
MAX_RUN_PLOTS = 24


def drag_finishing_study_pictures(rows: list[dict], quantity: str, reference: dict | None,
                                  tolerance: float) -> list[dict]:
    """The study report's drag-finishing sections: [{"title", "note", "png" (bytes)}].

    rows: the study's index rows (run_dir pointing at each run; a point is labelled with its varied parameters,
    or with its number, its 1-based position in rows, where those do not fit); quantity and reference: the
    report's compared column and reference row (None for a number); tolerance: relative error accepted (-).
    A section whose png is b"" is a note alone.
    """
    sections = []
    figure = quantities_figure(rows)
    if figure is not None:
        note = "Error bars: standard error of the mean by block averaging, where the run has it."
        noise = noise_note(reference, quantity, tolerance)
        sections.append({"title": "Measured quantities against wall time", "note": f"{note} {noise}".strip(),
                         "png": figure_png(figure)})
    return sections + run_force_plots(rows)


def quantities_figure(rows: list[dict]):
    """A matplotlib Figure: each TRADE_OFF_QUANTITIES column present in the finished rows against wall time (s),
    one panel each, points labelled; None when no row has any of them."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    numbered = [(n, r) for n, r in enumerate(rows, 1)
                if r.get("status") == "ok" and number_or_nan(r.get("wall_time_s")) > 0]
    present = [q for q in TRADE_OFF_QUANTITIES if any(math.isfinite(number_or_nan(r.get(q[0]))) for _, r in numbered)]
    if not present:
        return None
    fig = Figure(figsize=(7, 2.6 * len(present)), dpi=DPI, layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(len(present), 1, sharex=True, squeeze=False)[:, 0]
    walls = [number_or_nan(r["wall_time_s"]) for _, r in numbered]
    varied = _varied(rows)
    for ax, (column, error_column, label) in zip(axes, present):
        values = [number_or_nan(r.get(column)) for _, r in numbered]
        errors = [number_or_nan(r.get(error_column)) if error_column else 0.0 for _, r in numbered]
        ax.errorbar(walls, values, yerr=[e if math.isfinite(e) else 0.0 for e in errors], fmt="o", capsize=3)
        ax.set_ylabel(label, fontsize=8)
        ax.set_xscale("log")
        ax.margins(x=0.15, y=0.2)  # room for the labels beside the outermost points
        plain_log_ticks(ax.xaxis)
    axes[-1].set_xlabel("wall time [s]")
    for ax, (column, error_column, _) in zip(axes, present):
        values = [number_or_nan(r.get(column)) for _, r in numbered]
        errors = [number_or_nan(r.get(error_column)) if error_column else 0.0 for _, r in numbered]
        place_point_labels(ax, walls, values, [parameter_label(r, varied) for _, r in numbered],
                           [f"#{n}" for n, _ in numbered], yerr=errors)
    return fig


def noise_note(reference: dict | None, quantity: str, tolerance: float) -> str:
    """How the reference's own statistical error of the mean F_n compares with the tolerance ('' unless the
    compared quantity is fn_mean and the reference run has its standard error)."""
    if reference is None or quantity != "fn_mean" or not math.isfinite(number_or_nan(reference.get("fn_sem"))):
        return ""
    sem, value = number_or_nan(reference["fn_sem"]), number_or_nan(reference["fn_mean"])
    rel = abs(sem / value)
    # the difference of two runs' means has about sqrt(2) times one run's error; two of those is what resolves
    resolvable = 2 * math.sqrt(2) * rel
    verdict = ("differences larger than the tolerance are resolved" if resolvable < tolerance else
               f"differences below about {100 * resolvable:.0f} % are within the noise, so the tolerance of "
               f"{100 * tolerance:g} % cannot be resolved with runs this short")
    return (f"The reference's mean F_n has a standard error of {sem:.3g} N ({100 * rel:.1f} %, block averaging "
            f"over 10 blocks; an underestimate when a block is shorter than the force's correlation time); "
            f"{verdict}.")


def run_force_plots(rows: list[dict]) -> list[dict]:
    """The force plot (plot_drag_finishing_forces) of each finished run, up to MAX_RUN_PLOTS, titled with its
    number and parameters; a closing note names how many were left out."""
    sections = []
    stored = [(n, row) for n, row in enumerate(rows, 1)
              if row.get("status") == "ok" and (Path(row.get("run_dir", "")) / "run.h5").is_file()]
    for number, row in stored[:MAX_RUN_PLOTS]:
        h5 = Path(row["run_dir"]) / "run.h5"
        try:
            run = read_run(h5)
            if "workpiece_force" not in run.get("series", {}):
                continue
            case = stored_case(run, h5)
        except ReadError:
            continue  # the table still lists the run; a damaged run.h5 only loses its picture
        with tempfile.TemporaryDirectory() as tmp:
            png = plot_drag_finishing_forces(run, case, Path(tmp) / "forces.png").read_bytes()
        params = ", ".join(f"{k.removeprefix('param:')} = {v}" for k, v in row.items() if k.startswith("param:"))
        title = f"Run #{number}: {params} ({row.get('engine', '?')})"
        sections.append({"title": title, "note": "", "png": png})
    if len(stored) > MAX_RUN_PLOTS:
        sections.append({"title": "Other runs", "png": b"",
                         "note": f"The force plots of {len(stored) - MAX_RUN_PLOTS} more finished runs are left out "
                                 f"(at most {MAX_RUN_PLOTS} per page): orchestrator analyze RUN_DIR draws any run's."})
    return sections


def _varied(rows: list[dict]) -> list[str]:
    """The index's parameter columns whose value differs between rows."""
    return [k for k in (rows[0] if rows else {}) if k.startswith("param:") and len({r.get(k) for r in rows}) > 1]
