"""Matplotlib pictures of an ejector-drill run: the flow and pressure series, and the SPH beside the network."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.reference.drill_network import LITRE_PER_MIN


def plot_drill_series(time, flows: dict, series: dict, stored, path: Path, names=None, titles=None,
                      beside=None) -> Path:
    """Flows (l/min) and probe pressures (bar, gauge; dashed: column outlets' chambers) against time (ms), PNG at
    path; names: the flows drawn, titles: the two panels' (default the paper's two areas'); beside: (frame times s,
    gauge pressures Pa) of the head clearance beside the jets, drawn as dots."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.0, 6.5), dpi=110, layout="constrained")
    FigureCanvasAgg(fig)
    top, bottom = fig.subplots(2, 1, sharex=True)
    t = np.asarray(time) * 1e3
    titles = titles or ("volume flows through the planes (eq. 2: V_AG = V_IB + V_loss + storage)",
                        "sensor pressures (Fig. 5: A at the hole exits, B in the annular gap)")
    for name in names or ("V_AG", "V_holes", "V_front", "V_IB", "V_loss"):
        if name in flows:
            top.plot(t, flows[name] / LITRE_PER_MIN, label=name)
    if stored is not None:
        top.plot(t, stored / LITRE_PER_MIN, "k--", lw=1, label="d(stored)/dt")
    top.set_ylabel("flow [l/min]")
    top.set_title(titles[0], fontsize=10)
    top.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # beside the axes: never over a curve
    for name in sorted(series):
        if name.startswith("pressure_probe_"):
            bottom.plot(t, np.asarray(series[name], dtype=float) / 1e5, label=name.removeprefix("pressure_probe_"))
        elif name.startswith("column_pressure_"):  # a column outlet's chamber (engine eq. OB5)
            bottom.plot(t, np.asarray(series[name], dtype=float) / 1e5, "--", lw=1,
                        label=name.removeprefix("column_pressure_") + " column")
    if beside is not None and len(beside[0]):
        bottom.plot(np.asarray(beside[0]) * 1e3, np.asarray(beside[1]) / 1e5, "k.", ms=5,
                    label="A beside the jets\n(frames)")
    bottom.set_ylabel("p [bar, gauge]")
    bottom.set_xlabel("t [ms]")
    bottom.set_title(titles[1], fontsize=10)
    bottom.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.savefig(path)
    return Path(path)


def plot_comparison(rows, path: Path, labels=None) -> Path:
    """Bars: flows (l/min) and pressures (bar) of the SPH, the network at the SPH's V_AG and at the standard
    flow (or the columns `labels` names: rows carry one value per label after name and unit); the paper's 10-20 bar
    band shaded. PNG at path."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10.0, 4.2), dpi=110, layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, 2)
    labels = labels or ("SPH", "network at the SPH's V_AG", "network at the standard flow")
    width = 0.8 / len(labels)
    for ax, unit in zip(axes, ("l/min", "bar")):
        chosen = [r for r in rows if r[1] == unit]
        x = np.arange(len(chosen))
        for k, label in enumerate(labels):
            values = [r[2 + k] if math.isfinite(r[2 + k]) else 0.0 for r in chosen]
            ax.bar(x + (k - 0.5 * (len(labels) - 1)) * width, values, width, label=label)
        if unit == "bar":
            ax.axhspan(10.0, 20.0, color="0.85", zorder=0, label="paper: 10-20 bar")
        ax.set_xticks(x, [r[0].replace(" at the SPH's B", "\n(SPH's B)") for r in chosen], fontsize=8)
        ax.set_ylabel(unit)
        ax.axhline(0.0, color="k", lw=0.5)
    axes[0].set_title("flows (missing bars: outside the scene)", fontsize=10)
    axes[1].set_title("gauge pressures", fontsize=10)
    lo, hi = axes[1].get_ylim()
    axes[1].set_ylim(lo, hi + 0.3 * (hi - lo))  # headroom: the legend above the tallest bar
    axes[1].legend(fontsize=7, ncol=2, loc="upper left")
    fig.savefig(path)
    return Path(path)
