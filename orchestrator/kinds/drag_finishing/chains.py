"""Contact chains between rod and bowl (Uhlmann et al. 2015, Figs. 4b-c) and
their link to the force on the rod. Pure numpy/scipy on the arrays of a
run.h5 contact snapshot (``/contacts/<k>/``); everything SI (m, N, s),
angles in degrees.

Definitions (the defaults; each is a parameter):

* **Strong contact**: a compressive contact (normal force > 0) whose normal
  force exceeds the snapshot's mean + ``k_std`` (1.0) standard deviations
  of all compressive contacts (ball-ball, ball-bowl, ball-rod) of that
  snapshot.
* **Graph**: nodes are the balls and the bowl; edges are the strong
  ball-ball and ball-bowl contacts, weighted by their branch length (ball
  centre to ball centre, ball centre to the contact point on the bowl).
* **Chain**: for every ball with a strong contact on the rod, the shortest
  path (in metres, Dijkstra) through strong contacts from that ball to the
  bowl, if one exists: rod -> ball -> ... -> ball -> bowl. A ball touching
  two rod facets starts one chain. Its length is counted in contacts
  (including the rod and bowl contacts) and in metres along the path (rod
  contact point, ball centres, bowl contact point). Its orientation is the
  vector from the rod contact point to the bowl contact point: angle in the
  xy plane atan2(dy, dx), in the xz plane atan2(dz, dx), relative to the
  rod's velocity v_w in the xy plane (0 ahead, +90 outwards towards the bowl
  wall, -90 towards the bowl axis) and its elevation atan2(dz, |d_xy|).
* **Share**: the sum of the normal forces of all rod contacts of chain-
  starting balls over the sum of all compressive rod contacts, and the same
  for the force component along v_w (the part of F_n the chains carry).
* **Force peak**: a run of samples of the drag D = -F_n (N; F_n < 0
  resists the motion) above mean(D) + ``k_peak`` (1.0) std(D) after the
  transient (runs less than 0.05 s apart merged); the peak is the run's
  largest D. A peak coincides with chains when the snapshot nearest to it
  (within ``window``, default half the snapshot spacing) has a chain.

The rod turns about the bowl axis (z through the origin) from angle 0 (+x)
at omega = v_w / r_path (see ``rod_pose``).
"""

from __future__ import annotations

import math

import numpy as np

ROLE_BALL, ROLE_BOWL, ROLE_ROD = 0, 1, 2


def rod_pose(process_time: float, path_radius: float, speed: float) -> tuple[np.ndarray, np.ndarray]:
    """(rod axis xy (2,) m, unit velocity direction xy (2,)) at process_time (s) on a circle of
    path_radius (m) run at speed (m/s) counter-clockwise from +x."""
    theta = speed / path_radius * process_time
    return (path_radius * np.array([math.cos(theta), math.sin(theta)]),
            np.array([-math.sin(theta), math.cos(theta)]))


def strong_threshold(normal_force: np.ndarray, k_std: float = 1.0) -> float:
    """Mean + k_std * std (N, population std) of the compressive (> 0) normal forces; inf if there are none."""
    f = np.asarray(normal_force, dtype=float)
    f = f[np.isfinite(f) & (f > 0)]
    return float(f.mean() + k_std * f.std()) if f.size else math.inf


def contact_points(point1: np.ndarray, point2: np.ndarray, role: np.ndarray) -> np.ndarray:
    """Contact locations (n,3) m: the midpoint of the two centres for ball-ball, point2 (the contact point) on walls."""
    p1, p2 = np.asarray(point1, float).reshape(-1, 3), np.asarray(point2, float).reshape(-1, 3)
    return np.where((np.asarray(role) == ROLE_BALL)[:, None], 0.5 * (p1 + p2), p2)


