"""Normal impact speeds of the balls on the rod at contact start (Uhlmann et al. 2015: "number, type and intensity
of contacts"), recorded by both engines in output.impact_window (s of process time).

The prism test (Yade's script, every step; the reader for LIGGGHTS's rows): the generated rod is a regular prism
of ``segments`` sides about its axis with a flat tip, so the gap g (m) between a ball (centre p, radius r) and the
rod is the larger of the side gap, (p - axis) . n_k - a - r with n_k the outward normal of the side nearest in
angle and a the apothem, and the tip gap z_tip - z - r (exact where the ball faces a side or the tip, a slight
underestimate near an edge). u = -dg/dt is the normal approach speed relative to the rod surface, which moves
with the carousel: v_rod(p) = omega e_z x p. Yade records a contact start at the step where g <= 0 < g + u dt: it
overlaps now and did not one step earlier (to first order), with the ball's id, radius, position and velocity and
its g and u at that step.

LIGGGHTS takes its own contact detection instead (the deck's fixes and thresholds, no per-ball formula): a ball
starts a wall contact at the step where the force its wall fix stores is non-zero and was zero the step before;
it writes the ball's id, radius, position and velocity (LIGGGHTS_COLUMNS). The reader keeps the starts that
overlap the rod (the others are on the bowl: a ball cannot touch both, liggghts_deck checks the clearance) and
approach it (a zero force does not always mean no contact: a separating contact's normal force is held at zero by
limitForce, and then its friction too, so such a contact can seem to start again), and gives each the prism
test's u as its engine speed. The two tests differ at an edge or the tip's rim, where the prism test's gap falls
short of the mesh's (it counts a ball as touching before it does), and where the step's own contact force has
already slowed the ball so that g + u dt <= 0 (docs/drag_finishing.md compares them start by start).

What is kept in run.h5 (/events, one row per contact start; the same names for both engines): time and
process_time (s), ball (index), position (n,3) m and velocity (n,3) m/s at the step, facet (index of the rod
face nearest to the ball, the mesh as stored in /meshes/rod, i.e. the rod's final pose), gap (m, the overlap
from the mesh's own faces, < 0 when overlapping) and impact_speed (m/s): the relative velocity -(v - v_rod) . n
along the contact normal n from the facet's nearest point to the ball's centre (the facet's outward normal on a
face; from the edge at an edge, where the engine's prism test uses a face normal), recomputed here from the mesh
rather than taken from the engine (engine_speed keeps the prism test's u). A contact is detected within one step of
its start, so the speed has changed by at most the force of an overlap u dt acting for dt (about 2 % at E/1000,
0.02 m/s). Per face, /meshes/rod gets impact_count and impact_speed_mean, impact_speed_max (m/s; 0 where no impact).
"""

from __future__ import annotations

import math

import numpy as np

from orchestrator.engines.base import Series
from orchestrator.errors import OrchestratorError
from orchestrator.kinds.drag_finishing.chains import path_of
from orchestrator.kinds.drag_finishing.intensity import point_triangle_distance, sector_sums, turn_z
from orchestrator.reference.dem_geometry import closest_points_on_triangles

#: The columns the engines write for each contact start (SI units): Yade's with its prism test's g and u,
#: LIGGGHTS's without.
ENGINE_COLUMNS = ("id", "radius", "x", "y", "z", "vx", "vy", "vz", "gap", "speed")
LIGGGHTS_COLUMNS = ENGINE_COLUMNS[:-2]
#: A wall contact start is on the rod when the ball's gap to the rod mesh is below this, m: it overlaps (the
#: stored mesh's six digits move the gap by up to about 0.05 um); a ball on the bowl is farther (liggghts_deck).
ROD_GAP = 1e-6
#: How far from exact the rod mesh stored in run.h5 (six digits, from LIGGGHTS's VTK) is a prism (rod_prism).
STORED_TOL = 1e-4


