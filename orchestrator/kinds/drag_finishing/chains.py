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

from orchestrator.kinds.drag_finishing.chain_statistics import (
    binned_mean,
    conditional_means,
    force_peaks,
    lagged_correlation,
    peak_coincidence,
)

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


def _strong_graph(snapshot: dict, strong: np.ndarray, length: np.ndarray):
    """The graph of strong ball-ball and ball-bowl contacts (find_chains' rules) and its shortest paths to the bowl.

    Returns (a, n_balls, dist, pred, edge_of): a, the node of each contact's ball (id1); the bowl is node n_balls;
    dist (m) and pred, Dijkstra's distances and predecessors from the bowl; edge_of, (node, node) -> contact index.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra

    role = np.asarray(snapshot["body2_role"]).astype(int)
    id1, id2 = np.asarray(snapshot["id1"]), np.asarray(snapshot["id2"])
    balls = np.unique(np.concatenate([id1, id2[role == ROLE_BALL]]))
    n_balls = len(balls)
    a = np.searchsorted(balls, id1)
    b = np.where(role == ROLE_BALL, np.searchsorted(balls, np.where(role == ROLE_BALL, id2, balls[0])), n_balls)
    edges = np.flatnonzero(strong & (role != ROLE_ROD))
    # one edge per node pair (the shortest contact; duplicates would be summed by the sparse matrix)
    order = edges[np.argsort(length[edges], kind="stable")]
    lo, hi = np.minimum(a[order], b[order]), np.maximum(a[order], b[order])
    _, first = np.unique(lo * (n_balls + 1) + hi, return_index=True)
    edges = order[first]
    edge_of = {(int(min(a[c], b[c])), int(max(a[c], b[c]))): int(c) for c in edges}
    graph = coo_matrix((length[edges], (a[edges], b[edges])), shape=(n_balls + 1, n_balls + 1)).tocsr()
    dist, pred = dijkstra(graph, directed=False, indices=n_balls, return_predecessors=True)
    return a, n_balls, dist, pred, edge_of


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
    fn = np.asarray(snapshot["normal_force"], dtype=float)
    role = np.asarray(snapshot["body2_role"]).astype(int)
    p1 = np.asarray(snapshot["point1"], float).reshape(-1, 3)
    p2 = np.asarray(snapshot["point2"], float).reshape(-1, 3)
    thr = strong_threshold(fn, k_std) if threshold is None else float(threshold)
    strong = np.isfinite(fn) & (fn > 0) & (fn > thr)
    length = np.maximum(np.linalg.norm(p2 - p1, axis=1), 1e-12)
    a, n_balls, dist, pred, edge_of = _strong_graph(snapshot, strong, length)

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
    out, contacts = _per_snapshot(snaps, radius, speed, k_std)
    out["k_std"], out["k_peak"] = k_std, k_peak
    t, fn = _process_force(run, transient_time)
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
    out["shown"] = _shown_snapshots(out, snaps, use, radius, speed, k_std, show_time)
    out["peaks"] = {"times": peak_t, "drag": peak_v, "threshold": thr,
                    **peak_coincidence(peak_t, out["process_time"][use], has[use])}
    out["correlation_strength"] = (lagged_correlation(out["process_time"][use], out["strength"][use], t, -fn,
                                                      out["lags"]) if t.size else np.full(len(out["lags"]), math.nan))
    at_peak = -out["fn"] > thr
    out["strength_at_peaks"] = conditional_means(out["strength"][use], at_peak[use])
    out["scan"] = _strength_scan(out, use, peak_t)
    out["profiles"] = _force_profiles(*contacts)
    return out


def _per_snapshot(snaps: list[dict], radius: float, speed: float, k_std: float) -> tuple[dict, tuple]:
    """The per-snapshot arrays and the pooled per-chain arrays of analyze_chains, and the ball-ball contacts of
    all snapshots (angle to v_w deg, height m, normal force N: one array per snapshot each)."""
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
    return out, (angle, height, force)


def _process_force(run: dict, transient_time: float) -> tuple[np.ndarray, np.ndarray]:
    """(process time s, F_n N) of the force series in the process phase after the transient."""
    series = run.get("series", {})
    t_all = np.asarray(series.get("time", np.zeros(0)), float)
    phase = np.asarray(series.get("phase", np.zeros(0)))
    start = float(run.get("attrs", {}).get("process_start_time", math.nan))
    fn_all = np.asarray(series["workpiece_force"], float)[:, 0] if "workpiece_force" in series else np.zeros(0)
    keep = (phase == 3) & np.isfinite(fn_all) & (t_all - start >= transient_time) if fn_all.size else np.zeros(0, bool)
    return t_all[keep] - start, fn_all[keep]


def _shown_snapshots(out: dict, snaps: list[dict], use: np.ndarray, radius: float, speed: float, k_std: float,
                     show_time: float) -> dict:
    """analyze_chains' "shown": the chains of the snapshot nearest to show_time and of the one of lowest F_n."""
    shown = {"paper": int(np.argmin(np.abs(out["process_time"] - show_time))) if snaps else None,
             "peak": int(np.nanargmin(np.where(use, out["fn"], np.nan))) if (use & np.isfinite(out["fn"])).any()
             else None}
    for name, i in shown.items():
        if i is not None:
            axis, vw = rod_pose(out["process_time"][i], radius, speed)
            shown[name] = dict(find_chains(snaps[i], k_std=k_std, vw=vw), axis=axis, vw=vw, snapshot=snaps[i])
    return shown


def _strength_scan(out: dict, use: np.ndarray, peak_t: np.ndarray) -> list[dict]:
    """Presence of a chain under stricter rules, B > mean + k std for k in 1..5, with F_n and peak coincidence."""
    scan = []
    for k in (1.0, 2.0, 3.0, 4.0, 5.0):
        present = out["strength"] > out["fn_mean"] + k * out["fn_std"]
        scan.append({"k": k, "threshold": float(np.mean(out["fn_mean"] + k * out["fn_std"])),
                     "presence": float(present[use].mean()) if use.any() else math.nan,
                     **conditional_means(out["fn"][use], present[use]),
                     "peaks": peak_coincidence(peak_t, out["process_time"][use], present[use])})
    return scan


def _force_profiles(angle: list, height: list, force: list) -> dict:
    """Mean ball-ball contact force (N) against the angle to v_w (deg) and the height (m), pooled over snapshots."""
    angle_all, height_all, force_all = (np.concatenate(x) if x else np.zeros(0) for x in (angle, height, force))
    top = float(height_all.max()) if height_all.size else HEIGHT_STEP
    profiles = {"angle_edges": ANGLE_EDGES, "angle": binned_mean(angle_all, force_all, ANGLE_EDGES),
                "height_edges": np.arange(0.0, top + HEIGHT_STEP, HEIGHT_STEP)}
    profiles["height"] = binned_mean(height_all, force_all, profiles["height_edges"])
    return profiles