def _angles(d: np.ndarray, vw: np.ndarray | None) -> dict[str, np.ndarray]:
    d = np.asarray(d, float).reshape(-1, 3)
    out = {"angle_xy": np.degrees(np.arctan2(d[:, 1], d[:, 0])),
           "angle_xz": np.degrees(np.arctan2(d[:, 2], d[:, 0])),
           "elevation": np.degrees(np.arctan2(d[:, 2], np.hypot(d[:, 0], d[:, 1])))}
    vw = np.full(2, np.nan) if vw is None else np.asarray(vw, float)
    outward = np.array([vw[1], -vw[0]])  # v_w turned clockwise: away from the axis for counter-clockwise motion
    out["angle_to_vw"] = np.degrees(np.arctan2(d[:, :2] @ outward, d[:, :2] @ vw))
    return out


def find_chains(snapshot: dict, threshold: float | None = None, k_std: float = 1.0,
                vw: np.ndarray | None = None) -> dict:
    """Chains rod -> bowl in one contact snapshot (see the module docstring for the rules).

    snapshot: arrays id1, id2, normal_force (n,) N, point1, point2 (n,3) m,
    body2_role (n,); id1 is a ball. threshold (N) overrides the mean + k_std
    std rule; vw (2,) is the rod's unit velocity in xy (for angle_to_vw and
    the F_n share). Returns a dict: threshold, n_strong, n_chains, rod_force
    (sum of compressive rod contact forces, N), chain_rod_force, share,
    share_fn (of the force along v_w; nan without vw), and per chain arrays
    (length n_chains) n_contacts, path_length (m), span (m), vector (n,3) m,
    angle_xy, angle_xz, elevation, angle_to_vw (deg), start_force (N, the
    strongest rod contact of the chain's ball), weakest (N), and contacts
    (a list of index arrays into the snapshot, rod contact first).
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra

    fn = np.asarray(snapshot["normal_force"], dtype=float)
    role = np.asarray(snapshot["body2_role"]).astype(int)
    id1, id2 = np.asarray(snapshot["id1"]), np.asarray(snapshot["id2"])
    p1 = np.asarray(snapshot["point1"], float).reshape(-1, 3)
    p2 = np.asarray(snapshot["point2"], float).reshape(-1, 3)
    thr = strong_threshold(fn, k_std) if threshold is None else float(threshold)
    strong = np.isfinite(fn) & (fn > 0) & (fn > thr)
    balls = np.unique(np.concatenate([id1, id2[role == ROLE_BALL]]))
    n_balls = len(balls)
    a = np.searchsorted(balls, id1)
    b = np.where(role == ROLE_BALL, np.searchsorted(balls, np.where(role == ROLE_BALL, id2, balls[0])), n_balls)
    length = np.maximum(np.linalg.norm(p2 - p1, axis=1), 1e-12)
    edges = np.flatnonzero(strong & (role != ROLE_ROD))
    # one edge per node pair (the shortest contact; duplicates would be summed by the sparse matrix)
    order = edges[np.argsort(length[edges], kind="stable")]
    lo, hi = np.minimum(a[order], b[order]), np.maximum(a[order], b[order])
    _, first = np.unique(lo * (n_balls + 1) + hi, return_index=True)
    edges = order[first]
    edge_of = {(int(min(a[c], b[c])), int(max(a[c], b[c]))): int(c) for c in edges}
    graph = coo_matrix((length[edges], (a[edges], b[edges])), shape=(n_balls + 1, n_balls + 1)).tocsr()
    dist, pred = dijkstra(graph, directed=False, indices=n_balls, return_predecessors=True)

    rod = np.flatnonzero((role == ROLE_ROD) & np.isfinite(fn) & (fn > 0))
    along = (np.zeros(len(fn)) if vw is None else
             -(np.asarray(snapshot["normal_force_vector"], float).reshape(-1, 3)[:, :2] @ np.asarray(vw, float)))
    starts: dict[int, int] = {}  # ball node -> its strongest strong rod contact
    for c in rod[strong[rod]]:
        if np.isfinite(dist[a[c]]) and (a[c] not in starts or fn[c] > fn[starts[a[c]]]):
            starts[int(a[c])] = int(c)
    chains: list[np.ndarray] = []
    for node, c in sorted(starts.items()):
        path, here = [c], node
        while here != n_balls:
            nxt = int(pred[here])
            path.append(edge_of[(min(here, nxt), max(here, nxt))])
            here = nxt
        chains.append(np.array(path))
    in_chain = np.isin(a[rod], list(starts))
    vectors = np.array([p2[p[-1]] - p2[p[0]] for p in chains]).reshape(-1, 3)
    out = {"threshold": thr, "n_strong": int(strong.sum()), "n_chains": len(chains), "contacts": chains,
           "rod_force": float(fn[rod].sum()), "chain_rod_force": float(fn[rod[in_chain]].sum()),
           "n_contacts": np.array([len(p) for p in chains], dtype=int),
           "path_length": np.array([length[p].sum() for p in chains]),
           "span": np.linalg.norm(vectors, axis=1), "vector": vectors,
           "start_force": np.array([fn[p[0]] for p in chains]),
           "weakest": np.array([fn[p].min() for p in chains])}
    out["share"] = out["chain_rod_force"] / out["rod_force"] if out["rod_force"] > 0 else math.nan
    total_along = along[rod].sum()
    out["share_fn"] = float(along[rod[in_chain]].sum() / total_along) if vw is not None and total_along else math.nan
    out.update(_angles(vectors, vw))
    return out


def rod_drag_from_snapshot(snapshot: dict, vw: np.ndarray) -> float:
    """F_n (N) of one snapshot: the contact forces on the rod (normal_force_vector + tangential_force are
    the forces on body 2) along the unit velocity vw (2,); < 0 when the media resists the motion."""
    role = np.asarray(snapshot["body2_role"])
    force = (np.asarray(snapshot["normal_force_vector"], float).reshape(-1, 3)
             + np.asarray(snapshot["tangential_force"], float).reshape(-1, 3))[role == ROLE_ROD]
    return float(force[:, :2].sum(axis=0) @ np.asarray(vw, float))


def chain_strength(snapshot: dict) -> float:
    """Bottleneck B (N) of the strongest rod-to-bowl path: the largest force such that some path
    rod -> balls -> bowl has every contact above it (widest path; 0 if rod and bowl are not connected
    by compressive contacts). A chain exists under any threshold T exactly when B > T."""
    fn = np.asarray(snapshot["normal_force"], dtype=float)
    role = np.asarray(snapshot["body2_role"]).astype(int)
    id1, id2 = np.asarray(snapshot["id1"]), np.asarray(snapshot["id2"])
    balls = np.unique(np.concatenate([id1, id2[role == ROLE_BALL]]))
    n = len(balls)  # node n: the bowl, n + 1: the rod
    a = np.searchsorted(balls, id1)
    b = np.where(role == ROLE_BALL, np.searchsorted(balls, np.where(role == ROLE_BALL, id2, balls[0])),
                 n + (role == ROLE_ROD))
    parent = np.arange(n + 2)

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for c in np.argsort(-np.where(np.isfinite(fn), fn, -np.inf), kind="stable"):
        if not fn[c] > 0:
            break
        parent[root(int(a[c]))] = root(int(b[c]))
        if root(n) == root(n + 1):
            return float(fn[c])
    return 0.0


# ------------------------------------------------------------------ over snapshots


def conditional_means(values: np.ndarray, condition: np.ndarray) -> dict[str, float]:
    """Mean, std and count of values where condition holds ("with") and where not ("without"), in values' units."""
    values, condition = np.asarray(values, float), np.asarray(condition, bool)
    out = {}
    for name, sel in (("with", condition), ("without", ~condition)):
        v = values[sel & np.isfinite(values)]
        out[f"{name}_n"] = int(v.size)
        out[f"{name}_mean"] = float(v.mean()) if v.size else math.nan
        out[f"{name}_std"] = float(v.std(ddof=1)) if v.size > 1 else math.nan
    return out


