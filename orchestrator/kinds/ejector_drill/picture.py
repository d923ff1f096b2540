"""A picture of the ejector drill's geometry: the parts cut in half along the axis (pyvista, off-screen)."""

from __future__ import annotations

from pathlib import Path

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
