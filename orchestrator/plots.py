"""Picture helpers every kind uses: saving a matplotlib figure, pyvista off-screen set-up (font, quiet VTK),
meshes from run.h5 groups."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from orchestrator.humanize import os_problem
from orchestrator.outputs import WriteError, save_figure


def save_pyplot_figure(fig, path, dpi: int = 110, option: str = "picture", inputs=()) -> Path:
    """Lay out a pyplot figure, write it as a PNG at path (dpi in dots per inch; parent folders made) through the
    output policy (outputs.save_figure: a .png name, a regular file, never an input, a temporary name then a
    rename), close it (pyplot keeps open figures alive) and return the path."""
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise WriteError(f"{option} {path}: cannot create its folder: {os_problem(exc)}") from None
    return save_figure(fig, path, option, dpi, inputs)


# ---------------------------------------------------------------- force series

def font_file() -> str | None:
    """DejaVu Sans from matplotlib (VTK's built-in sans font draws [ ] like ( )); None if missing."""
    try:
        import matplotlib
    except ImportError:
        return None
    path = Path(matplotlib.get_data_path()) / "fonts" / "ttf" / "DejaVuSans.ttf"
    return str(path) if path.is_file() else None

class quiet_headless_vtk:
    """Without a display VTK first tries X, warns 'bad X server connection', then renders off-screen
    (EGL); the warning is noise for a headless run, so VTK's log is held to errors meanwhile."""

    def __enter__(self):

        self.logger = None
        if os.name == "posix" and not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY"):
            from vtkmodules.vtkCommonCore import vtkLogger

            self.logger = vtkLogger
            self.saved = vtkLogger.GetCurrentVerbosityCutoff()
            vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_ERROR)
        return self

    def __exit__(self, *exc):
        if self.logger is not None:
            self.logger.SetStderrVerbosity(self.saved)
        return False

def polydata(pv, group: dict):
    faces = np.asarray(group["faces"], dtype=np.int64).reshape(-1, 3)
    cells = np.column_stack([np.full(len(faces), 3), faces]).ravel()
    return pv.PolyData(np.asarray(group["vertices"], dtype=float).reshape(-1, 3), cells)