def rod_prism(vertices: np.ndarray, faces: np.ndarray, tol: float = 1e-9) -> dict:
    """The generated rod as the engines test it: segments, alpha0 (rad, the direction of the first side's outward
    normal from the axis), apothem (m) and the axis (x, y) of the mesh as given. ValueError when the mesh is not a
    regular prism about a vertical axis to tol (of a unit normal; 1e-4 for a mesh stored to 6 digits)."""
    tri = np.asarray(vertices, float)[np.asarray(faces, int)]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    side = np.abs(normal[:, 2]) < tol
    v = np.asarray(vertices, float)
    axis = 0.5 * (v[:, :2].min(axis=0) + v[:, :2].max(axis=0))
    raw = np.mod(np.arctan2(normal[side, 1], normal[side, 0]), 2 * math.pi)
    ordered = np.sort(raw)
    angles = ordered[np.r_[True, np.diff(ordered) > 10 * tol]]  # one per side, within tol of each other
    if len(angles) > 1 and angles[-1] > 2 * math.pi - 10 * tol + angles[0]:  # the same side either side of 0
        angles = angles[:-1]
    segments = len(angles)
    if segments < 3 or not np.allclose(np.diff(angles), 2 * math.pi / segments, atol=100 * tol):
        raise ValueError("the rod mesh is not a regular vertical prism: impacts cannot be tested by its faces")
    sector = 2 * math.pi / segments
    alpha0 = float(angles[0] + np.mean(np.mod(raw - angles[0] + 0.5 * sector, sector) - 0.5 * sector))
    centre = tri[side].mean(axis=1)[:, :2] - axis
    apothem = float(np.mean(np.einsum("ij,ij->i", centre, normal[side, :2])))
    return {"segments": segments, "alpha0": alpha0, "apothem": apothem, "axis": axis}


def prism_speed(position: np.ndarray, velocity: np.ndarray, radius: np.ndarray, prism: dict,
                tip_z: float) -> np.ndarray:
    """The prism test's approach speed u (m/s, see the module docstring) of balls at position (n,3) m with
    velocity (n,3) m/s relative to the rod surface and radius (n,) m, against the rod prism (rod_prism of the mesh
    in the same pose) with its tip at tip_z (m)."""
    sector = 2 * math.pi / prism["segments"]
    d = position[:, :2] - prism["axis"]
    angle = prism["alpha0"] + sector * np.floor((np.arctan2(d[:, 1], d[:, 0]) - prism["alpha0"]) / sector + 0.5)
    normal = np.column_stack([np.cos(angle), np.sin(angle)])
    side_gap = np.einsum("ij,ij->i", d, normal) - prism["apothem"] - radius
    tip_gap = tip_z - position[:, 2] - radius
    side_speed = -np.einsum("ij,ij->i", velocity[:, :2], normal)
    return np.where(side_gap > tip_gap, side_speed, velocity[:, 2])


def template_values(scene) -> dict:
    """What the engine templates need for the impact test (SI units): impact_window (start, end) in s of process
    time or None, and the rod prism about its own axis (segments, alpha0 rad, apothem m). OrchestratorError when
    the window is set and the rod is not a regular vertical prism (a user's mesh)."""
    window = scene.case.impact_window
    if window is None:
        return {"impact_window": None}
    rod = scene.meshes["rod"].mesh
    try:
        prism = rod_prism(rod.vertices, rod.faces)
    except ValueError:
        raise OrchestratorError(
            f"output.impact_window is set but the rod (workpiece.mesh = {scene.case.workpiece.mesh}) is not a regular "
            "prism about a vertical axis, the shape the engines test contact starts against; allowed: remove "
            "output.impact_window, or a rod mesh that is such a prism") from None
    return {"impact_window": (float(window[0]), float(window[1])), "impact_segments": prism["segments"],
            "impact_alpha0": repr(prism["alpha0"]), "impact_apothem": repr(prism["apothem"]),
            "impact_sector": repr(2 * math.pi / prism["segments"])}


def _in_stored_pose(raw: dict[str, np.ndarray], tri: np.ndarray, omega: float, stored_time: float):
    """Positions and velocities relative to the rod surface turned to the rod's stored pose (n,3), the nearest
    facet (n,) and the gap to it minus the radius (n,) m (see impact_events)."""
    t = np.asarray(raw["time"], float)
    p = np.asarray(raw["position"], float).reshape(-1, 3)
    v = np.asarray(raw["velocity"], float).reshape(-1, 3)
    w = v - omega * np.column_stack([-p[:, 1], p[:, 0], np.zeros(len(p))])  # relative to the rod surface
    turn = omega * (stored_time - t)
    p_s, w_s = turn_z(p, turn), turn_z(w, turn)
    facet = np.zeros(len(p), dtype=np.int64)
    gap = np.zeros(len(p))
    for lo in range(0, len(p), 2000):  # (n, faces) distances in blocks
        d = point_triangle_distance(p_s[lo:lo + 2000], tri)
        facet[lo:lo + 2000] = np.argmin(d, axis=1)
        gap[lo:lo + 2000] = d[np.arange(len(d)), facet[lo:lo + 2000]]
    return p_s, w_s, facet, gap - np.asarray(raw["radius"], float)


