"""The channel's pictures (`orchestrator analyze`): Fig. 5's three panels of Nutto et al. (the set-up, the wear
contact, after it) as sections through the grain's centre, and the grain's path, speed, contact force and the
medium's flow rate over time."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from orchestrator.kinds.afm_channel.scene import GRAIN, SECTION, workpiece_mask
from orchestrator.outputs import save_figure

#: The section's half thickness about the grain's centre, in dx.
SLAB = 1.0
#: Records of the flow rate's running mean (the plane counts whole particles crossing: a noisy series).
RUNNING = 20
#: The particle kind of a grain's particles in the frames.
GRAIN_KIND = 4


def _figure(size):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=size, dpi=120, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _frames(run: dict) -> list[tuple[float, dict]]:
    frames = run.get("frames", {})
    keys = sorted((k for k in frames if k != "attrs"), key=int)
    return [(float(frames[k].get("attrs", {}).get("time", np.nan)), frames[k]) for k in keys]


def chosen_frames(run: dict) -> list[tuple[str, float, dict]]:
    """(title, time s, frame) of the three panels: the first frame, the frame nearest the largest contact force
    (the last before it when there was none), the last frame."""
    frames = _frames(run)
    if not frames:
        return []
    times = np.array([t for t, _ in frames])
    series = run.get("series", {})
    force = np.asarray(series.get(f"grain_{GRAIN}_contact", np.zeros((1, 3))), dtype=float)
    t = np.asarray(series.get("time", np.zeros(1)), dtype=float)
    size = np.linalg.norm(force, axis=1)
    middle = len(frames) // 2
    if size.max() > 0.0 and len(t) == len(size):
        middle = int(np.argmin(np.abs(times - t[int(np.argmax(size))])))
    picks = [("set-up", 0), ("wear contact" if size.max() > 0.0 else "half way", middle), ("end", len(frames) - 1)]
    return [(title, frames[i][0], frames[i][1]) for title, i in picks]


def plot_panels(run: dict, case, path: Path) -> Path:
    """Three sections |y - y_grain| < SLAB dx (um): the medium as red dots, the grain blue, the workpiece coloured
    by equivalent plastic strain with its failed particles red-edged, the walls and the support grey-green."""
    dx = case.numerics.dx
    aspect = case.height() / case.channel.length
    fig = _figure((7.4, 1.4 + 3 * 5.8 * aspect))
    axes = fig.subplots(3, 1, sharex=True)
    picks = chosen_frames(run)
    mine = workpiece_mask(case, picks[0][2]) if picks else None
    last_eps = np.asarray(picks[-1][2].get("plastic_strain", [0.0]), dtype=float) if picks else np.zeros(1)
    vmax = max(float(last_eps[mine].max()) if mine is not None and mine.any() else 0.0, 1e-3)
    points = None
    for ax, (title, time, frame) in zip(axes, picks):
        x = np.asarray(frame["positions"], dtype=float)
        kind = np.asarray(frame["kind"])
        grain = kind == GRAIN_KIND
        y0 = float(x[grain, 1].mean()) if grain.any() else 0.5 * case.channel.width
        slab = np.abs(x[:, 1] - y0) < SLAB * dx
        eps = np.asarray(frame.get("plastic_strain", np.zeros(len(x))), dtype=float)
        damage = np.asarray(frame.get("damage", np.zeros(len(x))), dtype=float)
        um = x * 1e6
        fluid = slab & (kind == 0) & ~mine
        walls = slab & (kind == 1)
        ax.scatter(um[fluid, 0], um[fluid, 2], s=2.0, color="#e8a0a0", label="medium")
        ax.scatter(um[walls, 0], um[walls, 2], s=4.0, color="#8fb3a0", label="walls, support")
        ax.scatter(um[slab & grain, 0], um[slab & grain, 2], s=10.0, color="C0", label="grain")
        work = slab & mine
        points = ax.scatter(um[work, 0], um[work, 2], s=12.0, c=eps[work], cmap="viridis", vmin=0.0, vmax=vmax)
        failed = work & (damage >= 1.0)
        if failed.any():
            ax.scatter(um[failed, 0], um[failed, 2], s=16.0, facecolors="none", edgecolors="C3",
                       label=f"failed ({int(failed.sum())} in the section)")
        ax.set_title(f"{title}: t = {time * 1e6:.1f} us", fontsize=9)
        ax.set_aspect("equal")
        ax.set_ylabel("z, um")
        ax.set_ylim(-0.5, case.height() * 1e6 + 0.5)
    if len(picks):
        axes[0].legend(loc="lower left", fontsize=7, ncols=4, bbox_to_anchor=(0.0, 1.08), frameon=False)
        axes[-1].set_xlabel("x, um")
        fig.colorbar(points, ax=list(axes), label="equivalent plastic strain", shrink=0.6)
    fig.suptitle(f"{case.case.name}: sections through the grain's centre (|y - y_grain| < {SLAB:g} dx)", fontsize=10)
    return save_figure(fig, path, layout=False)


def plot_series(run: dict, case, path: Path) -> Path:
    """The grain's path in the x-z plane over the workpiece's outline; its speed over time; the contact force;
    the medium's flow rate against the empty channel's."""
    series = run.get("series", {})
    measured = run.get("measured", {}).get("attrs", {})
    t = np.asarray(series.get("time", np.zeros(1)), dtype=float) * 1e6
    pos = np.asarray(series.get(f"grain_{GRAIN}_position", np.zeros((len(t), 3))), dtype=float) * 1e6
    vel = np.asarray(series.get(f"grain_{GRAIN}_velocity", np.zeros((len(t), 3))), dtype=float)
    force = np.asarray(series.get(f"grain_{GRAIN}_contact", np.zeros((len(t), 3))), dtype=float)
    rate = np.asarray(series.get(f"flow_rate_{SECTION}", np.zeros(len(t))), dtype=float)
    fig = _figure((9.0, 6.4))
    (path_ax, speed_ax), (force_ax, flow_ax) = fig.subplots(2, 2)
    w, wall = case.workpiece, case.channel.wall_layers * case.numerics.dx
    outline = np.array([[w.front, wall], [w.front, wall + w.height], [w.front + w.length, wall + w.height],
                        [w.front + w.length, wall]]) * 1e6
    path_ax.plot(outline[:, 0], outline[:, 1], color="C2", label="workpiece")
    path_ax.plot(pos[:, 0], pos[:, 2], color="C0", label="grain's centre")
    path_ax.set(xlabel="x, um", ylabel="z, um", title="the grain's path")
    path_ax.legend(fontsize=7, loc="lower left")
    speed_ax.plot(t, np.linalg.norm(vel, axis=1), color="C0")
    speed_ax.set(xlabel="t, us", ylabel="speed, m/s", title="the grain's speed")
    force_ax.plot(t, np.linalg.norm(force, axis=1) * 1e3, color="C3")
    force_ax.set(xlabel="t, us", ylabel="|F|, mN", title="contact force on the grain")
    flow_ax.plot(t[1:], rate[1:] * 1e9, color="C1", lw=0.6, alpha=0.5, label="measured")
    if len(rate) > RUNNING:
        mean = np.convolve(rate[1:], np.ones(RUNNING) / RUNNING, mode="valid")
        flow_ax.plot(t[RUNNING // 2 + 1:][:len(mean)], mean * 1e9, color="C1", label=f"its mean over {RUNNING} records")
    for key, style, label in (("flow_rate_empty", "--", "empty channel (Poiseuille)"),
                              ("flow_rate_lubrication", ":", "lubrication theory")):
        if measured.get(key):
            flow_ax.axhline(measured[key] * 1e9, color="k", ls=style, lw=1.0, label=label)
    flow_ax.set(xlabel="t, us", ylabel="Q, mm^3/s", title="the medium's flow rate")
    flow_ax.legend(fontsize=7, loc="upper right")
    fig.suptitle(f"{case.case.name}", fontsize=10)
    return save_figure(fig, path, layout=False)
