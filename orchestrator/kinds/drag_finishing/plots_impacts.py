"""Pictures of the rod impacts (contact starts, impacts.py) and ``report_impacts``, the part of ``orchestrator
analyze`` that prints and draws them for a drag-finishing run (matplotlib, Agg, no pyplot state).

impact_speeds.png   left: histogram (log counts) of the normal impact speeds (mm/s) of the recorded contact starts, with the
                    frames' approach-speed proxy (balls within 10 % of R_b of the rod, moving towards it) as an
                    outline; right: where they hit, the rod unrolled (angle around the rod, height), coloured by
                    speed
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from orchestrator.kinds.drag_finishing.impacts import impact_summary, impact_text
from orchestrator.kinds.drag_finishing.intensity import frame_approach_speeds
from orchestrator.kinds.drag_finishing.plots_chains import figure, save


def plot_impact_speeds(res: dict | None, proxy: np.ndarray, rod_tip: float, bed_height: float, path) -> Path:
    """The figure described in the module docstring; res from impacts.impact_summary() (None: proxy only), proxy
    approach speeds in m/s, rod_tip and bed_height in m."""
    fig = figure(11.0, 4.4)
    ax_h, ax_m = fig.subplots(1, 2, width_ratios=[1.0, 1.3])
    speeds = 1e3 * (res["speed"] if res is not None else np.zeros(0))
    proxy = 1e3 * np.asarray(proxy, float)
    both = np.concatenate([speeds, proxy])
    bins = np.linspace(0.0, max(float(both.max(initial=0.0)), 1e-3) * 1.02, 31)
    if speeds.size:
        ax_h.hist(speeds, bins=bins, color="C0", edgecolor="white",
                  label=f"contact starts ({speeds.size}), median {np.median(speeds):.1f} mm/s")
    if proxy.size:
        ax_h.hist(proxy, bins=bins, histtype="step", color="C3", lw=1.2,
                  label=f"approach-speed proxy from frames ({proxy.size})")
    if both.size:
        ax_h.legend(fontsize=8)
    ax_h.set_yscale("log")
    ax_h.set_xlabel("normal impact speed relative to the rod surface [mm/s]")
    ax_h.set_ylabel("contacts (log scale)")
    ax_h.grid(True, color="0.93", lw=0.5)
    if res is not None and speeds.size:
        t0, t1 = res["window"]
        order = np.argsort(speeds)
        top = max(float(np.percentile(speeds, 99)), 1e-3)
        sc = ax_m.scatter(res["phi"][order], 1e3 * res["z"][order], c=speeds[order], cmap="viridis", s=14,
                          edgecolors="0.3", linewidths=0.3, vmin=0.0, vmax=top)
        fig.colorbar(sc, ax=ax_m, pad=0.01, extend="max").set_label("impact speed [mm/s] (top: 99th percentile)")
        ax_m.set_title(f"where the balls hit the rod, {t0:g} to {t1:g} s of process (ball centres)", fontsize=10)
    else:
        ax_m.text(0.5, 0.5, "no contact starts recorded\n(output.impact_window)", transform=ax_m.transAxes,
                  ha="center", va="center")
    ax_m.set_xlim(-180, 180)
    ax_m.set_xticks(np.arange(-180, 181, 45))
    ax_m.set_ylim(1e3 * rod_tip - 5.0, 1e3 * bed_height + 5.0)
    ax_m.set_xlabel("angle around the rod [deg] (0 front, 90 outer side, 180 back)")
    ax_m.set_ylabel("height above the bowl floor [mm]")
    ax_m.grid(True, color="0.93", lw=0.5)
    return save(fig, path)


def report_impacts(run_dir, run: dict, case, render: bool = True) -> dict:
    """Print the impact summary of a drag-finishing run and, when render, write impact_speeds.png into run_dir;
    returns {name: path}."""
    model = getattr(case, "model", case)
    if "rod" not in run.get("meshes", {}):
        return {}
    res = impact_summary(run)
    print(impact_text(res))
    if not render:
        return {}
    rod_tip = float(np.asarray(run["meshes"]["rod"]["vertices"], float)[:, 2].min())
    bed = float(run.get("attrs", {}).get("bed_height", model.media.fill_height))
    return {"impacts": plot_impact_speeds(res, frame_approach_speeds(run), rod_tip, bed,
                                          Path(run_dir) / "impact_speeds.png")}
