"""The network study's pictures (sensitivity.py): a tornado chart of the feed pressure per parameter over the scanned
factors, and the map of the feed pressure over the ejector nozzles' area and the annular gap with the paper's
10-20 bar band. Pressures in bar (gauge), areas in mm^2, gaps in mm."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.kinds.ejector_drill.comparison import PAPER_BAR
from orchestrator.kinds.ejector_drill.sensitivity import BY_NAME, AreaGapMap, Point
from orchestrator.plots import save_pyplot_figure


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def spans(points: list[Point]) -> list[tuple[str, float, float]]:
    """(parameter, lowest, highest p_feed_bar over its buildable points) per parameter, widest first."""
    out = {}
    for p in points:
        if p.buildable:
            low, high = out.get(p.parameter, (math.inf, -math.inf))
            out[p.parameter] = (min(low, p.p_feed_bar), max(high, p.p_feed_bar))
    return sorted(((k, lo, hi) for k, (lo, hi) in out.items()), key=lambda s: s[2] - s[1], reverse=True)


def plot_tornado(points: list[Point], base: Point, base_values: dict, flow_lpm: float, path: Path) -> Path:
    """Tornado chart: per parameter (widest spread on top) the feed pressure (bar gauge) at each factor, a marker
    coloured by the factor, round where the ejector draws (V_loss < 0) and a triangle where it leaks, hollow where
    the geometry cannot be built; the case's p_feed and the paper's band drawn across. base_values: {parameter:
    its case value, SI}."""
    plt = _pyplot()
    order = [name for name, _, _ in spans(points)]
    order += [n for n in dict.fromkeys(p.parameter for p in points) if n not in order]
    factors = sorted({p.factor for p in points})
    colours = plt.get_cmap("coolwarm")(np.linspace(0.0, 1.0, len(factors)))
    fig, ax = plt.subplots(figsize=(8.6, 0.3 * len(order) + 1.9))
    ax.axvspan(*PAPER_BAR, color="0.88", zorder=0)
    ax.axvline(base.p_feed_bar, color="k", lw=0.8, zorder=1)
    for row, name in enumerate(order):
        mine = [p for p in points if p.parameter == name and math.isfinite(p.p_feed_bar)]
        built = [p.p_feed_bar for p in mine if p.buildable] + [base.p_feed_bar]
        ax.plot([min(built), max(built)], [row, row], color="0.55", lw=2.5, solid_capstyle="butt", zorder=2)
        for p in mine:
            colour = colours[factors.index(p.factor)]
            ax.plot(p.p_feed_bar, row, "o" if p.V_loss < 0.0 else "^", ms=6.5, mec=colour,
                    mfc=colour if p.buildable else "none", mew=1.4, zorder=3)
    ax.set_yticks(range(len(order)), [_tick(name, base_values.get(name, math.nan)) for name in order], fontsize=8)
    ax.set_ylim(len(order) - 0.5, -0.5)
    ax.set_xlabel("feed pressure p_feed [bar gauge]")
    ax.grid(True, axis="x", lw=0.3, alpha=0.6)
    handles = [ax.plot([], [], "o", color=c, ms=6.5)[0] for c in colours]
    labels = [f"x {f:g}" for f in factors]
    handles += [ax.plot([], [], "^", color="0.4", ms=6.5)[0], ax.plot([], [], "o", mec="0.4", mfc="none")[0],
                plt.Rectangle((0, 0), 1, 1, color="0.88")]
    labels += ["leaks (V_loss > 0)", "cannot be built", f"paper {PAPER_BAR[0]:g}-{PAPER_BAR[1]:g} bar"]
    ax.legend(handles, labels, fontsize=7.5, loc="lower right", ncol=2, framealpha=0.95)
    ax.set_title(f"1D network at {flow_lpm:g} l/min: one parameter times a factor, the rest at the case's values\n"
                 f"case: p_feed = {base.p_feed_bar:.1f} bar, V_loss = {base.V_loss:+.1f} l/min (vertical line)",
                 fontsize=9)
    return save_pyplot_figure(fig, path)


def _tick(name: str, value: float) -> str:
    p = BY_NAME[name]
    shown = value * p.scale
    return f"{p.label} ({shown:.3g} {p.unit})" if p.unit != "-" else f"{p.label} ({shown:.3g})"


def plot_area_gap_map(m: AreaGapMap, count: int, path: Path) -> Path:
    """The feed pressure (bar gauge, colours) over the nozzles' total area (mm^2; top axis: the diameter of each of
    count nozzles, mm) and the gap d_Diff (mm): the paper's 10-20 bar band lightened between its two lines, hatched
    where the ejector leaks (V_loss > 0, its edge dashed), the jet pump's cavitation limit dotted, the case marked."""
    plt = _pyplot()
    area, gap = m.areas * 1e6, m.gaps * 1e3
    p = np.where(m.buildable, m.p_feed_bar, np.nan)
    fig, ax = plt.subplots(figsize=(7.6, 5.6))
    levels = np.arange(0.0, 65.0, 5.0)
    filled = ax.contourf(area, gap, np.clip(p, levels[0], levels[-1]), levels=levels, cmap="viridis", extend="max")
    fig.colorbar(filled, ax=ax, label="feed pressure p_feed [bar gauge]", pad=0.02)
    ax.contourf(area, gap, p, levels=list(PAPER_BAR), colors="w", alpha=0.35)
    band = ax.contour(area, gap, p, levels=list(PAPER_BAR), colors="w", linewidths=1.6)
    ax.clabel(band, fmt=lambda v: f"{v:g} bar", fontsize=8.5, colors="w", inline_spacing=6,
              manual=_label_spots(band, area, gap))
    leaks = np.where(m.buildable, m.V_loss, np.nan)
    ax.contourf(area, gap, leaks, levels=[0.0, np.nanmax(leaks) + 1.0], colors="none", hatches=["///"])
    ax.contour(area, gap, leaks, levels=[0.0], colors="orangered", linewidths=1.6, linestyles="--")
    margin = np.where(m.buildable, m.p_mixing_bar - m.p_vapour_bar, np.nan)
    if np.nanmin(margin) < 0.0 < np.nanmax(margin):
        ax.contour(area, gap, margin, levels=[0.0], colors="k", linewidths=1.6, linestyles=":")
    ax.plot(m.base_area * 1e6, m.base_gap * 1e3, "X", color="w", mec="k", ms=10)
    ax.annotate("case", (m.base_area * 1e6, m.base_gap * 1e3), xytext=(8, 6), textcoords="offset points",
                color="w", fontsize=9, fontweight="bold")
    ax.set_xlabel(f"ejector nozzles' total area [mm^2] ({count} nozzles)")
    ax.set_ylabel("annular gap d_Diff (diametral) [mm]")

    def diameter(a):
        return np.sqrt(4.0 * np.maximum(a, 1e-12) / (math.pi * count))

    def area_of(d):
        return 0.25 * math.pi * count * np.asarray(d) ** 2

    top = ax.secondary_xaxis("top", functions=(diameter, area_of))
    top.set_xlabel(f"diameter of each of the {count} nozzles [mm]", fontsize=9)
    handles = [plt.Rectangle((0, 0), 1, 1, fc="0.75", ec="w", lw=1.6),
               plt.Rectangle((0, 0), 1, 1, fc="0.9", ec="0.3", hatch="///"),
               plt.Line2D([], [], color="orangered", lw=1.6, ls="--"), plt.Line2D([], [], color="k", lw=1.6, ls=":")]
    labels = [f"paper {PAPER_BAR[0]:g}-{PAPER_BAR[1]:g} bar", "V_loss > 0: the ejector leaks", "V_loss = 0",
              "cavitation limit (below: cavitates)"]
    ax.legend(handles, labels, fontsize=7.5, loc="upper right", facecolor="0.92", framealpha=0.95)
    ax.set_title(f"1D network at {m.flow_lpm:g} l/min: feed pressure over nozzle area and gap", fontsize=9)
    return save_pyplot_figure(fig, path)


def _label_spots(contours, area, gap) -> list[tuple[float, float]]:
    """One label position per contour line, the point of its longest path nearest the plot's lower middle."""
    target = np.array([0.55 * area[0] + 0.45 * area[-1], gap[0] + 0.25 * (gap[-1] - gap[0])])
    scale = np.array([area[-1] - area[0], gap[-1] - gap[0]])
    spots = []
    for segs in contours.allsegs:
        longest = max(segs, key=len, default=None)
        if longest is None or len(longest) == 0:
            continue
        k = int(np.argmin(np.hypot(*((longest - target) / scale).T)))
        spots.append(tuple(longest[k]))
    return spots
