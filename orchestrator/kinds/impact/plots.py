"""Pictures of impact runs: normal force against time per scene and engine, contact peaks marked."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from orchestrator.plots import save_pyplot_figure


@dataclass
class ForceCurve:
    """One impact scene on one engine, as plotted: time (n,) s, normal_force (n,) N, peaks (k, 2) [s, N]."""

    scene: str
    engine: str
    status: str
    time: object = None
    normal_force: object = None
    peaks: object = None


def plot_force_curves(runs: list, path: Path) -> Path:
    """PNG: one panel per scene with the normal force against time of every engine (peaks marked), N vs s.

    runs: ForceCurve-like objects (scene, engine, status, time, normal_force, peaks).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    scenes = list(dict.fromkeys(run.scene for run in runs))
    engines = list(dict.fromkeys(run.engine for run in runs))
    colours = {engine: f"C{k}" for k, engine in enumerate(engines)}
    columns = min(4, len(scenes))
    rows = math.ceil(len(scenes) / columns)
    fig, axes = plt.subplots(rows, columns, figsize=(4.2 * columns, 3.0 * rows), squeeze=False)
    for ax, scene in zip(axes.ravel(), scenes):
        for k, run in enumerate(r for r in runs if r.scene == scene):
            style = dict(color=colours[run.engine], lw=1.2, ls="-" if k == 0 else "--")
            label = run.engine + ("" if run.status == "ok" else f" ({run.status})")
            if run.time is not None and len(run.time):
                ax.plot(np.asarray(run.time) * 1e3, run.normal_force, label=label, **style)
            if run.peaks is not None and len(run.peaks):
                ax.plot(run.peaks[:, 0] * 1e3, run.peaks[:, 1], "o", mfc="none", color=colours[run.engine], ms=5,
                        label=None if run.time is not None else label)
                recorded = np.max(run.normal_force, initial=0.0) if run.time is not None else 0.0
                if recorded < 0.8 * run.peaks[:, 1].max():  # contacts shorter than the record interval: stems
                    ax.vlines(run.peaks[:, 0] * 1e3, 0.0, run.peaks[:, 1], color=colours[run.engine], lw=1.0,
                              ls=style["ls"])
        ax.set_title(scene, fontsize=8)
        ax.set_xlabel("time [ms]", fontsize=8)
        ax.set_ylabel("normal force [N]", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.legend(fontsize=7)
    for ax in axes.ravel()[len(scenes):]:
        ax.set_visible(False)
    title = "contact normal force per verification scene (lines: recorded series; circles: each contact's peak)"
    fig.suptitle(title if columns > 1 else title.replace(" (", "\n("), fontsize=9)  # one panel: too narrow
    return save_pyplot_figure(fig, path)


def plot_compare_curves(runs: list[tuple[str, dict]], case, path: Path) -> Path | None:
    """`compare`'s picture of an impact case: the normal force (N) against time (ms) of every engine in one panel,
    each contact's peak marked. runs: (label, runh5.read_run dict) per engine."""
    import numpy as np

    curves = []
    for label, run in runs:
        series, events = run.get("series", {}), run.get("events", {})
        curve = ForceCurve(case.case.name, label, "ok")
        if "normal_force" in series:
            curve.time, curve.normal_force = series["time"], series["normal_force"]
        if "peak_time" in events:
            curve.peaks = np.column_stack([events["peak_time"], events["peak_normal_force"]])
        curves.append(curve)
    return plot_force_curves(curves, path) if curves else None
