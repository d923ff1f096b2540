"""The pictures of an ejector-drill run (drill/drawing.py draws them): its flows and probe pressures against time
(series.png, with the pressure beside the jets as dots), the SPH beside the network and the paper (comparison.png)
and, with render, sections through the frames at the case's picture times with the walls cut (section_<t>ms.png);
with guide pads or cutting edges, the flow around them at the picture times (head_sections_<t>ms.png)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from orchestrator.drill.drawing import draw_sections, plot_comparison, plot_drill_series
from orchestrator.kinds.ejector_drill.build import wall_meshes
from orchestrator.kinds.ejector_drill.head import edge_mouths, edge_solids, pad_solids


def draw_run_pictures(run_dir: Path, case, layout, time, flows: dict, series: dict, stored, beside, rows: list,
                      frames: dict, render: bool) -> dict:
    """series.png, comparison.png and (render) the sections in run_dir; {name: path}. time s, flows m^3/s, series:
    the run's, stored: the control volume's storage rate (m^3/s, or None), beside: (frame times s, pressures Pa)
    beside the jets, rows: report.print_comparison's."""
    outputs = {"series": plot_drill_series(time, flows, series, stored, run_dir / "series.png", beside=beside),
               "comparison": plot_comparison(rows, run_dir / "comparison.png")}
    if render:
        outputs.update(draw_sections(frames, case, layout, run_dir, lambda: wall_meshes(case, layout)))
    outputs.update(draw_head_sections(frames, case, lambda name: run_dir / f"{name}.png"))
    return outputs


#: The unrolled clearance's first angle, degrees: the edge's chip mouth (negative angles) and both pads (84 and
#: 180 degrees) in one piece.
UNROLL_FROM = -120.0


def draw_head_sections(frames: dict, case, path_of) -> dict:
    """head_sections_<t in ms>.png (path_of(name) -> path) at each of case.output.picture_times that has a frame
    and at the last frame (a run resumed past its duration), for a head with guide pads or cutting edges: the speed
    and pressure of the fluid in the head clearance unrolled (its angle from the main cutting edge against z: a
    section through the pads) and in the front gap's middle layer seen from the face (a section through the cutting
    edges). Returns {name: path}."""
    if not (case.head.pad_angles or case.head.edge_angles):
        return {}
    by_time = {round(float(f["attrs"]["time"]) * 1e9): f for k, f in frames.items() if k != "attrs"}
    out = {}
    times = {round(t * 1e9): t for t in case.output.picture_times}
    if by_time:
        times.setdefault(max(by_time), max(by_time) * 1e-9)
    for key, t in sorted(times.items()):
        frame = by_time.get(key)
        if frame is not None:
            name = f"head_sections_{t * 1e3:.2f}ms"
            out[name] = _draw_head_frame(frame, case, t, path_of(name))
    return out


