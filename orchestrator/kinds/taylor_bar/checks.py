"""The Taylor bar's verification rows (`verify solids`): each checked quantity (run.h5 /measured) against the
published range of the case's [reference]: rel_error is the distance to the nearer end of the range over that
end (0 inside the range). The suite's picture: every run's final bar beside its initial outline."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.kinds.sph_flow.checks_base import check_row
from orchestrator.kinds.taylor_bar.analysis import QUANTITIES
from orchestrator.outputs import save_figure

#: Units of the checked quantities in the table.
UNITS = {name: unit for name, (unit, _) in QUANTITIES.items()}


def distance_to_range(value: float, low: float, high: float) -> tuple[float, float]:
    """(the nearer end of [low, high], |value - end| / |end|); 0 inside the range."""
    end = low if value < low else high if value > high else value
    return end, (abs(value - end) / abs(end) if end else (0.0 if value == end else math.inf))


def check_run(case, engine: str, run: dict) -> tuple[list[dict], dict]:
    """The Taylor bar's rows (one per [[expected]] row; a quantity the run did not measure fails) and its picture
    data: the last frame's (r, z) in m."""
    measured = run.get("measured", {}).get("attrs", {}) if run else {}
    name = case.case.name
    rows = []
    for row in case.expected:
        value = measured.get(row.quantity)
        if row.quantity == "energy_balance":
            rows.append(_energy_row(name, value, row.tolerance))
            continue
        published = getattr(case.reference, row.quantity)
        source = f"{case.reference.source}: {published.low:g} - {published.high:g}"
        if value is None or not math.isfinite(value):
            rows.append(check_row(name, row.quantity, None, published.low, None, row.tolerance, passed=False,
                                  source=source, note=f"{row.quantity}: not measured (the run ended early?)"))
            continue
        end, error = distance_to_range(value, published.low, published.high)
        rows.append(check_row(name, row.quantity, value, end, error, row.tolerance, source=source,
                              note=f"{row.quantity}: rel_error = distance to the published range over its nearer end"))
    return rows, {"outline": _outline(run), "radius": case.bar.radius, "length": case.bar.length}


def _energy_row(scene: str, value, tolerance: float) -> dict:
    """Kinetic plus internal energy at the end against the initial kinetic energy: rel_error = |energy_balance|."""
    known = value is not None and math.isfinite(value)
    return check_row(scene, "energy_balance", value if known else None, 0.0, abs(value) if known else None,
                     tolerance, passed=None if known else False, source="conservation",
                     note="energy_balance: (kinetic + internal energy) at the end / initial kinetic energy - 1; "
                          "rel_error = its magnitude")


def _outline(run: dict) -> tuple[list, list]:
    frames = run.get("frames", {}) if run else {}
    keys = sorted((k for k in frames if k != "attrs"), key=int)
    if not keys:
        return [], []
    x = np.asarray(frames[keys[-1]]["positions"], dtype=float)
    return np.hypot(x[:, 0], x[:, 1]).tolist(), (x[:, 2] - x[:, 2].min()).tolist()


def plot_suite(runs, path: Path) -> Path:
    """Each run's final bar in the r-z plane (mm) over its initial outline, one panel per run."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    shown = [run for run in runs if run.picture.get("outline", ([], []))[0]] or list(runs)[:1]
    fig = Figure(figsize=(3.6 * max(len(shown), 1) + 0.6, 6.0), dpi=110, layout="constrained")
    FigureCanvasAgg(fig)
    axes = np.atleast_1d(fig.subplots(1, max(len(shown), 1)))
    for ax, run in zip(axes, shown):
        r, z = run.picture.get("outline", ([], []))
        r0, l0 = run.picture.get("radius", 0.0) * 1e3, run.picture.get("length", 0.0) * 1e3
        ax.plot([0, r0, r0, 0], [0, 0, l0, l0], "k--", lw=0.8, label="initial")
        ax.plot(np.asarray(r) * 1e3, np.asarray(z) * 1e3, ".", ms=1.0, color="C0", label=f"{run.engine}, final")
        ax.set_xlim(0.0, 2.6 * r0)  # room for the legend right of the initial outline
        ax.set_ylim(-0.05 * l0, 1.12 * l0)
        ax.set_aspect("equal")
        ax.set_xlabel("r, mm")
        ax.set_title(run.scene, fontsize=8)
        ax.legend(loc="upper right", fontsize=7)
    axes[0].set_ylabel("z above the face, mm")
    return save_figure(fig, path, layout=False)
