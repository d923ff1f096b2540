"""PNG figures of a run: the drag-finishing force series with the paper's
bands (matplotlib, Agg backend) and the 3D interaction network (pyvista,
off-screen). Both read the nested dicts of ``runh5.read_run``; the heavy
libraries are imported inside the functions.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.errors import ReadError
from orchestrator.kinds.drag_finishing.forces import force_statistics, process_series
from orchestrator.plots import font_file, polydata, quiet_headless_vtk
from orchestrator.runh5 import normal_force_of
from orchestrator.outputs import save_figure

#: Mean ball radius of the paper's media (Uhlmann et al. 2015), m; used when a run has no frames.
DEFAULT_BALL_RADIUS = 3.27e-3
#: Thinnest drawn contact, as a fraction of the thickest (keeps near-zero forces visible as hairlines).
MIN_TUBE_FRACTION = 0.04


def plot_drag_finishing_forces(run: dict, case, path) -> Path:
    """Plot F_n and F_t on the rod (N) against process time (s) and write a PNG at path; returns path.

    run: ``read_run`` output; case: the validated DragFinishingCase (or a
    LoadedCase). Top panel F_n (along the rod's velocity) with the case's
    reference bands (mean +- std, N) shaded; bottom panel F_t (horizontal,
    radial). Both panels: the start-up transient (``analysis.transient_time``,
    s) shaded grey and this run's mean after the transient as a dashed line.
    Only the process phase (phase 3) is drawn; t = 0 is the start of dragging.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    model = getattr(case, "model", case)
    path = Path(path)
    attrs = run.get("attrs", {})
    t, f = _process_forces(run)
    transient = float(model.analysis.transient_time)
    stats = force_statistics(t, f, transient) if t.size else {}

    fig = Figure(figsize=(9.0, 7.0), dpi=150, layout="constrained")
    FigureCanvasAgg(fig)  # the Agg backend, without touching pyplot's global state
    ax_n, ax_t = fig.subplots(2, 1, sharex=True)
    engine = f"{attrs.get('engine', '?')} {attrs.get('engine_version', '')}".strip()
    status = attrs.get("status", "ok")
    fig.suptitle(f"Force on the rod: case {model.case.name}, engine {engine}"
                 + ("" if status == "ok" else f" (status {status})"), fontsize=12)

    t_end = max(float(t.max()) if t.size else 0.0, transient * 1.05, 1e-9)
    for ax in (ax_n, ax_t):
        ax.axvspan(0.0, transient, color="0.85", lw=0, zorder=0)
        ax.axhline(0.0, color="0.6", lw=0.6, zorder=1)
        ax.grid(True, color="0.92", lw=0.6)
        ax.set_xlim(0.0, t_end)
    columns: list[list] = [[], []]  # legend entries (handle, label): F_n side, F_t side

    panels = ((ax_n, 0, "fn", "F_n", "along the rod velocity", "C0"),
              (ax_t, 1, "ft", "F_t", "horizontal, radial", "C1"))
    for ax, column, key, symbol, meaning, color in panels:
        ax.set_ylabel(f"${symbol}$ {meaning} [N]")
        if not t.size:
            ax.text(0.5, 0.5, "no process-phase samples in this run", transform=ax.transAxes,
                    ha="center", va="center", color="0.3")
            continue
        (line,) = ax.plot(t, f[:, column], color=color, lw=1.0, zorder=3)
        columns[column].append((line, f"${symbol}$ of this run"))
        mean, std = stats.get(f"{key}_mean", math.nan), stats.get(f"{key}_std", math.nan)
        if np.isfinite(mean):
            dashed = ax.hlines(mean, transient, t_end, colors="k", linestyles="--", lw=1.3, zorder=4)
            columns[column].append((dashed, f"${symbol}$ mean after the transient: {_num(mean)} N"
                                    + (f" (std {_num(std, '.2g')} N)" if np.isfinite(std) else "")))
    ax_t.set_xlabel(r"process time $t - t_0$ [s]  ($t_0$: the rod starts moving)")

    if t.size:
        columns[0] += _reference_bands(ax_n, model.reference, f[:, 0])
    columns[1].append((Patch(color="0.85"), f"start-up transient ({transient:g} s), discarded"))
    blank = (Patch(alpha=0.0), "")
    rows = max(len(c) for c in columns)
    entries = [e for c in columns for e in c + [blank] * (rows - len(c))]
    fig.legend([h for h, _ in entries], [lab for _, lab in entries], loc="outside lower center", ncols=2,
               fontsize=8, frameon=False)
    path.parent.mkdir(parents=True, exist_ok=True)
    save_figure(fig, path, dpi=fig.dpi, layout=False)  # the output policy: temporary name, rename
    return path


def _process_forces(run: dict) -> tuple[np.ndarray, np.ndarray]:
    """(process time s, workpiece force N (n, 3)) of a run's process phase; ReadError without a force series."""

    attrs = run.get("attrs", {})
    series = run.get("series", {})
    if "workpiece_force" not in series or "time" not in series:
        raise ReadError("run.h5 holds no /series/workpiece_force; the run ended before recording forces")
    time = np.asarray(series["time"], dtype=float)
    force = np.asarray(series["workpiece_force"], dtype=float).reshape(len(time), -1)
    phase = np.asarray(series.get("phase", np.full(len(time), 3)))
    start = _finite(attrs.get("process_start_time"))
    if start is None:
        in_process = time[phase == 3]
        start = float(in_process[0]) if in_process.size else 0.0
    return process_series(time, phase, force, start)


def plot_engine_forces(runs: list[tuple[str, dict]], case, path) -> Path:
    """Overlay several engines' F_n and F_t on the rod (N) against process time (s) in one PNG; returns path.

    runs: (label, ``read_run`` output) per engine, e.g. ("yade 2023.02a", run);
    a run without a force series is named in the legend and not drawn. As in
    plot_drag_finishing_forces: the transient shaded grey, each engine's mean
    after it dashed in the engine's colour, the case's reference bands on F_n.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    model = getattr(case, "model", case)
    path = Path(path)
    transient = float(model.analysis.transient_time)
    fig = Figure(figsize=(9.0, 7.0), dpi=150, layout="constrained")
    FigureCanvasAgg(fig)
    ax_n, ax_t = fig.subplots(2, 1, sharex=True)
    fig.suptitle(f"Force on the rod: case {model.case.name}, engines compared", fontsize=12)
    entries, fn_all, t_end = [], [], transient * 1.05
    for k, (label, run) in enumerate(runs):
        color = ("C0", "C1", "C9", "C6", "k")[k % 5]  # not the colours _reference_bands uses
        try:
            t, f = _process_forces(run)
        except ReadError:
            t, f = np.empty(0), np.empty((0, 3))
        if not t.size:
            entries.append((Patch(alpha=0.0), f"{label}: no process-phase force series"))
            continue
        t_end = max(t_end, float(t.max()))
        fn_all.append(f[:, 0])
        stats = force_statistics(t, f, transient)
        for ax, column, key in ((ax_n, 0, "fn"), (ax_t, 1, "ft")):
            ax.plot(t, f[:, column], color=color, lw=0.9, alpha=0.85, zorder=3)
            if np.isfinite(stats[f"{key}_mean"]):
                ax.hlines(stats[f"{key}_mean"], transient, float(t.max()), colors=color, linestyles="--", lw=1.4,
                          zorder=4)
        (handle,) = ax_n.plot([], [], color=color, lw=1.2)
        entries.append((handle, f"{label}: $F_n$ {_num(stats['fn_mean'])} ± {_num(stats['fn_std'], '.2g')} N, "
                                f"$F_t$ {_num(stats['ft_mean'])} ± {_num(stats['ft_std'], '.2g')} N (dashed: means)"))
    for ax, symbol, meaning in ((ax_n, "F_n", "along the rod velocity"), (ax_t, "F_t", "horizontal, radial")):
        ax.axvspan(0.0, transient, color="0.85", lw=0, zorder=0)
        ax.axhline(0.0, color="0.6", lw=0.6, zorder=1)
        ax.grid(True, color="0.92", lw=0.6)
        ax.set_xlim(0.0, t_end)
        ax.set_ylabel(f"${symbol}$ {meaning} [N]")
    ax_t.set_xlabel(r"process time $t - t_0$ [s]  ($t_0$: the rod starts moving)")
    if fn_all:
        entries += _reference_bands(ax_n, model.reference, np.concatenate(fn_all))
    entries.append((Patch(color="0.85"), f"start-up transient ({transient:g} s), discarded"))
    fig.legend([h for h, _ in entries], [lab for _, lab in entries], loc="outside lower center", ncols=1,
               fontsize=8, frameon=False)
    path.parent.mkdir(parents=True, exist_ok=True)
    save_figure(fig, path, dpi=fig.dpi, layout=False)  # the output policy: temporary name, rename
    return path


def _reference_bands(ax, references, fn: np.ndarray) -> list:
    """Shade each reference mean +- std (N) on the F_n axis; returns legend entries (handle, label).

    When the bands lie far from this run's values (they would squash its
    series to a flat line), the axis keeps to the run's range and each band
    off the axis is named at the edge it lies beyond, with its numbers.
    """
    from matplotlib.patches import Patch

    colors = ("tab:red", "tab:green", "tab:purple", "tab:brown", "tab:olive")
    values = fn[np.isfinite(fn)]
    lo, hi = (float(values.min()), float(values.max())) if values.size else (0.0, 0.0)
    lo, hi = min(lo, 0.0), max(hi, 0.0)
    span = hi - lo
    band_lo = min([r.fn_mean - r.fn_std for r in references] + [lo])
    band_hi = max([r.fn_mean + r.fn_std for r in references] + [hi])
    squash = span > 0 and (band_hi - band_lo) > 6.0 * span
    if squash:
        pad = 0.08 * span
        ax.set_ylim(lo - pad, hi + pad)
    entries = []
    below = above = 0
    for i, ref in enumerate(references):
        color = colors[i % len(colors)]
        label = f"{ref.label}: {_num(ref.fn_mean)} ± {_num(ref.fn_std, '.2g')} N"
        ax.axhspan(ref.fn_mean - ref.fn_std, ref.fn_mean + ref.fn_std, color=color, alpha=0.18, lw=0, zorder=1)
        line = ax.axhline(ref.fn_mean, color=color, lw=1.2, zorder=2)
        entries.append(((Patch(color=color, alpha=0.18, lw=0), line), f"$F_n$ {label} (mean ± std)"))
        if squash and (ref.fn_mean + ref.fn_std < lo or ref.fn_mean - ref.fn_std > hi):
            low_side = ref.fn_mean < lo
            slot = below if low_side else above
            y = 0.03 + 0.06 * slot if low_side else 0.97 - 0.06 * slot
            ax.text(0.01, y, f"{'▼' if low_side else '▲'} {label} (off scale, {'below' if low_side else 'above'})",
                    transform=ax.transAxes, ha="left", va="bottom" if low_side else "top", fontsize=8, color=color,
                    bbox={"facecolor": "white", "edgecolor": color, "alpha": 0.85, "boxstyle": "round,pad=0.25"})
            below, above = below + low_side, above + (not low_side)
    return entries


def _num(value: float, fmt: str = ".3g") -> str:
    """A number as the axes print it (typographic minus sign)."""
    return format(value, fmt).replace("-", "\u2212")


def _finite(value) -> float | None:
    try:
        value = float(value)
    except (TypeError, ValueError):
        return None
    return value if math.isfinite(value) else None


# ---------------------------------------------------------------- network rendering


def render_network(run: dict, path, k: int = 0) -> Path:
    """Render contact snapshot k as a force network (Uhlmann et al. 2015, Fig. 4b) into a PNG; returns path.

    One tube per interaction with normal force > 0 (compression), from
    point1 (ball centre) to point2 (the other ball's centre, or the contact
    point on a facet), m. Tube radius is proportional to the normal force:
    the largest force gets the mean ball radius (of the frame nearest in time,
    else 3.27e-3 m); the thinnest are kept at 4 % of that. Colour: normal
    force, N, green (low) to red (high). The bowl is a translucent wireframe;
    the rod is drawn at its pose at the snapshot time (see _rod_at). View from
    above at an angle, 1200 x 900 pixels, off-screen (no display needed).
    """
    import pyvista as pv

    path = Path(path)
    contacts = run.get("contacts", {})
    key = str(k)
    if key not in contacts:
        have = sorted(int(c) for c in contacts if c != "attrs")
        raise ReadError(f"run.h5 has no contact snapshot {k}; it has {have if have else 'none'}")
    snap = contacts[key]
    snap_time = _finite(snap["attrs"].get("time"))
    process_time = _finite(snap["attrs"].get("process_time"))
    fn, _ = normal_force_of(snap)
    p1 = np.asarray(snap["point1"], dtype=float).reshape(-1, 3)
    p2 = np.asarray(snap["point2"], dtype=float).reshape(-1, 3)
    keep = np.isfinite(fn) & (fn > 0) & (np.linalg.norm(p2 - p1, axis=1) > 0)
    fn, p1, p2 = fn[keep], p1[keep], p2[keep]
    r_ball = _mean_ball_radius(run, snap_time)

    font = font_file()
    with quiet_headless_vtk():
        plotter = pv.Plotter(off_screen=True, window_size=(1200, 900))
        try:
            _draw_network(pv, plotter, run, fn, p1, p2, r_ball, snap_time, process_time, font)
            path.parent.mkdir(parents=True, exist_ok=True)
            plotter.screenshot(str(path))
        finally:
            plotter.close()
    return path


def _draw_network(pv, plotter, run, fn, p1, p2, r_ball, snap_time, process_time, font) -> None:
    """Add the meshes, the tubes, the scalar bar, the caption and the camera to plotter."""
    plotter.set_background("white")
    meshes = {name: polydata(pv, g) for name, g in run.get("meshes", {}).items() if name != "attrs"}
    if "bowl" in meshes:
        plotter.add_mesh(meshes["bowl"], style="wireframe", color="gray", opacity=0.35, line_width=1.0)
    if "rod" in meshes:
        rod = _rod_at(run, meshes["rod"], snap_time)
        plotter.add_mesh(rod, color="silver", ambient=0.35, diffuse=0.7, specular=0.3)

    title = "interaction network"
    if process_time is not None:
        title += f" at process time {process_time:.3g} s"
    if fn.size:
        n = len(fn)
        fmax = float(fn.max())
        radius = np.maximum(fn / fmax, MIN_TUBE_FRACTION) * r_ball
        lines = pv.PolyData(np.vstack([p1, p2]))
        lines.lines = np.column_stack([np.full(n, 2), np.arange(n), np.arange(n, 2 * n)]).ravel()
        lines.point_data["tube_radius"] = np.concatenate([radius, radius])
        lines.point_data["normal force [N]"] = np.concatenate([fn, fn])
        tubes = lines.tube(scalars="tube_radius", absolute=True, n_sides=18, capping=True)
        plotter.add_mesh(
            tubes, scalars="normal force [N]", cmap="RdYlGn_r", clim=(0.0, fmax), smooth_shading=True,
            scalar_bar_args={"title": "normal force [N]", "color": "black", "vertical": True,
                             "position_x": 0.86, "position_y": 0.2, "height": 0.6, "width": 0.06,
                             "title_font_size": 18, "label_font_size": 15, "fmt": "%.3g"},
        )
        if font:
            bar = plotter.scalar_bars["normal force [N]"]
            for prop in (bar.GetTitleTextProperty(), bar.GetLabelTextProperty()):
                prop.SetFontFamily(4)  # VTK_FONT_FILE
                prop.SetFontFile(font)
        title += f": {n} compressive contacts, max {fmax:.3g} N"
    else:
        title += ": no compressive contacts"

    plotter.add_text(title, position="upper_left", font_size=12, color="black", font_file=font)
    _camera_from_above(plotter, run, p1, p2, r_ball)


def _mean_ball_radius(run: dict, when: float | None) -> float:
    """Mean radius (m) of the frame nearest in time to `when` (s); DEFAULT_BALL_RADIUS without frames."""
    frames = [g for key, g in run.get("frames", {}).items() if key != "attrs" and "radii" in g]
    if not frames:
        return DEFAULT_BALL_RADIUS
    if when is not None:
        frames.sort(key=lambda g: abs(float(g["attrs"].get("time", math.inf)) - when))
    radii = np.asarray(frames[0]["radii"], dtype=float)
    radii = radii[np.isfinite(radii) & (radii > 0)]
    return float(radii.mean()) if radii.size else DEFAULT_BALL_RADIUS


def _rod_at(run: dict, rod, when: float | None):
    """The rod mesh at time `when` (s).

    run.h5 keeps the rod's vertices at the end of the run (the last frame).
    During the process phase the rod turns rigidly about the bowl axis (z
    through the origin) at omega = workpiece.speed / workpiece.path_radius,
    so the pose at an earlier snapshot is the final one turned back by
    omega * (t_end - t). When that cannot be worked out (no final pose, no
    case parameters), the rod is drawn where run.h5 has it.
    """
    meshes = run.get("meshes", {})
    moved = "contact_intensity" in meshes.get("rod", {})  # only the final pose comes with the intensities
    params = run.get("case", {}).get("attrs", {})
    speed = _finite(params.get("workpiece.speed"))
    radius = _finite(params.get("workpiece.path_radius"))
    t_end = _finite(run.get("attrs", {}).get("simulated_time"))
    if t_end is None:
        times = [_finite(g["attrs"].get("time")) for key, g in run.get("frames", {}).items() if key != "attrs"]
        times = [x for x in times if x is not None]
        t_end = max(times) if times else None
    if not moved or when is None or speed is None or not radius or t_end is None:
        return rod
    angle = -speed / radius * (t_end - when)
    c, s = math.cos(angle), math.sin(angle)
    turned = rod.copy()
    xyz = np.asarray(rod.points)
    turned.points = np.column_stack([c * xyz[:, 0] - s * xyz[:, 1], s * xyz[:, 0] + c * xyz[:, 1], xyz[:, 2]])
    return turned


def _camera_from_above(plotter, run: dict, p1: np.ndarray, p2: np.ndarray, r_ball: float) -> None:
    """Look down on the bed from about 55 degrees above the horizon, framing the bowl's floor and the network."""
    bowl = run.get("meshes", {}).get("bowl")
    pts = [p for p in (p1, p2) if p.size]
    if bowl is not None:
        v = np.asarray(bowl["vertices"], dtype=float).reshape(-1, 3)
        top = max([float(np.max(p[:, 2])) + r_ball for p in pts], default=float(v[:, 2].max()))
        lo = np.array([v[:, 0].min(), v[:, 1].min(), v[:, 2].min()])
        hi = np.array([v[:, 0].max(), v[:, 1].max(), min(float(v[:, 2].max()), top)])
    elif pts:
        allp = np.vstack(pts)
        lo, hi = allp.min(axis=0) - r_ball, allp.max(axis=0) + r_ball
    else:
        plotter.reset_camera()
        return
    centre = 0.5 * (lo + hi)
    elevation, azimuth = math.radians(55.0), math.radians(-60.0)
    direction = np.array([math.cos(elevation) * math.cos(azimuth), math.cos(elevation) * math.sin(azimuth),
                          math.sin(elevation)])
    size = float(np.linalg.norm(hi - lo))
    plotter.camera.focal_point = tuple(centre)
    plotter.camera.position = tuple(centre + 3.0 * size * direction)
    plotter.camera.up = (0.0, 0.0, 1.0)
    plotter.reset_camera(bounds=(lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]))
    plotter.camera.zoom(1.15)
