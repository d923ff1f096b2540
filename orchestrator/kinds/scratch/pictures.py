"""The scratch's picture (`orchestrator analyze`), after Nutto et al.'s Fig. 1: the target's surface seen from
above coloured by plastic strain with the removed particles marked, and the section through the kerf's middle."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from orchestrator.kinds.sph_flow.removal import removed
from orchestrator.outputs import save_figure


def plot_scratch(run: dict, case, path: Path) -> Path:
    """Top: the particles of the top layer (at the start) as they are at the end, seen from above and coloured
    by plastic strain, removed particles as red dots, the grain's path dashed (um). Bottom: the lattice rows
    nearest y = 0 at the start, seen from the side, the same colours."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    dx = case.numerics.dx
    fig = Figure(figsize=(9.0, 7.6), dpi=120, layout="constrained")
    FigureCanvasAgg(fig)
    top, side = fig.subplots(2, 1, height_ratios=[1.0, 0.75])
    frames = run.get("frames", {})
    keys = sorted((k for k in frames if k != "attrs"), key=int)
    measured = run.get("measured", {}).get("attrs", {})
    if keys:
        first, last = frames[keys[0]], frames[keys[-1]]
        moving = np.asarray(first["kind"]) == 0
        x0 = np.asarray(first["positions"], dtype=float)
        x = np.asarray(last["positions"], dtype=float)
        eps = np.asarray(last.get("plastic_strain", np.zeros(len(x))), dtype=float)
        damage = np.asarray(last.get("damage", np.zeros(len(x))), dtype=float)
        gone = removed(x, np.where(moving, damage, 0.0), np.ones(len(x), dtype=bool), dx) & moving
        vmax = max(float(np.percentile(eps[moving], 99.5)), 1e-3)
        layer = moving & (x0[:, 2] > -dx) & ~gone
        points = top.scatter(x[layer, 0] * 1e6, x[layer, 1] * 1e6, c=eps[layer], s=6.0, cmap="viridis", vmin=0.0,
                             vmax=vmax)
        section = moving & (np.abs(x0[:, 1]) < 0.75 * dx) & ~gone
        side.scatter(x[section, 0] * 1e6, x[section, 2] * 1e6, c=eps[section], s=8.0, cmap="viridis", vmin=0.0,
                     vmax=vmax)
        for axes, (i, j) in ((top, (0, 1)), (side, (0, 2))):
            if gone.any():
                shown = gone if axes is top else gone & (np.abs(x[:, 1]) < 3.0 * dx)
                axes.scatter(x[shown, i] * 1e6, x[shown, j] * 1e6, s=6.0, color="C3",
                             label=f"removed ({int(gone.sum())} particles)")
        fig.colorbar(points, ax=[top, side], label="equivalent plastic strain", shrink=0.8)
    series = run.get("series", {})
    path_xz = np.asarray(series.get("impactor_grain_position", np.zeros((1, 3))), dtype=float)
    top.plot(path_xz[:, 0] * 1e6, path_xz[:, 1] * 1e6, "--", color="k", lw=1.0, label="grain's centre")
    side.plot(path_xz[:, 0] * 1e6, path_xz[:, 2] * 1e6, "--", color="k", lw=1.0, label="grain's centre")
    lx, ly, lz = (s * 1e6 for s in case.target.size)
    top.set_xlim(-0.5 * lx - 5, 0.5 * lx + 5)
    top.set_ylim(-0.5 * ly - 5, 0.5 * ly + 5)
    side.set_xlim(-0.5 * lx - 5, 0.5 * lx + 5)
    side.set_ylim(-lz - 5, max(float(path_xz[:, 2].max()) * 1e6, 20.0) + 5)
    for axes in (top, side):
        axes.set_aspect("equal")
        axes.set_xlabel("x, um")
        axes.legend(loc="lower right" if axes is top else "upper right", fontsize=7)
    top.set_ylabel("y, um")
    side.set_ylabel("z, um")
    g = case.grain
    failure = "with failure" if g and case.material.fails and case.material.solid.failure else "without failure"
    top.set_title(f"{case.case.name}: {g.speed:g} m/s at {g.angle:g} deg from the surface, {failure}; "
                  f"surface at the end from above", fontsize=9)
    kerf = (f"kerf {measured.get('kerf_length', np.nan) * 1e6:.0f} x {measured.get('kerf_width', np.nan) * 1e6:.0f}"
            f" um, {measured.get('kerf_depth', np.nan) * 1e6:.1f} um deep")
    side.set_title(f"section |y| < 0.75 dx at the end; {kerf}", fontsize=9)
    return save_figure(fig, path, layout=False)
