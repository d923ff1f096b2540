"""A channel study's own report section (Kind.study_pictures): the wear against the flow's speed, one point per
finished run: the contact force, the largest plastic strain and the removed volume against the grain's mean
speed."""

from __future__ import annotations

import math

from orchestrator.plots import figure_png, number_or_nan

#: (column, scale to the plotted unit, axis label) of the panels.
PANELS = (
    ("contact_force_max", 1e3, "largest contact force, mN"),
    ("max_plastic_strain", 1.0, "largest plastic strain, -"),
    ("removed_volume", 1e18, "removed volume, um^3"),
)
#: Resolution of the study picture, dots per inch.
DPI = 110


def channel_study_pictures(rows: list[dict], quantity: str, reference: dict | None, tolerance: float) -> list[dict]:
    """[{"title", "note", "png"}]: the wear panels against grain_speed_mean (m/s) of the finished runs; [] when no
    run has finished. quantity, reference and tolerance (the report's comparison) are not used here."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    done = [r for r in rows if r.get("status") == "ok" and math.isfinite(number_or_nan(r.get("grain_speed_mean")))]
    if not done:
        return []
    done.sort(key=lambda r: number_or_nan(r["grain_speed_mean"]))
    speed = [number_or_nan(r["grain_speed_mean"]) for r in done]
    fig = Figure(figsize=(6.4, 2.2 * len(PANELS)), dpi=DPI, layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(len(PANELS), 1, sharex=True)
    for ax, (column, scale, label) in zip(axes, PANELS):
        values = [number_or_nan(r.get(column, 0.0)) * scale for r in done]
        ax.plot(speed, values, "o-", color="C0")
        ax.set_ylabel(label, fontsize=8)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("the grain's mean speed over the run, m/s")
    note = ("Each point is one run; its speed is the grain's mean along the channel (set by medium.body_force). "
            "Volumes of whole particles: dx^3 each.")
    return [{"title": "Wear against the flow's speed", "note": note, "png": figure_png(fig)}]