def lagged_correlation(t_events: np.ndarray, counts: np.ndarray, t: np.ndarray, signal: np.ndarray,
                       lags: np.ndarray) -> np.ndarray:
    """Pearson correlation of counts (at times t_events, s) with signal(t_event + lag) for each lag (s);
    the signal (sampled at t, s) is interpolated linearly. nan where fewer than 3 events fall inside
    the signal's span or either side is constant. Positive lag: the signal follows the counts."""
    t_events, counts = np.asarray(t_events, float), np.asarray(counts, float)
    t, signal = np.asarray(t, float), np.asarray(signal, float)
    r = np.full(len(lags), math.nan)
    for i, lag in enumerate(lags):
        when = t_events + lag
        inside = (when >= t[0]) & (when <= t[-1])
        if inside.sum() < 3:
            continue
        x, y = counts[inside], np.interp(when[inside], t, signal)
        if x.std() > 0 and y.std() > 0:
            r[i] = float(np.corrcoef(x, y)[0, 1])
    return r


def force_peaks(t: np.ndarray, drag: np.ndarray, k_peak: float = 1.0,
                min_gap: float = 0.05) -> tuple[np.ndarray, np.ndarray, float]:
    """(peak times s, peak values, threshold) of a series: one peak per run of samples above mean + k_peak
    std (same units as drag), at the run's largest sample; runs less than min_gap (s) apart count as one
    (noise makes a single excursion cross the threshold several times)."""
    t, drag = np.asarray(t, float), np.asarray(drag, float)
    thr = float(np.nanmean(drag) + k_peak * np.nanstd(drag))
    above = np.concatenate([[False], drag > thr, [False]])
    starts, ends = np.flatnonzero(~above[:-1] & above[1:]), np.flatnonzero(above[:-1] & ~above[1:])
    runs: list[list[int]] = []
    for s, e in zip(starts, ends):
        if runs and t[s] - t[runs[-1][1] - 1] < min_gap:
            runs[-1][1] = e
        else:
            runs.append([s, e])
    idx = np.array([s + int(np.argmax(drag[s:e])) for s, e in runs], dtype=int)
    return t[idx], drag[idx], thr


