"""Sectional pictures of an ejector-drill run (pyvista, off-screen): the fluid particles within one spacing of the
plane y = 0 (through a hole's axis), coloured by speed (m/s) and by gauge pressure (bar), over the section of the
walls, in mm, at the case's picture times."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from orchestrator.kinds.ejector_drill.build import wall_meshes
from orchestrator.plots import quiet_headless_vtk


def draw_sections(frames: dict, case, layout, run_dir: Path, walls: dict | None = None) -> dict:
    """section_<t in ms>.png for each of case.output.picture_times that has a frame; returns {name: path}. walls:
    name -> trimesh drawn cut (default build.wall_meshes)."""
    keys = [k for k in frames if k != "attrs"]
    by_time = {round(float(frames[k]["attrs"]["time"]) * 1e9): k for k in keys}
    out = {}
    for t in case.output.picture_times:
        key = by_time.get(round(t * 1e9))
        if key is None:
            continue
        if walls is None:
            walls = wall_meshes(case, layout)
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
