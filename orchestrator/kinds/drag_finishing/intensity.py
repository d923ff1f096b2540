"""Contact intensity on the workpiece (Uhlmann et al. 2015: "number, type and
intensity of contacts ... for finite areas of any workpiece"), per rod facet.

What run.h5 holds and what is measured from it (SI units, angles in deg):

* ``/meshes/rod`` contact_intensity (N s): per facet the sum of |F| dt over
  the records from the insertion on, |F| the whole contact force (normal and
  shear: LIGGGHTS from fix mesh/surface/stress, Yade from the facet's force),
  dt the record interval; contact_count: the number of records in which the
  facet carried force (not the number of distinct contacts).
* From the contact snapshots (``/contacts/<k>/``, body2_role 2): each ball-rod
  contact is mapped to the facet nearest to its contact point (the point
  turned into the pose the mesh was stored in); per facet the number of
  contacts seen in the snapshots, the largest normal force (N) and the
  sampled normal impulse sum(F_n) * spacing (N s; an estimate only when the
  snapshots are dense, spacing = the median time between snapshots).
* The normal impact speed at contact start: impacts.py (/events, recorded by the engines in
  output.impact_window). ``approach_speeds`` is a proxy from the frames (positions and velocities stored with
  each snapshot): the normal velocity, relative to the rod surface, of the balls within a small gap of the rod
  and moving towards it.

Angles around the rod: phi = 0 faces v_w (front), +90 outwards (towards the
bowl wall), +-180 the back, -90 towards the bowl axis.
"""

from __future__ import annotations

import math

import numpy as np

from orchestrator.kinds.drag_finishing.chains import ROLE_ROD, path_of, rod_pose, snapshots_of


def turn_z(points: np.ndarray, angle: float | np.ndarray) -> np.ndarray:
    """points (n,3) turned by angle (rad, scalar or (n,)) about the z axis."""
    p = np.asarray(points, float).reshape(-1, 3)
    c, s = np.cos(angle), np.sin(angle)
    return np.column_stack([c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1], p[:, 2]])


def rod_angle(points: np.ndarray, axis_xy: np.ndarray, vw: np.ndarray) -> np.ndarray:
    """phi (deg, -180..180] of points (n,3) m around the rod axis: 0 along v_w, +90 outwards."""
    d = np.asarray(points, float).reshape(-1, 3)[:, :2] - np.asarray(axis_xy, float)
    outward = np.array([vw[1], -vw[0]])
    return np.degrees(np.arctan2(d @ outward, d @ np.asarray(vw, float)))