def rod_starts(raw: dict[str, np.ndarray], rod_vertices: np.ndarray, rod_faces: np.ndarray, omega: float,
               stored_time: float) -> dict[str, np.ndarray]:
    """LIGGGHTS's wall contact starts (raw as impact_events, without engine_speed) reduced to those on the rod
    (gap to the mesh below ROD_GAP), in order of time, with the prism test's u as
    engine_speed (m/s)."""
    tri = np.asarray(rod_vertices, float)[np.asarray(rod_faces, int)]
    p_s, w_s, _, gap = _in_stored_pose(raw, tri, omega, stored_time)
    radius = np.asarray(raw["radius"], float)
    keep = np.flatnonzero(gap < ROD_GAP)
    keep = keep[np.argsort(np.asarray(raw["time"], float)[keep], kind="stable")]
    prism = rod_prism(rod_vertices, rod_faces, tol=STORED_TOL)
    speed = prism_speed(p_s[keep], w_s[keep], radius[keep], prism, float(np.min(np.asarray(rod_vertices)[:, 2])))
    return {**{k: np.asarray(val)[keep] for k, val in raw.items()}, "engine_speed": speed}


def impact_events(raw: dict[str, np.ndarray], rod_vertices: np.ndarray, rod_faces: np.ndarray, omega: float,
                  process_start: float, stored_time: float) -> dict[str, Series]:
    """The /events of a drag-finishing run from the engine's rows (see the module docstring).

    raw: time (n,) s, ball (n,) index, radius (n,) m, position (n,3) m, velocity (n,3) m/s, engine_speed (n,)
    m/s. rod_vertices, rod_faces: the rod mesh in the pose it had at stored_time (s); omega: the carousel's
    angular velocity, rad/s; process_start: s.
    """
    t = np.asarray(raw["time"], float)
    p = np.asarray(raw["position"], float).reshape(-1, 3)
    v = np.asarray(raw["velocity"], float).reshape(-1, 3)
    tri = np.asarray(rod_vertices, float)[np.asarray(rod_faces, int)]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    p_s, w_s, facet, gap = _in_stored_pose(raw, tri, omega, stored_time)
    # the contact normal: from the nearest point of the facet to the centre (the facet's normal on its face, the
    # direction from the edge or corner where the ball meets one)
    chosen = tri[facet]
    q, _ = closest_points_on_triangles(p_s, chosen[:, 0], chosen[:, 1], chosen[:, 2])
    n = p_s - q
    length = np.linalg.norm(n, axis=1)
    n = np.where(length[:, None] > 1e-12, n / np.maximum(length, 1e-300)[:, None], normal[facet])
    speed = -np.einsum("ij,ij->i", w_s, n) if len(p) else np.zeros(0)
    return {
        "time": Series(t, "s", "step of the contact start"),
        "process_time": Series(t - process_start, "s", "time since the rod started moving"),
        "ball": Series(np.asarray(raw["ball"], np.int64), "-", "index of the ball"),
        "position": Series(p, "m", "ball centre at the contact start"),
        "velocity": Series(v, "m/s", "ball velocity at the contact start"),
        "facet": Series(facet, "-", "rod face nearest to the ball (/meshes/rod, its stored pose)"),
        "gap": Series(gap, "m", "distance to that face minus the ball radius (< 0: overlapping)"),
        "impact_speed": Series(speed, "m/s", "normal speed towards the face, relative to the moving rod"),
        "engine_speed": Series(np.asarray(raw["engine_speed"], float), "m/s", "the prism test's speed u"),
    }


def facet_impacts(facet: np.ndarray, speed: np.ndarray, n_faces: int) -> dict[str, np.ndarray]:
    """Per rod face: impact_count, impact_speed_mean and impact_speed_max (m/s, 0 where none)."""
    facet = np.asarray(facet, np.int64)
    speed = np.asarray(speed, float)
    count = np.bincount(facet, minlength=n_faces)
    total = np.bincount(facet, speed, minlength=n_faces)
    peak = np.zeros(n_faces)
    np.maximum.at(peak, facet, speed)
    return {"impact_count": count, "impact_speed_mean": total / np.maximum(count, 1), "impact_speed_max": peak}


