"""The picture of `verify sph`: one panel per scene run (its check's profiles, pressures, fronts, wall forces or
stresses against their references), from the panels the kinds' checks return."""

from __future__ import annotations

import math
from pathlib import Path

from orchestrator.plots import save_pyplot_figure


def plot_scenes(runs: list, path: Path) -> Path:
    """PNG: one panel per scene run (profiles against the series, pressure against depth, front against the
    measurements, wall forces, stresses). runs: workflows.base.CheckedRun whose picture is a panel: title, xlabel,
    ylabel and lines [(x, y, fmt, colour, label)] in the units the labels state."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs = [r for r in runs if r.picture]
    columns = min(3, max(1, len(runs)))
    rows = max(1, math.ceil(len(runs) / columns))
    fig, axes = plt.subplots(rows, columns, figsize=(4.6 * columns, 3.6 * rows), squeeze=False)
    for ax, run in zip(axes.ravel(), runs):
        for x, y, fmt, colour, label in run.picture["lines"]:
            style = dict(color=colour, label=label)
            if fmt in ("-", "--"):
                ax.plot(x, y, fmt, lw=1.2, **style)
            else:
                ax.plot(x, y, fmt, ms=2.5 if fmt == "." else 4, mfc="none" if fmt != "." else None, **style)
        status = "" if run.status == "ok" else f" ({run.status})"
        ax.set_title(run.picture["title"] + status, fontsize=8)
        ax.set_xlabel(run.picture["xlabel"], fontsize=8)
        ax.set_ylabel(run.picture["ylabel"], fontsize=8)
        ax.tick_params(labelsize=7)
        ax.legend(fontsize=6)
    for ax in axes.ravel()[len(runs):]:
        ax.set_visible(False)

    return save_pyplot_figure(fig, path)
