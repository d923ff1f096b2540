"""Picture helpers every kind uses: saving a matplotlib figure, pyvista off-screen set-up (font, quiet VTK),
meshes from run.h5 groups."""

from __future__ import annotations

import io
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


# ---------------------------------------------------------------- point labels and log ticks

#: Where a point's label may sit: directions from the point (right/left, up/down) and distances in points,
#: nearest first; the text is aligned so that it extends away from the point.
LABEL_DIRECTIONS = ((1, 1), (1, -1), (-1, 1), (-1, -1), (1, 0), (-1, 0), (0, 1), (0, -1))
LABEL_DISTANCES_PT = (4.0, 12.0, 24.0, 40.0)
#: Free space kept between two labels, and between a label and another point's marker, in pixels.
LABEL_GAP_PX = 2.0


def place_point_labels(ax, xs, ys, labels, short_labels=None, yerr=None, fontsize: float = 7.0,
                       max_labels: int = 40) -> list:
    """Label points (xs, ys in data units) with texts that stay inside the axes and overlap neither one another
    nor another point's marker or error bar (yerr: half-lengths in data units); returns the placed Annotation
    artists.

    Each label tries the offsets of LABEL_DIRECTIONS x LABEL_DISTANCES_PT (fontsize in points), nearest first; one
    not beside its point gets a thin leader line, which crosses no other label. When none fits, the point's short
    label (e.g. its run number) is tried, and when that does not fit either the point stays unlabelled. Only the
    first max_labels points are labelled. The figure is laid out before the texts are measured, and the labels
    are kept out of its layout, so a constrained layout does not move the axes afterwards: save the figure at its
    own dpi.
    """
    import matplotlib

    fig = ax.figure
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    radius = (0.5 * float(matplotlib.rcParams["lines.markersize"]) + 1.0) * fig.dpi / 72.0  # a marker, px
    xy = np.column_stack([np.asarray(xs, dtype=float), np.asarray(ys, dtype=float)]).reshape(-1, 2)
    centres = ax.transData.transform(xy)
    # obstacles as rows (x0, y0, x1, y1) in pixels: each marker, stretched over its error bar
    half = np.zeros(len(xy)) if yerr is None else np.nan_to_num(np.abs(np.asarray(yerr, dtype=float)))
    shift = np.column_stack([np.zeros(len(xy)), half])
    with np.errstate(invalid="ignore", divide="ignore"):  # a bar reaching below 0 on a log axis
        low, high = ax.transData.transform(xy - shift)[:, 1], ax.transData.transform(xy + shift)[:, 1]
    low = np.where(np.isfinite(low), low, frame.y0)
    high = np.where(np.isfinite(high), high, frame.y1)
    markers = np.column_stack([centres[:, 0] - radius, np.fmin(centres[:, 1] - radius, low),
                               centres[:, 0] + radius, np.fmax(centres[:, 1] + radius, high)])
    markers[~np.all(np.isfinite(markers), axis=1)] = np.nan  # compares False: no obstacle
    # a point's own error bar beyond its marker, as wide as a cap of 3 points: its label sits beside the bar
    cap = 3.0 * fig.dpi / 72.0
    bars = np.stack([np.column_stack([centres[:, 0] - cap, centres[:, 1] + radius, centres[:, 0] + cap, high]),
                     np.column_stack([centres[:, 0] - cap, low, centres[:, 0] + cap, centres[:, 1] - radius])], 1)
    placed, boxes, leaders = [], np.empty((0, 4)), np.empty((0, 2))
    for i in range(min(len(centres), max_labels)):
        if not np.all(np.isfinite(centres[i])) or not frame.contains(*centres[i]):
            continue
        own_bar = bars[i][bars[i, :, 3] > bars[i, :, 1]] if yerr is not None else np.empty((0, 4))
        taken = np.vstack([boxes, markers[:i], markers[i + 1:], own_bar])
        for text in (labels[i], short_labels[i] if short_labels is not None else ""):
            found = _fit_label(ax, renderer, xy[i], centres[i], text, fontsize, frame, taken, leaders) if text else None
            if found is not None:
                note, box, path = found
                placed.append(note)
                boxes = np.vstack([boxes, [box.x0 - LABEL_GAP_PX, box.y0 - LABEL_GAP_PX, box.x1 + LABEL_GAP_PX,
                                           box.y1 + LABEL_GAP_PX]])
                leaders = np.vstack([leaders, path])
                break
    return placed