def peak_coincidence(peak_times: np.ndarray, t_snap: np.ndarray, has_chain: np.ndarray,
                     window: float | None = None) -> dict[str, float]:
    """Fraction of force peaks whose nearest snapshot (within window s; default half the median snapshot
    spacing) has a chain, next to the base rate (fraction of all snapshots with a chain). Peaks with no
    snapshot within the window are not counted."""
    t_snap, has_chain = np.asarray(t_snap, float), np.asarray(has_chain, bool)
    peak_times = np.asarray(peak_times, float)
    if window is None:
        window = 0.5 * float(np.median(np.diff(np.sort(t_snap)))) if len(t_snap) > 1 else 0.0
    base = float(has_chain.mean()) if has_chain.size else math.nan
    if not t_snap.size or not peak_times.size:
        return {"n_peaks": 0, "fraction": math.nan, "base_rate": base, "window": window}
    nearest = np.argmin(np.abs(peak_times[:, None] - t_snap[None, :]), axis=1)
    covered = np.abs(t_snap[nearest] - peak_times) <= window + 1e-12
    hits = has_chain[nearest[covered]]
    return {"n_peaks": int(covered.sum()), "fraction": float(hits.mean()) if hits.size else math.nan,
            "base_rate": base, "window": float(window)}


def binned_mean(x: np.ndarray, values: np.ndarray, edges: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(mean, std, count) of values in the bins of x given by edges (len(edges) - 1 each; nan if empty)."""
    x, values = np.asarray(x, float), np.asarray(values, float)
    idx = np.digitize(x, edges) - 1
    nb = len(edges) - 1
    ok = (idx >= 0) & (idx < nb) & np.isfinite(values)
    count = np.bincount(idx[ok], minlength=nb).astype(float)
    s1 = np.bincount(idx[ok], values[ok], minlength=nb)
    s2 = np.bincount(idx[ok], values[ok] ** 2, minlength=nb)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = s1 / count
        std = np.sqrt(np.maximum(s2 / count - mean**2, 0.0))
    return mean, std, count.astype(int)


def angle_to_velocity(points: np.ndarray, axis_xy: np.ndarray, vw: np.ndarray) -> np.ndarray:
    """Angle (deg, 0..180) between the horizontal offset of points (n,3) m from the rod axis and v_w:
    0 straight ahead of the rod, 180 straight behind."""
    d = np.asarray(points, float).reshape(-1, 3)[:, :2] - np.asarray(axis_xy, float)
    cos = (d @ np.asarray(vw, float)) / np.maximum(np.linalg.norm(d, axis=1), 1e-300)
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


# ------------------------------------------------------------------ a whole run

#: Bins of the force profiles: the angle to v_w (deg) and the height above the bowl floor (m).
ANGLE_EDGES = np.arange(0.0, 180.1, 30.0)
HEIGHT_STEP = 0.01


def snapshots_of(run: dict) -> list[dict]:
    """The contact snapshots of a read_run() dict in time order (those holding normal forces)."""
    snaps = [g for key, g in run.get("contacts", {}).items() if key != "attrs" and "normal_force" in g]
    return sorted(snaps, key=lambda g: float(g["attrs"].get("time", math.nan)))


def path_of(run: dict) -> tuple[float, float]:
    """(workpiece.path_radius m, workpiece.speed m/s) from the run's case parameters."""
    params = run.get("case", {}).get("attrs", {})
    return float(params["workpiece.path_radius"]), float(params["workpiece.speed"])


def analyze_chains(run: dict, transient_time: float = 0.0, k_std: float = 1.0, k_peak: float = 1.0,
                   max_lag: float = 0.5, show_time: float = 4.5) -> dict:
    """Chains in every snapshot of a run and their relation to F_n (see the module docstring).

    Returns a dict: per snapshot arrays (time, process_time s, n_chains, n_strong, threshold N, share,
    share_fn, fn (F_n of the force series at the snapshot, N), fn_snapshot (from the snapshot's rod
    contacts, N)); chains: the per-chain arrays of all snapshots pooled (n_contacts, path_length,
    angle_to_vw, elevation, angle_xy, angle_xz); shown: {"paper": find_chains() with axis, vw and
    snapshot of the snapshot nearest to show_time (s of process; the paper's Figs. 4b-c: 4.5 s),
    "peak": the same for the snapshot of lowest F_n after the transient}; conditional (F_n with
    and without chains), lags (s) and correlation (chain count against the drag -F_n); strength
    (chain_strength() per snapshot, N), correlation_strength (against -F_n), strength_at_peaks
    (conditional_means of the strength at snapshots with -F_n above the peak threshold or not);
    scan: per k in 1..5 the presence of a chain under B > mean + k std, F_n with and without, peak
    coincidence; fn_mean, fn_std (N, of the compressive contacts); peaks (times, drag, threshold,
    coincidence); t, fn_series (after the transient); profiles of the
    mean ball-ball contact force against the angle to v_w and height, pooled over the snapshots.
    """
    radius, speed = path_of(run)
    snaps = snapshots_of(run)
    keys = ("n_chains", "n_strong", "threshold", "share", "share_fn", "fn_snapshot", "strength", "fn_mean", "fn_std")
    per: dict[str, list] = {k: [] for k in ("time", "process_time", *keys)}
    pooled: dict[str, list] = {k: [] for k in ("n_contacts", "path_length", "angle_to_vw", "elevation", "angle_xy",
                                                "angle_xz")}
    angle, height, force = [], [], []
    for snap in snaps:
        tp = float(snap["attrs"].get("process_time", math.nan))
        axis, vw = rod_pose(tp, radius, speed)
        found = find_chains(snap, k_std=k_std, vw=vw)
        per["time"].append(float(snap["attrs"]["time"]))
        per["process_time"].append(tp)
        for k in keys[:5]:
            per[k].append(found[k])
        per["fn_snapshot"].append(rod_drag_from_snapshot(snap, vw))
        per["strength"].append(chain_strength(snap))
        role = np.asarray(snap["body2_role"])
        fn = np.asarray(snap["normal_force"], float)
        per["fn_mean"].append(fn[fn > 0].mean() if (fn > 0).any() else math.nan)
        per["fn_std"].append(fn[fn > 0].std() if (fn > 0).any() else math.nan)
        for k in pooled:
            pooled[k].extend(np.asarray(found[k]).tolist())
        sel = (role == ROLE_BALL) & (fn > 0)
        pts = contact_points(snap["point1"], snap["point2"], role)[sel]
        angle.append(angle_to_velocity(pts, axis, vw))
        height.append(pts[:, 2])
        force.append(fn[sel])
    out = {k: np.asarray(v, float) for k, v in per.items()}
    out["chains"] = {k: np.asarray(v, float) for k, v in pooled.items()}
    out["k_std"], out["k_peak"] = k_std, k_peak

    series = run.get("series", {})
    t_all = np.asarray(series.get("time", np.zeros(0)), float)
    phase = np.asarray(series.get("phase", np.zeros(0)))
    start = float(run.get("attrs", {}).get("process_start_time", math.nan))
    fn_all = np.asarray(series["workpiece_force"], float)[:, 0] if "workpiece_force" in series else np.zeros(0)
    keep = (phase == 3) & np.isfinite(fn_all) & (t_all - start >= transient_time) if fn_all.size else np.zeros(0, bool)
    t, fn = t_all[keep] - start, fn_all[keep]
    out["t"], out["fn_series"] = t, fn
    has = out["n_chains"] > 0
    use = out["process_time"] >= transient_time
    inside = use & (out["process_time"] <= (t[-1] if t.size else -math.inf))
    out["fn"] = np.where(inside, np.interp(out["process_time"], t, fn) if t.size else math.nan, math.nan)
    out["conditional"] = conditional_means(out["fn"][use], has[use])
    step = float(np.median(np.diff(t))) if t.size > 1 else 0.005
    out["lags"] = np.arange(-round(max_lag / step), round(max_lag / step) + 1) * step
    out["correlation"] = (lagged_correlation(out["process_time"][use], out["n_chains"][use], t, -fn, out["lags"])
                          if t.size else np.full(len(out["lags"]), math.nan))
    peak_t, peak_v, thr = force_peaks(t, -fn, k_peak) if t.size else (np.zeros(0), np.zeros(0), math.nan)
    shown = {"paper": int(np.argmin(np.abs(out["process_time"] - show_time))) if snaps else None,
             "peak": int(np.nanargmin(np.where(use, out["fn"], np.nan))) if (use & np.isfinite(out["fn"])).any()
             else None}
    for name, i in shown.items():
        if i is not None:
            axis, vw = rod_pose(out["process_time"][i], radius, speed)
            shown[name] = dict(find_chains(snaps[i], k_std=k_std, vw=vw), axis=axis, vw=vw, snapshot=snaps[i])
    out["shown"] = shown
    out["peaks"] = {"times": peak_t, "drag": peak_v, "threshold": thr,
                    **peak_coincidence(peak_t, out["process_time"][use], has[use])}
    out["correlation_strength"] = (lagged_correlation(out["process_time"][use], out["strength"][use], t, -fn,
                                                      out["lags"]) if t.size else np.full(len(out["lags"]), math.nan))
    at_peak = -out["fn"] > thr
    out["strength_at_peaks"] = conditional_means(out["strength"][use], at_peak[use])
    out["scan"] = []  # presence under stricter rules: B > mean + k std
    for k in (1.0, 2.0, 3.0, 4.0, 5.0):
        present = out["strength"] > out["fn_mean"] + k * out["fn_std"]
        out["scan"].append({"k": k, "threshold": float(np.mean(out["fn_mean"] + k * out["fn_std"])),
                            "presence": float(present[use].mean()) if use.any() else math.nan,
                            **conditional_means(out["fn"][use], present[use]),
                            "peaks": peak_coincidence(peak_t, out["process_time"][use], present[use])})
    angle_all, height_all, force_all = (np.concatenate(x) if x else np.zeros(0) for x in (angle, height, force))
    top = float(height_all.max()) if height_all.size else HEIGHT_STEP
    out["profiles"] = {"angle_edges": ANGLE_EDGES, "angle": binned_mean(angle_all, force_all, ANGLE_EDGES),
                       "height_edges": np.arange(0.0, top + HEIGHT_STEP, HEIGHT_STEP)}
    out["profiles"]["height"] = binned_mean(height_all, force_all, out["profiles"]["height_edges"])
    return out
