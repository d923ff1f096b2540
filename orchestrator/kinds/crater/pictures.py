"""The crater's picture (`orchestrator analyze`): the target's mid-plane section coloured by plastic strain with
the sphere at its deepest, and the contact force against penetration."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from orchestrator.outputs import save_figure


def plot_crater(run: dict, case, path: Path) -> Path:
    """Left: the two lattice rows nearest the y = 0 plane (at the start) as they are at the end, coloured by plastic
    strain, with the sphere at its deepest (um). Right: contact force (N) against penetration (um)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle

    dx, r = case.numerics.dx, 0.5 * case.sphere.diameter
    fig = Figure(figsize=(10.0, 4.2), dpi=120, layout="constrained")
    FigureCanvasAgg(fig)
    left, right = fig.subplots(1, 2, width_ratios=[1.6, 1.0])
    frames = run.get("frames", {})
    keys = sorted((k for k in frames if k != "attrs"), key=int)
    series = run.get("series", {})
    position = np.asarray(series.get("impactor_sphere_position", np.zeros((1, 3))), dtype=float)
    deepest = float(position[:, 2].min()) if len(position) else r
    if keys:
        last = frames[keys[-1]]
        x = np.asarray(last["positions"], dtype=float)
        section = np.abs(np.asarray(frames[keys[0]]["positions"], dtype=float)[:, 1]) < dx
        colour = np.asarray(last.get("plastic_strain", np.zeros(len(x))), dtype=float)[section]
        points = left.scatter(x[section, 0] * 1e6, x[section, 2] * 1e6, c=colour, s=4.0, cmap="viridis", vmin=0.0)
        fig.colorbar(points, ax=left, label="equivalent plastic strain")
    left.add_patch(Circle((0.0, deepest * 1e6), r * 1e6, fill=False, ls="--", color="C3", label="sphere, deepest"))
    half = 0.5 * case.target.size[0] * 1e6
    left.set_xlim(-half, half)
    left.set_ylim(-case.target.size[2] * 1e6 - 3 * dx * 1e6, 0.6 * r * 1e6)
    left.set_aspect("equal")
    left.set_xlabel("x, um")
    left.set_ylabel("z, um")
    left.set_title(f"{case.case.name}: {case.sphere.speed:g} m/s, section |y| < dx at the end", fontsize=9)
    left.legend(loc="upper right", fontsize=7)
    force = np.asarray(series.get("impactor_sphere_force", np.zeros((1, 3))), dtype=float)[:, 2]
    right.plot((r - position[:, 2]) * 1e6, force, "-", lw=1.2)
    right.set_xlabel("penetration, um")
    right.set_ylabel("contact force, N")
    right.set_title("force against penetration", fontsize=9)
    return save_figure(fig, path, layout=False)


#: The sweep picture's diameters: check_run's picture key -> legend.
DIAMETERS = {"volume": "cap holding the crater's volume (checked)", "diameter": "rim crest",
             "contact": "contact chord at the deepest", "hutchings": "eq. 20 at the mean contact pressure"}


def plot_speed_sweep(runs, path: Path) -> Path:
    """A crater sweep (runs with check_run's picture: speed m/s, diameters m, hardness and pressure Pa). Left: the
    diameters against the impact speed on log axes with v^(1/2) through the checked one at the top speed (um).
    Right: Hutchings' dynamic hardness (kinetic energy over crater volume) and the mean contact pressure (GPa)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    runs = sorted(runs, key=lambda run: run.picture.get("speed", 0.0))
    v = np.array([run.picture.get("speed", np.nan) for run in runs], dtype=float)
    fig = Figure(figsize=(10.0, 4.2), dpi=120, layout="constrained")
    FigureCanvasAgg(fig)
    left, right = fig.subplots(1, 2)
    for (key, label), marker in zip(DIAMETERS.items(), "osD^"):
        d = np.array([run.picture.get(key, np.nan) for run in runs], dtype=float) * 1e6
        left.loglog(v, d, marker + "-", lw=1.0, ms=5, label=label)
    d = np.array([run.picture.get("volume", np.nan) for run in runs], dtype=float) * 1e6
    if len(v) and np.isfinite(d[-1]):
        guide = d[-1] * np.sqrt(v / v[-1])
        left.loglog(v, guide, "k:", lw=1.0, label="v^(1/2) through the checked one")
    from matplotlib.ticker import FormatStrFormatter

    left.set_xticks(v, [f"{s:g}" for s in v])
    left.xaxis.set_minor_formatter(FormatStrFormatter(""))
    for formatter in (left.yaxis.set_major_formatter, left.yaxis.set_minor_formatter):
        formatter(FormatStrFormatter("%g"))
    left.set_xlabel("impact speed, m/s")
    left.set_ylabel("crater diameter, um")
    left.legend(fontsize=7, loc="upper left")
    left.set_title("diameters against speed", fontsize=9)
    for key, label, marker in (("hardness", "dynamic hardness: kinetic energy / crater volume", "o"),
                               ("pressure", "mean contact pressure while the sphere goes in", "s")):
        right.plot(v, np.array([run.picture.get(key, np.nan) for run in runs], dtype=float) / 1e9, marker + "-",
                   label=label)
    right.set_xlabel("impact speed, m/s")
    right.set_ylabel("GPa")
    right.set_ylim(bottom=0.0)
    right.legend(fontsize=7, loc="lower right")
    right.set_title("hardness against speed", fontsize=9)
    return save_figure(fig, path, layout=False)
