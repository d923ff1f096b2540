"""The cantilever plate's pictures and `orchestrator analyze`: the tip's displacement against time beside thin-plate
theory's A sin(omega t), and the plate at its largest swing coloured by the bending stress sigma_xx."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from orchestrator.kinds.cantilever_plate.theory import plate_theory
from orchestrator.outputs import save_figure


def plot_plate(frames, tip, case, path: Path, title: str | None = None) -> Path:
    """Two panels (`tip`: the tip's (t s, y m) series, analysis.tip_series): the tip's displacement over t / T (T theory's period) with A sin(omega t), A = V c0 / omega; the
    plate at the frame of the largest tip displacement, every particle coloured by sigma_xx = s_xx - p (kPa)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    theory = plate_theory(case)
    fig = Figure(figsize=(7.5, 6.4), dpi=120, layout="constrained")
    FigureCanvasAgg(fig)
    top, bottom = fig.subplots(2, 1, height_ratios=(1.0, 1.1))
    if len(frames) >= 2:
        t, y = tip
        fine = np.linspace(0.0, t[-1], 2000)
        top.plot(fine / theory["period"], theory["amplitude"] * np.sin(theory["omega"] * fine) * 1e3, "k--", lw=0.8,
                 label="thin-plate theory, A sin(omega t)")
        top.plot(t / theory["period"], y * 1e3, "o-", ms=2.5, lw=1.0, color="C0", label="SPH, tip")
        _draw_plate(bottom, frames[int(np.argmax(np.abs(y)))], fig)
        top.set_ylim(-1.3e3 * np.max(np.abs(y)), 1.9e3 * np.max(np.abs(y)))  # the legend above the swing
    top.set_xlabel("t / T (T thin-plate theory's period)")
    top.set_ylabel("tip displacement, mm")
    top.legend(loc="upper right", fontsize=8, ncols=2)
    top.set_title(title or f"{case.case.name}: dx = {case.numerics.dx * 1e3:g} mm", fontsize=9)
    bottom.set_xlabel("x, mm")
    bottom.set_ylabel("y, mm")
    bottom.set_aspect("equal")
    return save_figure(fig, path, layout=False)


def _draw_plate(ax, item, fig) -> None:
    t, frame = item
    x = np.asarray(frame["positions"], dtype=float) * 1e3
    plate = np.asarray(frame["kind"]) == 0
    sigma = (np.asarray(frame["stress"])[:, 0, 0] - np.asarray(frame["pressures"])) * 1e-3
    bound = max(float(np.max(np.abs(sigma[plate]))), 1e-12)
    points = ax.scatter(x[plate, 0], x[plate, 1], c=sigma[plate], s=3.0, cmap="coolwarm", vmin=-bound, vmax=bound)
    ax.scatter(x[~plate, 0], x[~plate, 1], s=3.0, color="0.4", label="clamp (fixed particles)")
    fig.colorbar(points, ax=ax, label="sigma_xx, kPa", shrink=0.8)
    ax.set_title(f"t = {t:.3f} s, the largest tip displacement", fontsize=9)
    ax.legend(loc="upper left", fontsize=7)