def point_triangle_distance(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Distances (n, m) in m from points (n,3) to triangles (m,3,3): to the plane where the projection
    falls inside the triangle, else to the nearest edge."""
    p = np.asarray(points, float).reshape(-1, 1, 3)
    tri = np.asarray(triangles, float).reshape(1, -1, 3, 3)
    a, b, c = tri[..., 0, :], tri[..., 1, :], tri[..., 2, :]
    normal = np.cross(b - a, c - a)
    normal = normal / np.maximum(np.linalg.norm(normal, axis=-1, keepdims=True), 1e-300)
    height = np.sum((p - a) * normal, axis=-1)
    q = p - height[..., None] * normal
    inside = np.ones(height.shape, bool)
    for u, v in ((a, b), (b, c), (c, a)):
        inside &= np.sum(np.cross(v - u, q - u) * normal, axis=-1) >= -1e-15
    best = np.where(inside, np.abs(height), np.inf)
    for u, v in ((a, b), (b, c), (c, a)):
        e = v - u
        s = np.clip(np.sum((p - u) * e, axis=-1) / np.maximum(np.sum(e * e, axis=-1), 1e-300), 0.0, 1.0)
        best = np.minimum(best, np.linalg.norm(p - (u + s[..., None] * e), axis=-1))
    return best


def nearest_facet(points: np.ndarray, vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Index of the nearest face (of vertices (v,3) m, faces (f,3)) for each point (n,3) m."""
    if len(points) == 0:
        return np.zeros(0, dtype=int)
    tri = np.asarray(vertices, float)[np.asarray(faces, int)]
    return np.argmin(point_triangle_distance(points, tri), axis=1)


def facet_geometry(vertices: np.ndarray, faces: np.ndarray, axis_xy: np.ndarray, vw: np.ndarray) -> dict:
    """Per face: centroid (f,3) m, area m^2, phi (deg, of the centroid), kind (0 side, 1 tip cap, 2 top cap)."""
    tri = np.asarray(vertices, float)[np.asarray(faces, int)]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    area = 0.5 * np.linalg.norm(cross, axis=1)
    nz = cross[:, 2] / np.maximum(2 * area, 1e-300)
    kind = np.where(nz < -0.9, 1, np.where(nz > 0.9, 2, 0))
    centroid = tri.mean(axis=1)
    return {"centroid": centroid, "area": area, "phi": rod_angle(centroid, axis_xy, vw), "kind": kind,
            "triangles": tri}


def snapshot_facet_contacts(run: dict) -> dict:
    """Rod contacts of every snapshot mapped to the rod facets (see the module docstring).

    Returns: facet (n,) index per contact, normal_force (n,) N, process_time (n,) s, phi (n,) deg,
    z (n,) m (contact point), and per facet count, peak (N), impulse (N s, sum F_n x spacing),
    spacing (s) and the mesh's pose (axis, vw at the time the mesh was stored).
    """
    radius, speed = path_of(run)
    rod = run["meshes"]["rod"]
    n_faces = len(rod["faces"])
    attrs = run.get("attrs", {})
    tp_end = float(attrs.get("simulated_time", math.nan)) - float(attrs.get("process_start_time", math.nan))
    axis_end, vw_end = rod_pose(tp_end, radius, speed)
    snaps = snapshots_of(run)
    times = np.array([float(s["attrs"].get("process_time", math.nan)) for s in snaps])
    spacing = float(np.median(np.diff(times))) if len(times) > 1 else math.nan
    facet, force, when, phi, z = [], [], [], [], []
    for snap, tp in zip(snaps, times):
        sel = (np.asarray(snap["body2_role"]) == ROLE_ROD) & (np.asarray(snap["normal_force"], float) > 0)
        pts = np.asarray(snap["point2"], float).reshape(-1, 3)[sel]
        axis, vw = rod_pose(tp, radius, speed)
        phi.append(rod_angle(pts, axis, vw))
        z.append(pts[:, 2])
        facet.append(nearest_facet(turn_z(pts, speed / radius * (tp_end - tp)), rod["vertices"], rod["faces"]))
        force.append(np.asarray(snap["normal_force"], float)[sel])
        when.append(np.full(int(sel.sum()), tp))
    cat = lambda x, dtype=float: np.concatenate(x).astype(dtype) if x else np.zeros(0, dtype)  # noqa: E731
    out = {"facet": cat(facet, int), "normal_force": cat(force), "process_time": cat(when), "phi": cat(phi),
           "z": cat(z), "spacing": spacing, "axis": axis_end, "vw": vw_end}
    out["count"] = np.bincount(out["facet"], minlength=n_faces)
    out["peak"] = np.zeros(n_faces)
    np.maximum.at(out["peak"], out["facet"], out["normal_force"])
    out["impulse"] = np.bincount(out["facet"], out["normal_force"], minlength=n_faces) * spacing
    return out


def approach_speeds(positions: np.ndarray, radii: np.ndarray, velocities: np.ndarray, axis_xy: np.ndarray,
                    omega: float, rod_radius: float, z_range: tuple[float, float], gap: float) -> np.ndarray:
    """Normal approach speeds (m/s, > 0) towards the rod's side of the balls whose surface is within gap (m)
    of it (not yet touching: 0 <= gap_i <= gap) and that move towards it.

    The rod's surface moves with the carousel: v_rod(p) = omega z x p (omega rad/s about the bowl axis).
    Only balls with centres within z_range (m, the rod's wetted length) count.
    """
    p = np.asarray(positions, float).reshape(-1, 3)
    v = np.asarray(velocities, float).reshape(-1, 3)
    d = p[:, :2] - np.asarray(axis_xy, float)
    dist = np.linalg.norm(d, axis=1)
    clearance = dist - rod_radius - np.asarray(radii, float)
    n = d / np.maximum(dist, 1e-300)[:, None]
    v_rod = omega * np.column_stack([-p[:, 1], p[:, 0]])
    approach = -np.sum((v[:, :2] - v_rod) * n, axis=1)
    sel = (clearance >= 0) & (clearance <= gap) & (p[:, 2] >= z_range[0]) & (p[:, 2] <= z_range[1]) & (approach > 0)
    return approach[sel]


def frame_approach_speeds(run: dict, gap: float | None = None) -> np.ndarray:
    """approach_speeds() over every process-phase frame of a run (the frames stored with the snapshots);
    gap defaults to 10 % of the mean ball radius."""
    radius, speed = path_of(run)
    params = run.get("case", {}).get("attrs", {})
    rod_radius = float(params["workpiece.radius"])
    start = float(run.get("attrs", {}).get("process_start_time", math.nan))
    z_tip = float(np.asarray(run["meshes"]["rod"]["vertices"], float)[:, 2].min())
    speeds = []
    for key, frame in run.get("frames", {}).items():
        if key == "attrs" or "velocities" not in frame:
            continue
        tp = float(frame["attrs"].get("time", math.nan)) - start
        if not tp > 0:
            continue
        axis, _ = rod_pose(tp, radius, speed)
        r = np.asarray(frame["radii"], float)
        g = 0.1 * float(r.mean()) if gap is None else gap
        speeds.append(approach_speeds(frame["positions"], r, frame["velocities"], axis, speed / radius, rod_radius,
                                      (z_tip, math.inf), g))
    return np.concatenate(speeds) if speeds else np.zeros(0)


#: The four 90-degree sectors around the rod as (name, lower, upper) phi in deg, on -45..315.
SECTORS = (("front", -45.0, 45.0), ("outer side", 45.0, 135.0), ("back", 135.0, 225.0), ("inner side", 225.0, 315.0))


def sector_sums(phi: np.ndarray, values: np.ndarray) -> dict[str, float]:
    """Sum of values in the four 90-degree sectors around the rod (front, outer side, back, inner side)."""
    phi = np.mod(np.asarray(phi, float) + 45.0, 360.0) - 45.0  # -45..315
    values = np.asarray(values, float)
    return {name: float(values[(phi >= lo) & (phi < hi)].sum()) for name, lo, hi in SECTORS}


def intensity_summary(run: dict) -> dict:
    """Mesh and snapshot measures of the rod's contact intensity (see the module docstring); None entries where
    run.h5 lacks the data."""
    rod = run["meshes"]["rod"]
    snap = snapshot_facet_contacts(run)
    geo = facet_geometry(rod["vertices"], rod["faces"], snap["axis"], snap["vw"])
    out = {"geometry": geo, "snapshots": snap}
    if "contact_intensity" in rod:
        out["intensity"] = np.asarray(rod["contact_intensity"], float)
        out["count"] = np.asarray(rod.get("contact_count", np.zeros(len(geo["area"]))), float)
    return out


def intensity_text(res: dict, record_interval: float | None = None) -> str:
    """The printed summary of intensity_summary() (SI units)."""
    geo, snap = res["geometry"], res["snapshots"]
    lines = ["contact intensity on the rod (phi around the rod: 0 front = along v_w, 90 outer side, 180 back)"]
    pct = lambda sums, total: ", ".join(f"{k} {100 * v / total:.0f} %" for k, v in sums.items())  # noqa: E731
    if "intensity" in res:
        ci, kind = res["intensity"], geo["kind"]
        every = f" of {record_interval:g} s" if record_interval else ""
        lines.append(f"  mesh (from the insertion on): sum |F| dt = {ci.sum():.3f} N s over {len(ci)} facets (side "
                     f"{ci[kind == 0].sum():.3f}, tip {ci[kind == 1].sum():.3f}, top {ci[kind == 2].sum():.3f}); the "
                     f"busiest facet {ci.max():.3f} N s at phi {geo['phi'][np.argmax(ci)]:+.0f} deg; facets in contact "
                     f"in up to {res['count'].max():.0f} records{every}")
        if ci.sum() > 0:
            lines.append("  mesh by sector: " + pct(sector_sums(geo["phi"], ci), ci.sum()))
    n = len(snap["facet"])
    if n:
        lines.append(f"  snapshots: {n} rod contacts on {np.count_nonzero(snap['count'])} facets, largest contact "
                     f"normal force {snap['peak'].max():.3f} N; normal force by sector: "
                     + pct(sector_sums(snap["phi"], snap["normal_force"]), snap["normal_force"].sum()))
        if np.isfinite(snap["spacing"]):
            agree = ""
            if "intensity" in res and np.std(res["intensity"]) > 0 and np.std(snap["impulse"]) > 0:
                agree = (f" (mesh {res['intensity'].sum():.3f} N s; per facet correlation "
                         f"{np.corrcoef(res['intensity'], snap['impulse'])[0, 1]:.2f})")
            lines.append(f"  sampled normal impulse of the process, contact normal forces x {snap['spacing']:.3g} s = "
                         f"{snap['impulse'].sum():.3f} N s{agree}")
    return "\n".join(lines)