def _fit_label(ax, renderer, xy, centre, text: str, fontsize: float, frame, taken, leaders):
    """The first candidate position of a label whose box lies inside frame, clear of the taken boxes (rows x0,
    y0, x1, y1) and of the leader lines drawn so far (leaders: points along them), and whose own leader crosses
    no taken box (all in pixels): (annotation, box, points along its leader), or None (nothing is left on the
    axes then)."""
    from matplotlib.text import Text

    for distance in LABEL_DISTANCES_PT:
        for dx, dy in LABEL_DIRECTIONS:
            scale = distance / float(np.hypot(dx, dy))
            leader = dict(arrowstyle="-", color="0.55", lw=0.5, shrinkA=0, shrinkB=3) if distance > 5 else None
            note = ax.annotate(text, tuple(xy), xytext=(dx * scale, dy * scale), textcoords="offset points",
                               fontsize=fontsize, ha={1: "left", -1: "right", 0: "center"}[dx],
                               va={1: "bottom", -1: "top", 0: "center"}[dy], arrowprops=leader,
                               annotation_clip=False)
            note.set_in_layout(False)
            note.update_positions(renderer)
            box = Text.get_window_extent(note, renderer)
            path = _leader_points(centre, box) if leader else np.empty((0, 2))
            inside = frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
            own = np.array([[box.x0, box.y0, box.x1, box.y1]])
            gap = np.array([[-LABEL_GAP_PX, -LABEL_GAP_PX, LABEL_GAP_PX, LABEL_GAP_PX]])
            if inside and not _overlap(own, taken) and not _inside(leaders, own + gap) and not _inside(path, taken):
                return note, box, path
            note.remove()
    return None


def _leader_points(centre, box, samples: int = 16) -> np.ndarray:
    """Points (pixels) along the straight line from a point's centre to its label's box, outside the box and
    clear of the point's own marker."""
    end = np.array([0.5 * (box.x0 + box.x1), 0.5 * (box.y0 + box.y1)])
    points = centre + np.linspace(0.0, 1.0, samples)[:, None] * (end - centre)
    keep = [not box.contains(*p) and np.hypot(*(p - centre)) > 6.0 for p in points]
    return points[keep]


def _overlap(box: np.ndarray, boxes: np.ndarray) -> bool:
    """True when box (one row x0, y0, x1, y1) overlaps one of boxes (rows), pixels."""
    return bool(np.any((boxes[:, 0] <= box[0, 2]) & (box[0, 0] <= boxes[:, 2])
                       & (boxes[:, 1] <= box[0, 3]) & (box[0, 1] <= boxes[:, 3])))


def _inside(points: np.ndarray, boxes: np.ndarray) -> bool:
    """True when one of the points (rows x, y) lies inside one of boxes (rows x0, y0, x1, y1), pixels."""
    if not len(points) or not len(boxes):
        return False
    x, y = points[:, 0:1], points[:, 1:2]
    return bool(np.any((boxes[:, 0] <= x) & (x <= boxes[:, 2]) & (boxes[:, 1] <= y) & (y <= boxes[:, 3])))


def plain_log_ticks(axis) -> None:
    """Tick labels of a log axis as plain numbers (8, 20, 0.05) instead of 8 x 10^0; minor ticks are labelled
    only when the axis spans about a decade or less, as matplotlib's own log labels are."""
    from matplotlib.ticker import LogFormatter

    class PlainLogFormatter(LogFormatter):
        def __call__(self, x, pos=None):
            return f"{x:g}" if super().__call__(x, pos) else ""

    axis.set_major_formatter(PlainLogFormatter(labelOnlyBase=False, minor_thresholds=(1, 0.4)))
    axis.set_minor_formatter(PlainLogFormatter(labelOnlyBase=False, minor_thresholds=(1, 0.4)))


# ---------------------------------------------------------------- pages

def figure_png(fig) -> bytes:
    """A matplotlib figure as PNG bytes at its own dpi (for pages that embed their pictures)."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi="figure")
    return buffer.getvalue()


def number_or_nan(value) -> float:
    """float(value), or NaN for a value that is not a number (an empty CSV cell, None)."""
    try:
        return float(value)
    except (TypeError, ValueError):
        return float("nan")


def parameter_label(row: dict, keys: list[str] | None = None, short: bool = True) -> str:
    """'name = value, ...' of a study row's parameters (its 'param:' columns, or only keys when given), each name
    shortened to its last part when short and that stays unique (numerics.stiffness_scale -> stiffness_scale)."""
    keys = keys if keys is not None else [k for k in row if k.startswith("param:")]
    names = [k.removeprefix("param:") for k in keys]
    last = [n.rsplit(".", 1)[-1] for n in names]
    names = last if short and len(set(last)) == len(last) else names
    return ", ".join(f"{name} = {row.get(k)}" for name, k in zip(names, keys))