def attach_impacts(result, raw: dict[str, np.ndarray], omega: float, stored_time: float) -> None:
    """Put the events of raw (see impact_events; without engine_speed: LIGGGHTS's wall contact starts, see
    rod_starts) into result.events and the per-face measures into result.meshes['rod'] (which holds the rod in its
    pose at stored_time, s)."""
    rod = result.meshes["rod"]
    start = float(result.attrs.get("process_start_time", math.nan))
    wall_starts = "engine_speed" not in raw
    if wall_starts:
        raw = rod_starts(raw, rod["vertices"], rod["faces"], omega, stored_time)
    events = impact_events(raw, rod["vertices"], rod["faces"], omega, start, stored_time)
    if wall_starts:  # a start that does not approach is a contact whose force had vanished for a step
        keep = events["impact_speed"].values > 0
        events = {name: Series(s.values[keep], s.units, s.description) for name, s in events.items()}
    result.events = events
    rod.update(facet_impacts(events["facet"].values, events["impact_speed"].values, len(rod["faces"])))


def impact_rows(rows: np.ndarray, columns=ENGINE_COLUMNS) -> dict[str, np.ndarray]:
    """Engine rows (n, len(columns)) as the raw dict of impact_events (without time; without engine_speed when
    the columns have no speed)."""
    col = {name: rows[:, k] for k, name in enumerate(columns)}
    raw = {"ball": col["id"].astype(np.int64), "radius": col["radius"],
           "position": np.column_stack([col["x"], col["y"], col["z"]]),
           "velocity": np.column_stack([col["vx"], col["vy"], col["vz"]])}
    return {**raw, "engine_speed": col["speed"]} if "speed" in col else raw


def impact_summary(run: dict) -> dict | None:
    """The contact starts of a run (its /events) around the rod, or None when it recorded none: speed (m/s), phi
    (deg around the rod at the event's time: 0 front along v_w, 90 outer side), z (m), tip (True where the ball
    met the tip cap), window (start, end) s of process, engine_speed (m/s)."""
    ev = run.get("events", {})
    if "impact_speed" not in ev:
        return None
    radius, speed = path_of(run)
    params = run.get("case", {}).get("attrs", {})
    tp = np.asarray(ev["process_time"], float)
    window = np.asarray(params.get("output.impact_window", [tp.min(initial=0.0), tp.max(initial=0.0)]), float)
    window[1] = min(window[1], float(params.get("process.duration", window[1])))  # cut to the process, as the run
    theta = speed / radius * tp
    axis = radius * np.column_stack([np.cos(theta), np.sin(theta)])
    d = np.asarray(ev["position"], float).reshape(-1, 3)[:, :2] - axis
    # phi as rod_angle() for each event's own pose: along v_w = (-sin, cos), outward = (cos, sin)
    phi = np.degrees(np.arctan2(d[:, 0] * np.cos(theta) + d[:, 1] * np.sin(theta),
                                -d[:, 0] * np.sin(theta) + d[:, 1] * np.cos(theta)))
    rod = run["meshes"]["rod"]
    tri = np.asarray(rod["vertices"], float)[np.asarray(rod["faces"], int)]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    nz = cross[:, 2] / np.maximum(np.linalg.norm(cross, axis=1), 1e-300)
    facet = np.asarray(ev["facet"], np.int64)
    return {"speed": np.asarray(ev["impact_speed"], float), "phi": phi,
            "z": np.asarray(ev["position"], float).reshape(-1, 3)[:, 2], "tip": nz[facet] < -0.9,
            "window": (float(window[0]), float(window[1])), "engine_speed": np.asarray(ev["engine_speed"], float)}


def impact_text(res: dict | None) -> str:
    """The printed summary of impact_summary() (SI units, speeds in mm/s)."""
    if res is None:
        return ("rod impacts: not recorded (set output.impact_window = [start, end] s of process to record every "
                "ball's first touch of the rod with its normal impact speed)")
    sp, (t0, t1) = res["speed"], res["window"]
    head = (f"rod impacts (contact starts, tested every step from {t0:g} to {t1:g} s of process): {len(sp)}, "
            f"{len(sp) / max(t1 - t0, 1e-300):.1f} per s")
    if not len(sp):
        return head
    shares = sector_sums(res["phi"], np.ones(len(sp)))
    return "\n".join([
        head + f" ({int(res['tip'].sum())} on the tip cap)",
        f"  normal impact speed relative to the rod surface: median {1e3 * np.median(sp):.2f} mm/s, 90th percentile "
        f"{1e3 * np.percentile(sp, 90):.2f} mm/s, max {1e3 * sp.max():.2f} mm/s",
        "  impacts by sector: " + ", ".join(f"{k} {100 * v / len(sp):.0f} %" for k, v in shares.items()),
        f"  the engine's prism test and the stored mesh's contact normal agree on the speed to 1e-6 m/s for "
        f"{100 * np.mean(np.abs(res['engine_speed'] - sp) <= 1e-6):.1f} % of the contacts (the others meet an edge, "
        "where the test takes a face normal)"])
