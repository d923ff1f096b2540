"""How the drill kinds draw (each kind's pictures.py says what): the series of flows and probe pressures and the SPH
beside the network as bars (matplotlib), sections through a run's frames coloured by speed and pressure, and the
geometry cut along its axis (pyvista, off-screen). Lengths in mm, flows in l/min, pressures in bar on the axes."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.plots import quiet_headless_vtk
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


def draw_sections(frames: dict, case, layout, run_dir: Path, walls) -> dict:
    """section_<t in ms>.png for each of case.output.picture_times that has a frame; returns {name: path}. walls:
    name -> trimesh drawn cut, or a callable that returns them (called only when a picture is drawn)."""
    keys = [k for k in frames if k != "attrs"]
    by_time = {round(float(frames[k]["attrs"]["time"]) * 1e9): k for k in keys}
    out = {}
    for t in case.output.picture_times:
        key = by_time.get(round(t * 1e9))
        if key is None:
            continue
        if callable(walls):
            walls = walls()
        name = f"section_{t * 1e3:.2f}ms"
        with quiet_headless_vtk():  # no 'bad X server connection' warning on a headless machine
            out[name] = draw_section(frames[key], t, walls, case.numerics.dx, Path(run_dir) / f"{name}.png",
                                     box=(layout.z_lo, layout.z_hi, layout.r_max))
    return out


def draw_section(frame: dict, t: float, walls: dict, dx: float, path: Path, size=(1500, 1100), box=None) -> Path:
    """One PNG: speed (top) and pressure (bottom) of the fluid particles with |y| < dx and x > 0 (the half plane
    through the hole at angle 0), walls cut at y = 0; the drill axis z runs to the right, the radius x upwards.
    box: (z_lo, z_hi, r_max) m, the scene's extent: particles that left it past an outlet are not drawn."""
    import pyvista as pv

    pv.OFF_SCREEN = True
    x = np.asarray(frame["positions"], dtype=float)
    fluid = (np.asarray(frame["kind"]) == 0) & (np.abs(x[:, 1]) < dx) & (x[:, 0] > 0.0)  # the half through a hole
    if box is not None:
        fluid &= (x[:, 2] >= box[0]) & (x[:, 2] <= box[1]) & (x[:, 0] <= box[2])
    points = pv.PolyData(x[fluid] * 1e3)
    points["speed [m/s]"] = np.linalg.norm(np.asarray(frame["velocities"], dtype=float)[fluid], axis=1)
    points["p [bar]"] = np.asarray(frame["pressures"], dtype=float)[fluid] / 1e5
    plotter = pv.Plotter(off_screen=True, shape=(2, 1), window_size=size)
    for column, field in enumerate(("speed [m/s]", "p [bar]")):
        plotter.subplot(column, 0)
        for mesh in walls.values():
            cut = pv.wrap(mesh).scale(1e3, inplace=False).slice(normal=(0, 1, 0), origin=(0, 0, 0)).clip(
                normal=(1, 0, 0), origin=(0, 0, 0), invert=False)
            if cut.n_points:
                plotter.add_mesh(cut, color="black", line_width=2)
        if points.n_points:
            clim = np.percentile(points[field], [2, 98])  # the particle pressures are noisy: the scale shows 96 %
            plotter.add_mesh(points, scalars=field, clim=clim if clim[1] > clim[0] else None, point_size=5,
                             render_points_as_spheres=True, cmap="viridis",
                             scalar_bar_args={"title": field, "vertical": True, "position_x": 0.88,
                                              "position_y": 0.1, "height": 0.8, "width": 0.06})
        plotter.add_text(f"t = {t * 1e3:.2f} ms: section y = 0 through a hole; z (axis) to the right, "
                         "radius up, mm; colours span 2-98 % of the particles", font_size=9)
        plotter.view_vector((0, 1, 0), viewup=(1, 0, 0))  # z (the drill axis) to the right, radius x upwards
        plotter.reset_camera()
        plotter.camera.zoom(1.3)  # the title above the walls, not over them
    plotter.screenshot(str(path))
    plotter.close()
    return Path(path)


#: The parts' colours in draw_geometry.
COLOURS = {"workpiece": "lightgrey", "head": "goldenrod", "outer_tube": "steelblue", "inner_tube": "seagreen",
           "adduction_holes": "crimson", "ejector_nozzles": "darkorange"}


def draw_geometry(meshes: dict, path: Path, z_max: float = 0.06, size=(1400, 900)) -> Path:
    """PNG of the parts (name -> trimesh, m) cut by the plane y = 0 and kept for z <= z_max (m; default the head
    and the first 35 mm of the tubes), in mm. Returns the path."""
    import pyvista as pv

    pv.OFF_SCREEN = True
    plotter = pv.Plotter(off_screen=True, window_size=size)
    for name, mesh in meshes.items():
        surface = pv.wrap(mesh).scale(1e3, inplace=False)  # mm on the axes
        cut = surface.clip(normal=(0, -1, 0), origin=(0, 0, 0)).clip(normal=(0, 0, 1), origin=(0, 0, z_max * 1e3))
        if cut.n_points == 0:
            continue
        plotter.add_mesh(cut, color=COLOURS.get(name, "white"), label=name, opacity=0.35 if name == "workpiece"
                         else 1.0, show_edges=False)
    plotter.add_legend(bcolor="white", size=(0.22, 0.22))
    plotter.show_axes()
    plotter.camera_position = [(-45, -110, -10), (0, 0, 22), (0, 0, 1)]
    plotter.screenshot(str(path))
    plotter.close()
    return Path(path)