def _draw_head_frame(frame: dict, case, t: float, path: Path) -> Path:
    """One PNG of draw_head_sections: speed (top) and pressure (bottom); the clearance unrolled (left), the front
    gap (right); pads and blades outlined in black, the edges' chip mouths dashed. Lengths mm, angles degrees."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    net, g, dx = case.network(), case.geometry(), case.numerics.dx
    r_h, r_b, c = net.d_head_body / 2, net.d_bore / 2, g.front_clearance
    fluid = np.asarray(frame["kind"]) == 0
    x = np.asarray(frame["positions"], dtype=float)[fluid]
    speed = np.linalg.norm(np.asarray(frame["velocities"], dtype=float)[fluid], axis=1)
    p = np.asarray(frame["pressures"], dtype=float)[fluid] / 1e5
    r = np.hypot(x[:, 0], x[:, 1])
    angle = np.mod(np.degrees(np.arctan2(x[:, 1], x[:, 0])) - UNROLL_FROM, 360.0) + UNROLL_FROM
    clearance = (r >= r_h) & (r < r_b) & (x[:, 2] < layout_top(case))
    layer = (np.abs(x[:, 2] + 0.5 * c) < 0.5 * dx) & (r < r_b)
    fig = Figure(figsize=(12.0, 8.0), dpi=100, layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(2, 2, width_ratios=(1.6, 1.0))
    for row, (values, label) in enumerate(((speed, "speed [m/s]"), (p, "p [bar, gauge]"))):
        lo, hi = np.percentile(values, [2, 98]) if len(values) else (0.0, 1.0)
        if not hi > lo:  # a field nearly uniform: its whole range
            lo, hi = (float(values.min()), float(values.max()) + 1e-12) if len(values) else (0.0, 1.0)
        left, right = axes[row]
        art = left.scatter(angle[clearance], x[clearance, 2] * 1e3, c=values[clearance], s=6, vmin=lo, vmax=hi,
                           cmap="viridis")
        for pad in pad_solids(case):
            a0 = (np.degrees(pad.a0) - UNROLL_FROM) % 360.0 + UNROLL_FROM
            left.add_patch(Rectangle((a0, pad.z_lo * 1e3), np.degrees(pad.span), (pad.z_hi - pad.z_lo) * 1e3,
                                     fill=False, ec="k", lw=1.5))
        for edge in edge_solids(case):
            a0 = (np.degrees(edge.a0) - UNROLL_FROM) % 360.0 + UNROLL_FROM
            left.add_patch(Rectangle((a0, -c * 1e3), np.degrees(edge.span), c * 1e3, fill=False, ec="k", lw=1.5))
        left.axhline(0.0, color="0.5", lw=0.8)
        left.set_xlim(UNROLL_FROM, UNROLL_FROM + 360.0)
        left.set_xlabel("angle from the main cutting edge [deg] (the tool turns toward -)")
        left.set_ylabel("z [mm] (face at 0, the flow comes down)")
        left.set_title(f"through the pads: the head clearance (r {r_h * 1e3:.4g}-{r_b * 1e3:.4g} mm) unrolled,\n"
                       "and the front gap's outer ring below the face (z < 0)", fontsize=9)
        right.scatter(x[layer, 0] * 1e3, x[layer, 1] * 1e3, c=values[layer], s=6, vmin=lo, vmax=hi, cmap="viridis")
        for solid, style in ([(e, "-") for e in edge_solids(case)] + [(m, "--") for m in edge_mouths(case)]):
            _outline(right, solid, style)
        right.set_xlim(-1.08e3 * r_b, 1.08e3 * r_b)
        right.set_ylim(-1.08e3 * r_b, 1.08e3 * r_b)
        right.set_aspect("equal")
        right.set_xlabel("x [mm]")
        right.set_ylabel("y [mm]")
        right.set_title(f"through the cutting edge: the front gap at z = {-0.5 * c * 1e3:.3g} mm,\n"
                        "seen from the face (dashed: the edge's chip mouth)", fontsize=9)
        fig.colorbar(art, ax=[left, right], label=label, shrink=0.9)
    fig.suptitle(f"t = {t * 1e3:.2f} ms: colours span 2-98 % of the particles", fontsize=10)
    fig.savefig(path)
    return Path(path)


def layout_top(case) -> float:
    """z (m) of the drill-head scene's inlet plane (the flow-exit scene: the head's rear end)."""
    g = case.geometry()
    return g.hole_z - case.scene.inlet_distance if case.scene.area == "drill_head" else g.head_length


def _outline(ax, sector, style: str) -> None:
    """Draw an annular sector's outline (m) in mm on ax."""
    a = np.linspace(sector.a0, sector.a0 + sector.span, 30)
    ring = np.concatenate([sector.r_in * np.exp(1j * a), sector.r_out * np.exp(1j * a[::-1]), [sector.r_in *
                                                                                               np.exp(1j * a[0])]])
    ax.plot(ring.real * 1e3, ring.imag * 1e3, "k" + style, lw=1.5)
