"""Pictures of contact chains and of the rod's contact intensity (matplotlib, Agg, no pyplot state), and
``report_chains``, the part of ``orchestrator analyze`` that prints and draws them for a drag-finishing run.

Figures (all SI; see chains.py and intensity.py for the definitions):
chains_network.png  xy and xz views of a snapshot's network with the chains highlighted (Uhlmann Fig. 4b-c)
chains_fn.png       F_n with its peaks, the chain count per snapshot and their cross-correlation against lag
contact_profiles.png mean ball-ball contact force against the angle to v_w and against height
rod_intensity.png   the rod unrolled (phi around the rod, height): mesh |F| dt per facet, snapshot normal forces
(impact_speeds.png: plots_impacts.py)
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.kinds.drag_finishing.chains import analyze_chains, chain_strength, find_chains, snapshots_of
from orchestrator.kinds.drag_finishing.intensity import intensity_summary, intensity_text, rod_angle
from orchestrator.plots import font_file, polydata, quiet_headless_vtk
from orchestrator.outputs import save_figure


def figure(width: float, height: float):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=110, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def save(fig, path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    save_figure(fig, path, dpi=fig.dpi, layout=False)  # the output policy: temporary name, rename
    return path


def plot_chain_network(chains: dict, bowl_radius: float, rod_radius: float, rod_tip: float, bed_height: float,
                       path, title: str = "", dominant: dict | None = None) -> Path:
    """xy (top view) and xz (side view) of one snapshot's compressive contacts, width and colour by normal
    force (N), the chains of ``chains`` (find_chains() with snapshot, axis and vw added) underlaid in blue,
    those of ``dominant`` (find_chains() at a threshold just below the chain strength B, with B added) in
    black."""
    from matplotlib.collections import LineCollection
    from matplotlib.patches import Circle, Rectangle

    snap = chains["snapshot"]
    fn = np.asarray(snap["normal_force"], float)
    keep = np.flatnonzero(np.isfinite(fn) & (fn > 0))
    keep = keep[np.argsort(fn[keep])]  # strongest drawn last
    p1 = np.asarray(snap["point1"], float).reshape(-1, 3)
    p2 = np.asarray(snap["point2"], float).reshape(-1, 3)
    fmax = float(fn[keep].max()) if keep.size else 1.0
    halos = [(np.unique(np.concatenate(c["contacts"])), color, width, label) for c, color, width, label in (
        (chains, "tab:blue", 4.5, f"chains rod -> bowl ({chains['n_chains']}): shortest strong paths"),
        (dominant, "k", 7.0, f"dominant chain: widest path, B = {(dominant or {}).get('strength', 0):.3g} N"))
        if c and c["contacts"]]
    fig = figure(12.0, 6.4)
    ax_xy, ax_xz = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.0, 1.0]})
    axis, vw = chains["axis"], chains["vw"]
    for ax, (i, j) in ((ax_xy, (0, 1)), (ax_xz, (0, 2))):
        segs = np.stack([p1[keep][:, [i, j]], p2[keep][:, [i, j]]], axis=1) * 1e3
        lines = LineCollection(segs, array=fn[keep], cmap="RdYlGn_r", clim=(0.0, fmax),
                               linewidths=0.25 + 3.0 * fn[keep] / fmax, zorder=2)
        ax.add_collection(lines)
        for z, (idx, color, width, label) in enumerate(halos):  # under the force colours
            cs = np.stack([p1[idx][:, [i, j]], p2[idx][:, [i, j]]], axis=1) * 1e3
            ax.add_collection(LineCollection(cs, colors=color, linewidths=width, alpha=0.55, zorder=1.9 - 0.1 * z,
                                             label=label))
        ax.set_aspect("equal")
        ax.grid(True, color="0.93", lw=0.5, zorder=0)
    r_b = 1e3 * bowl_radius
    ax_xy.add_patch(Circle((0, 0), r_b, fill=False, color="0.4", lw=1.0))
    ax_xy.add_patch(Circle(1e3 * axis, 1e3 * rod_radius, color="0.55", zorder=4))
    ax_xy.annotate("", xy=1e3 * (axis + 2.2 * rod_radius * vw), xytext=1e3 * (axis + rod_radius * vw),
                   arrowprops={"arrowstyle": "-|>", "color": "k", "lw": 1.5}, zorder=5)
    ax_xy.text(*(1e3 * (axis + 2.9 * rod_radius * vw)), "$v_w$", ha="center", va="center", fontsize=11, zorder=5,
               bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.85})
    ax_xy.set_xlim(-1.05 * r_b, 1.05 * r_b)
    ax_xy.set_ylim(-1.05 * r_b, 1.05 * r_b)
    ax_xy.set_xlabel("x [mm]")
    ax_xy.set_ylabel("y [mm]")
    ax_xy.set_title("xy plane (from above)", fontsize=10)
    top = 1e3 * max(bed_height, float(p1[:, 2].max()) if len(p1) else 0.0) * 1.05
    ax_xz.plot([-r_b, -r_b, r_b, r_b], [top, 0, 0, top], color="0.4", lw=1.0)
    ax_xz.add_patch(Rectangle((1e3 * (axis[0] - rod_radius), 1e3 * rod_tip), 2e3 * rod_radius,
                              top - 1e3 * rod_tip, color="0.55", alpha=0.5, zorder=1.5))
    ax_xz.axhline(1e3 * bed_height, color="0.5", ls="--", lw=0.8)
    ax_xz.set_xlim(-1.05 * r_b, 1.05 * r_b)
    ax_xz.set_ylim(-2.0, top)
    ax_xz.set_xlabel("x [mm]")
    ax_xz.set_ylabel("z [mm]")
    ax_xz.set_title("xz plane (from the side, along -y); dashed: bed level", fontsize=10)
    if halos:
        fig.legend(*ax_xz.get_legend_handles_labels(), loc="outside lower center", ncols=2, fontsize=9, frameon=False)
    bar = fig.colorbar(lines, ax=[ax_xy, ax_xz], shrink=0.8, pad=0.01)
    bar.set_label("normal contact force [N]")
    fig.suptitle(title or "interaction network with contact chains", fontsize=11)
    return save(fig, path)


def plot_chains_time(res: dict, path) -> Path:
    """F_n (N) against process time with the peak threshold and the peaks; the chain count and the chain
    strength B (N) per snapshot; their correlations with -F_n against lag (s)."""
    fig = figure(10.0, 9.0)
    grid = fig.add_gridspec(4, 1, height_ratios=[2.2, 1.0, 1.0, 1.4])
    ax_f = fig.add_subplot(grid[0])
    ax_c, ax_b = fig.add_subplot(grid[1], sharex=ax_f), fig.add_subplot(grid[2], sharex=ax_f)
    ax_r = fig.add_subplot(grid[3])
    t, fn, pk = res["t"], res["fn_series"], res["peaks"]
    ax_f.plot(t, fn, color="C0", lw=0.8, label="$F_n$ of the run (after the transient)")
    if np.isfinite(pk["threshold"]):
        ax_f.axhline(-pk["threshold"], color="C3", ls="--", lw=1.0,
                     label=f"peak threshold: mean $-$ {res['k_peak']:g} std = {-pk['threshold']:.2f} N")
        ax_f.plot(pk["times"], -pk["drag"], "v", color="C3", ms=5, label=f"peaks ({len(pk['times'])})")
    has = res["n_chains"] > 0
    ax_f.plot(res["process_time"][has], res["fn"][has], "o", color="tab:blue", ms=3,
              label="snapshots with a chain")
    ax_f.plot(res["process_time"][~has], res["fn"][~has], "o", mfc="none", color="0.4", ms=3,
              label="snapshots without")
    ax_f.set_ylabel("$F_n$ [N]")
    ax_f.legend(loc="lower left", bbox_to_anchor=(0.0, 1.01), fontsize=7.5, ncols=3, frameon=False)
    ax_c.vlines(res["process_time"], 0, res["n_chains"], color="tab:blue", lw=1.2)
    ax_c.set_ylabel("chains")
    ax_b.plot(res["process_time"], res["strength"], ".-", color="C1", lw=0.8, ms=3)
    ax_b.set_ylabel("strength B [N]")
    ax_b.set_xlabel("process time [s]")
    ax_r.axhline(0.0, color="0.6", lw=0.6)
    ax_r.plot(res["lags"], res["correlation"], color="tab:blue", lw=1.0, label="chain count")
    ax_r.plot(res["lags"], res["correlation_strength"], color="C1", lw=1.0, label="chain strength B")
    n = len(res["time"])
    if not np.isfinite(res["correlation"]).any():
        ax_r.text(0.5, 0.5, "the correlation needs 3 or more snapshots", transform=ax_r.transAxes, ha="center",
                  va="center", color="0.3")
    else:
        ax_r.axhspan(-2 / math.sqrt(n), 2 / math.sqrt(n), color="0.9", lw=0, label="$\\pm 2/\\sqrt{n}$ (noise)")
        ax_r.legend(loc="upper right", fontsize=7.5, ncols=3)
    ax_r.set_xlabel("lag [s] (> 0: $F_n$ after the chains)")
    ax_r.set_ylabel("correlation with $-F_n$")
    for ax in (ax_f, ax_c, ax_b, ax_r):
        ax.grid(True, color="0.93", lw=0.5)
    fig.suptitle("normal force on the rod and contact chains", fontsize=11)
    return save(fig, path)


def plot_force_profiles(res: dict, path) -> Path:
    """Mean ball-ball contact force (N, +- standard error) against the angle to v_w (deg) and height (mm)."""
    fig = figure(10.0, 4.2)
    ax_a, ax_h = fig.subplots(1, 2)
    prof = res["profiles"]
    for ax, key, horizontal in ((ax_a, "angle", True), (ax_h, "height", False)):
        mean, std, count = prof[key]
        edges = prof[f"{key}_edges"] * (1.0 if horizontal else 1e3)
        mid = 0.5 * (edges[1:] + edges[:-1])
        err = std / np.sqrt(np.maximum(count, 1))
        ok = count > 0
        if horizontal:
            ax.errorbar(mid[ok], mean[ok], yerr=err[ok], fmt="o-", color="C3", capsize=3)
            ax.set_xlabel("angle between contact offset from the rod axis and $v_w$ [deg]\n(0 ahead, 180 behind)")
            ax.set_ylabel("mean contact normal force [N]")
            ax.set_xticks(edges)
        else:
            ax.errorbar(mean[ok], mid[ok], xerr=err[ok], fmt="o-", color="C2", capsize=3)
            ax.set_ylabel("height above the bowl floor [mm]")
            ax.set_xlabel("mean contact normal force [N]")
        ax.grid(True, color="0.93", lw=0.5)
    n = len(res["time"])
    fig.suptitle(f"ball-ball contact forces, {n} snapshot{'s' if n != 1 else ''} pooled (bars: standard error, "
                 "contacts taken as independent)", fontsize=11)
    return save(fig, path)


def plot_rod_intensity(ires: dict, rod_tip: float, bed_height: float, path) -> Path:
    """The rod's side unrolled (phi deg, height mm, from the tip to 5 mm above the bed): left the mesh's
    |F| dt per facet (N s; every side facet of the prism spans the rod's whole length), right the snapshots'
    rod contacts: their normal force (N) at the contact points, or with 200 contacts and more the sampled
    normal impulse (N s) in 15 deg x 5 mm bins."""
    from matplotlib.collections import PolyCollection

    geo, snap = ires["geometry"], ires["snapshots"]
    fig = figure(11.0, 5.0)
    ax_m, ax_s = fig.subplots(1, 2, sharey=True)
    side = np.flatnonzero(geo["kind"] == 0)
    if "intensity" in ires and side.size:
        tri = geo["triangles"][side]
        phi = rod_angle(tri.reshape(-1, 3), snap["axis"], snap["vw"]).reshape(-1, 3)
        centre = geo["phi"][side][:, None]
        phi = centre + (np.mod(phi - centre + 180.0, 360.0) - 180.0)  # no triangle split at +-180
        coll = PolyCollection(np.stack([phi, 1e3 * tri[..., 2]], axis=-1), array=ires["intensity"][side],
                              cmap="magma_r", edgecolors="0.7", linewidths=0.3)
        ax_m.add_collection(coll)
        fig.colorbar(coll, ax=ax_m, pad=0.01).set_label("mesh contact intensity $\\sum |F|\\,dt$ [N s]")
        tip = ires["intensity"][geo["kind"] == 1].sum()
        ax_m.set_title(f"per facet, {len(side)} side facets (tip cap: {tip:.3g} N s)", fontsize=10)
    else:
        ax_m.text(0.5, 0.5, "run.h5 holds no per-facet intensity", transform=ax_m.transAxes, ha="center")
    top = 1e3 * bed_height + 5.0
    n = len(snap["phi"])
    if n >= 200 and np.isfinite(snap["spacing"]):
        z_edges = np.arange(1e3 * rod_tip, top + 5.0, 5.0)
        hist, _, _ = np.histogram2d(snap["phi"], 1e3 * snap["z"], bins=[np.arange(-180, 181, 15), z_edges],
                                    weights=snap["normal_force"] * snap["spacing"])
        mesh = ax_s.pcolormesh(np.arange(-180, 181, 15), z_edges, hist.T, cmap="magma_r")
        fig.colorbar(mesh, ax=ax_s, pad=0.01).set_label(f"sampled normal impulse $\\sum f_n \\times$ "
                                                        f"{snap['spacing']:.3g} s [N s]")
    elif n:
        order = np.argsort(snap["normal_force"])
        sc = ax_s.scatter(snap["phi"][order], 1e3 * snap["z"][order], c=snap["normal_force"][order], cmap="magma_r",
                          s=8 + 60 * snap["normal_force"][order] / snap["normal_force"].max(), edgecolors="0.3",
                          linewidths=0.3)
        fig.colorbar(sc, ax=ax_s, pad=0.01).set_label("contact normal force [N]")
    k = ires.get("n_snapshots", 0)
    ax_s.set_title(f"{n} rod contacts in {k} snapshot{'s' if k != 1 else ''}", fontsize=10)
    for ax in (ax_m, ax_s):
        ax.set_xlim(-180, 180)
        ax.set_xticks(np.arange(-180, 181, 45))
        ax.set_xlabel("angle around the rod [deg] (0 front, 90 outer side, 180 back)")
        ax.grid(True, color="0.93", lw=0.5)
    ax_m.set_ylim(1e3 * rod_tip - 2.0, top)
    ax_m.set_ylabel("height above the bowl floor [mm]")
    fig.suptitle("contact intensity on the rod, unrolled (up to 5 mm above the bed)", fontsize=11)
    return save(fig, path)


def render_rod_intensity(ires: dict, vertices: np.ndarray, faces: np.ndarray, top: float, path) -> Path:
    """The rod mesh below height top (m) coloured by its per-facet |F| dt (N s), from four sides (pyvista,
    off-screen, 1200 x 640 pixels); the mesh is turned so that v_w points along +y, outwards along +x."""
    import pyvista as pv

    snap = ires["snapshots"]
    v = np.asarray(vertices, float).reshape(-1, 3).copy()
    v[:, :2] -= snap["axis"]
    c, s = snap["vw"][1], snap["vw"][0]  # turn v_w onto +y
    v[:, :2] = np.column_stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]])
    rod = polydata(pv, {"vertices": v, "faces": faces})
    rod.cell_data["intensity"] = ires["intensity"]
    rod = rod.clip(normal="z", origin=(0.0, 0.0, top), invert=True)
    font = font_file()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    views = (("front (v_w)", (0, 1)), ("outer side", (1, 0)), ("back", (0, -1)), ("inner side", (-1, 0)))
    low, high = rod.bounds[4], rod.bounds[5]
    centre = np.array([0.0, 0.0, 0.5 * (low + high)])
    with quiet_headless_vtk():
        plotter = pv.Plotter(off_screen=True, window_size=(1200, 640), shape=(1, 4), border=False)
        try:
            for col, (label, (dx, dy)) in enumerate(views):
                plotter.subplot(0, col)
                plotter.set_background("white")
                plotter.add_mesh(rod.copy(), scalars="intensity", cmap="magma_r", show_edges=True, edge_color="gray",
                                 clim=(0.0, float(ires["intensity"].max()) or 1.0), show_scalar_bar=col == 3,
                                 scalar_bar_args={"title": "intensity [N s]", "color": "black", "fmt": "%.2g",
                                                  "vertical": True, "position_x": 0.7, "position_y": 0.1,
                                                  "width": 0.1, "height": 0.8})
                plotter.add_text(label, position=(0.04, 0.94), viewport=True, font_size=11, color="black",
                                 font_file=font)
                plotter.camera.focal_point = tuple(centre)
                plotter.camera.position = tuple(centre + 0.2 * np.array([dx, dy, 0.05]))
                plotter.camera.up = (0.0, 0.0, 1.0)
                plotter.camera.view_angle = 18.0
            bar = plotter.scalar_bars["intensity [N s]"]
            for prop in (bar.GetTitleTextProperty(), bar.GetLabelTextProperty()) if font else ():
                prop.SetFontFamily(4)  # VTK_FONT_FILE
                prop.SetFontFile(font)
            plotter.screenshot(str(path))
        finally:
            plotter.close()
    return path


def chain_text(res: dict) -> str:
    """The printed summary of chains.analyze_chains(): each rule first, then the numbers (SI)."""
    n = len(res["time"])
    lines = [f"contact chains ({n} snapshot{'s' if n != 1 else ''}): strong contact = normal force > mean + "
             f"{res['k_std']:g} std of the snapshot's compressive contacts; chain = shortest path (m) through strong "
             "contacts from a ball on the rod to the bowl, one per ball"]
    if not n:
        return "\n".join(lines + ["  no contact snapshots in this run"])
    ch, nc = res["chains"], res["n_chains"]
    lines.append(f"  chains per snapshot {nc.mean():.2f} (min {nc.min():.0f}, max {nc.max():.0f}); snapshots with a "
                 f"chain {100 * np.mean(nc > 0):.0f} %; strong threshold {np.mean(res['threshold']):.4f} N (mean)")
    if ch["n_contacts"].size:
        a, e = (np.percentile(ch[k], [25, 50, 75]) for k in ("angle_to_vw", "elevation"))
        lines += [f"  chain length {ch['n_contacts'].mean():.1f} contacts (min {ch['n_contacts'].min():.0f}, max "
                  f"{ch['n_contacts'].max():.0f}), {1e3 * ch['path_length'].mean():.1f} mm along the path",
                  f"  orientation rod -> bowl: angle to v_w median {a[1]:+.0f} deg (quartiles {a[0]:+.0f}, {a[2]:+.0f};"
                  f" + outwards), ahead (|angle| < 90 deg) {100 * np.mean(np.abs(ch['angle_to_vw']) < 90):.0f} %; "
                  f"elevation median {e[1]:+.0f} deg (quartiles {e[0]:+.0f}, {e[2]:+.0f})",
                  f"  share of the rod's contact normal force on chain balls "
                  f"{100 * np.nanmean(res['share'][nc > 0]):.0f} %, of F_n "
                  f"{100 * np.nanmean(res['share_fn'][nc > 0]):.0f} % (snapshots with chains)"]
    cond, pk = res["conditional"], res["peaks"]
    num = lambda v, w=0: f"{v:{w}.3f}" if np.isfinite(v) else f"{'-':>{w}}"  # noqa: E731
    lines.append(f"  F_n at the snapshots after the transient: with chains {num(cond['with_mean'])} N "
                 f"(n {cond['with_n']}), without {num(cond['without_mean'])} N (n {cond['without_n']})")
    r, rb = res["correlation"], res["correlation_strength"]
    if n > 2 and np.isfinite(r).any():
        i0 = int(np.argmin(np.abs(res["lags"])))
        for name, cc in (("the chain count", r), ("the chain strength B", rb)):
            best = int(np.nanargmax(cc)) if np.isfinite(cc).any() else i0
            lines.append(f"  correlation of {name} with -F_n: r = {cc[i0]:+.2f} at lag 0, largest {cc[best]:+.2f} at "
                         f"lag {res['lags'][best]:+.3f} s (> 0: F_n after the chains; noise about 2/sqrt(n) = "
                         f"{2 / math.sqrt(n):.2f})")
        sb = res["strength_at_peaks"]
        lines += [f"  chain strength B = the largest force that every contact of some rod-to-bowl path exceeds (a "
                  f"chain exists under a threshold T exactly when B > T): mean {np.mean(res['strength']):.3f} N; at "
                  f"snapshots with -F_n above the peak threshold {sb['with_mean']:.3f} N (n {sb['with_n']}), elsewhere "
                  f"{sb['without_mean']:.3f} N (n {sb['without_n']})",
                  f"  F_n peaks (F_n below mean - {res['k_peak']:g} std = {-pk['threshold']:.3f} N, runs < 0.05 s "
                  f"apart merged): {pk['n_peaks']} with a snapshot within {pk['window']:.3f} s, of them with a chain "
                  f"{100 * pk['fraction']:.0f} % (all snapshots: {100 * pk['base_rate']:.0f} %)",
                  "  stricter rules: a chain present when B > mean + k std of the snapshot's compressive contacts",
                  f"    {'k':>3} {'strong > N':>10} {'with chain':>10} {'F_n with':>9} {'without':>9} {'(n)':>5} "
                  f"{'peaks with chain':>17}"]
        for row in res["scan"]:
            lines.append(f"    {row['k']:3g} {row['threshold']:10.3f} {100 * row['presence']:9.0f}% "
                         f"{num(row['with_mean'], 9)} {num(row['without_mean'], 9)} {row['without_n']:5d} "
                         f"{100 * row['peaks']['fraction']:16.0f}%")
    else:
        lines.append("  correlation and peak coincidence need a series of snapshots (output.network_times)")
    for key, label, scale, unit in (("angle", "angle to v_w (0 ahead, 180 behind)", 1.0, "deg"),
                                    ("height", "height above the floor", 1e3, "mm")):
        mean, _, count = res["profiles"][key]
        edges = res["profiles"][f"{key}_edges"] * scale
        cols = [i for i in range(len(mean)) if count[i]]
        lines += [f"  mean ball-ball contact force against {label}:",
                  f"    {unit:>6} " + " ".join(f"{f'{edges[i]:.0f}-{edges[i + 1]:.0f}':>8}" for i in cols),
                  f"    {'F [N]':>6} " + " ".join(f"{mean[i]:8.4f}" for i in cols)]
    return "\n".join(lines)


def report_chains(run_dir, run: dict, case, render: bool = True) -> dict:
    """Print the chain statistics and the intensity summary of a drag-finishing run and write the PNGs
    into run_dir (when render); returns {name: path}."""

    model = getattr(case, "model", case)
    run_dir = Path(run_dir)
    if not snapshots_of(run):
        return {}
    res = analyze_chains(run, float(model.analysis.transient_time))
    print(chain_text(res))
    ires = intensity_summary(run) if "rod" in run.get("meshes", {}) else None
    if ires is not None:
        print(intensity_text(ires, float(model.output.record_interval)))
    if not render:
        return {}
    rod_tip = float(np.asarray(run["meshes"]["rod"]["vertices"], float)[:, 2].min()) if ires is not None else 0.0
    bed = float(run.get("attrs", {}).get("bed_height", model.media.fill_height))
    out = {}
    for name, view in res["shown"].items():
        if view is None or (name == "peak" and view["snapshot"] is res["shown"]["paper"]["snapshot"]):
            continue
        when = "at the lowest F_n of the snapshots, " if name == "peak" else ""
        title = (f"interaction network {when}at process time {float(view['snapshot']['attrs']['process_time']):.3g}"
                 f" s: strong > {view['threshold']:.3g} N, {view['n_chains']} chains (blue)")
        key, file = ("chains", "chains_network.png") if name == "paper" else ("chain_pk", "chains_network_peak.png")
        strength = chain_strength(view["snapshot"])
        dominant = dict(find_chains(view["snapshot"], threshold=strength * (1 - 1e-9)), strength=strength)
        out[key] = plot_chain_network(view, model.bowl.inner_radius, model.workpiece.radius, rod_tip, bed,
                                      run_dir / file, title, dominant if strength > 0 else None)
    out.update({
        "chain_fn": plot_chains_time(res, run_dir / "chains_fn.png"),
        "profiles": plot_force_profiles(res, run_dir / "contact_profiles.png")})
    if ires is not None:
        ires["n_snapshots"] = len(res["time"])
        out["rod_map"] = plot_rod_intensity(ires, rod_tip, bed, run_dir / "rod_intensity.png")
        if "intensity" in ires:
            rod = run["meshes"]["rod"]
            out["rod_3d"] = render_rod_intensity(ires, rod["vertices"], rod["faces"], bed + 0.005,
                                                 run_dir / "rod_intensity_3d.png")
    return out
