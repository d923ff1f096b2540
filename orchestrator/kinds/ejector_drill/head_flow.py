"""The flow around the drill head's guide pads and cutting edges in one run.h5 frame (the paper's Figs. 3-4: "no
problematic effects around the guide strips and the cutting edges"): the pressure the clearance's flow builds in
front of each pad's rear end against its dynamic pressure, the speed past the pads, the dead share (the volume
without moving fluid: empty, or slower than STILL_SHARE v_in) of each pad's lee against the same window away from the
pads, and that along each cutting edge's faces against the whole front gap. SI units (m, Pa, m/s); angles in rad;
head.py says where the pads and edges are.
"""

from __future__ import annotations

import math

import numpy as np

from orchestrator.kinds.ejector_drill.flows import STILL_SHARE
from orchestrator.kinds.ejector_drill.head import TAU, edge_solids, pad_solids

#: Layers (lattice spacings) of the band in front of a pad's rear end and along an edge's faces.
BAND_LAYERS = 2.0
#: A still zone beyond the open flow's own by more than this share (of the window's particles) is a dead zone.
DEAD_MARGIN = 0.10


def _off(angles: np.ndarray, centre: float) -> np.ndarray:
    """|angle - centre| wrapped to [0, pi], rad."""
    return np.abs(np.mod(angles - centre + math.pi, TAU) - math.pi)


def _fluid(frame: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(positions (n, 3) m, velocities (n, 3) m/s, pressures (n,) Pa) of the frame's fluid particles."""
    fluid = np.asarray(frame["kind"]) == 0
    return (np.asarray(frame["positions"], dtype=float)[fluid], np.asarray(frame["velocities"], dtype=float)[fluid],
            np.asarray(frame["pressures"], dtype=float)[fluid])


def _mean(values: np.ndarray) -> float:
    return float(np.mean(values)) if len(values) else math.nan


def dead_share(n_moving: int, dx: float, volume: float) -> float:
    """The share (-) of a window of `volume` (m^3) that holds no moving fluid: 1 less the n_moving particles' lattice
    volume dx^3 each (m), at least 0; NaN for an empty window volume."""
    return max(0.0, 1.0 - n_moving * dx ** 3 / volume) if volume > 0 else math.nan


def _open_angles(case, angle: np.ndarray) -> np.ndarray:
    """Mask of the angles (rad) at least a pad's width from every pad and edge: the clearance's open flow."""
    keep = np.ones(len(angle), dtype=bool)
    for solid in (*pad_solids(case), *edge_solids(case)):
        keep &= _off(angle, solid.mid_angle) > 1.5 * solid.span
    return keep


def pad_flow(case, frame: dict) -> dict:
    """The flow at the guide pads: 'approach' the clearance's mean downward speed over the BAND_LAYERS..3
    BAND_LAYERS spacings behind the pads' rear ends (m/s), 'dynamic' 1/2 rho approach^2 (Pa); per pad (lists)
    'rise' the mean pressure of the BAND_LAYERS spacings in front of its rear end less that of the same band beside
    the pads (Pa), 'past' the mean speed within a pad's width beside it over its middle half (m/s), 'wake_dead' the
    dead share (dead_share: empty, or slower than STILL_SHARE v_in) of its wake, the clearance's width under it from
    its front end down to the bore bottom; 'open_dead' that of the same window away from the pads and edges (-).
    NaN where no fluid is there yet."""
    pads = pad_solids(case)
    dx, v_in, c = case.numerics.dx, case.scene.inlet_velocity, case.geometry().front_clearance
    x, v, p = _fluid(frame)
    r, angle, z = np.hypot(x[:, 0], x[:, 1]), np.arctan2(x[:, 1], x[:, 0]), x[:, 2]
    out = {"rise": [], "past": [], "wake_dead": [], "open_dead": math.nan, "approach": math.nan, "dynamic": math.nan}
    if not pads:
        return out
    r_h, r_b, top, front = pads[0].r_in, case.network().d_bore / 2, pads[0].z_hi, pads[0].z_lo
    band, length = BAND_LAYERS * dx, top - front
    ring = (r >= r_h) & (r < r_b)
    beside = ring & np.all([_off(angle, pd.mid_angle) > 0.5 * pd.span + band / r_h for pd in pads], axis=0)
    behind = ring & (z >= top + band) & (z < top + 3 * band)
    out["approach"] = -_mean(v[behind, 2])
    out["dynamic"] = 0.5 * case.fluid.density * out["approach"] ** 2
    front_band = ring & (z >= top) & (z < top + band)
    open_rise = _mean(p[front_band & beside])
    speed = np.linalg.norm(v, axis=1)
    moving = ring & (z >= front - c) & (z < front) & (speed >= STILL_SHARE * v_in)
    middle = ring & (z >= front + 0.25 * length) & (z < top - 0.25 * length)
    for pd in pads:
        off = _off(angle, pd.mid_angle)
        out["rise"].append(_mean(p[front_band & (off < 0.5 * pd.span)]) - open_rise)
        out["past"].append(_mean(speed[middle & (off >= 0.5 * pd.span) & (off < 1.5 * pd.span)]))
        window = 0.5 * pd.span * (r_b ** 2 - r_h ** 2) * c
        out["wake_dead"].append(dead_share(int(np.sum(moving & (off < 0.5 * pd.span))), dx, window))
    grid = np.linspace(-math.pi, math.pi, 3600, endpoint=False)
    free_angle = TAU * float(np.mean(_open_angles(case, grid)))
    out["open_dead"] = dead_share(int(np.sum(moving & _open_angles(case, angle))), dx,
                                  0.5 * free_angle * (r_b ** 2 - r_h ** 2) * c)
    return out


def edge_flow(case, frame: dict) -> dict:
    """The flow at the cutting edges: per edge (lists) 'jump' the mean pressure of the front gap's BAND_LAYERS
    spacings along its rake face (ahead, toward its chip mouth) less that along its back (Pa), 'face_dead' the dead
    share (dead_share) of those two bands, 'mouth_speed' the mean speed in its chip mouth (m/s); 'gap_dead' that of
    the whole front gap between the central chip mouth's rim and the bore (-). NaN where no fluid is there yet."""
    edges = edge_solids(case)
    out = {"jump": [], "face_dead": [], "mouth_speed": [], "gap_dead": math.nan}
    if not edges:
        return out
    dx, v_in, hd = case.numerics.dx, case.scene.inlet_velocity, case.head
    x, v, p = _fluid(frame)
    r, angle, z = np.hypot(x[:, 0], x[:, 1]), np.arctan2(x[:, 1], x[:, 0]), x[:, 2]
    e0 = edges[0]
    gap = (r >= e0.r_in) & (r < e0.r_out) & (z >= e0.z_lo) & (z < e0.z_hi)
    speed = np.linalg.norm(v, axis=1)
    moving = speed >= STILL_SHARE * v_in
    height = e0.z_hi - e0.z_lo
    gap_volume = math.pi * (e0.r_out ** 2 - e0.r_in ** 2) * height - sum(e.volume() for e in edges)
    out["gap_dead"] = dead_share(int(np.sum(gap & moving)), dx, gap_volume)
    band = BAND_LAYERS * dx / np.maximum(r, dx)  # the band's angle at each particle's radius: 2 spacings of arc
    mouth = (r >= e0.r_in) & (r < hd.edge_mouth_radius) & (z >= 0.0) & (z < hd.edge_mouth_depth)
    for e in edges:  # its rake face at a0 looks ahead, toward its chip mouth
        rake = gap & (np.mod(e.a0 - angle, TAU) < band)
        back = gap & (np.mod(angle - e.a0 - e.span, TAU) < band)
        out["jump"].append(_mean(p[rake]) - _mean(p[back]))
        faces = 2 * BAND_LAYERS * dx * (e.r_out - e.r_in) * height
        out["face_dead"].append(dead_share(int(np.sum((rake | back) & moving)), dx, faces))
        ahead = np.mod(e.a0 - angle, TAU) < math.radians(hd.edge_mouth_angle)
        out["mouth_speed"].append(_mean(speed[mouth & ahead]))
    return out


def _worst(values: list) -> float:
    """The largest finite value of a list, NaN when none is."""
    finite = [v for v in values if math.isfinite(v)]
    return max(finite) if finite else math.nan


def head_finding(case, frame: dict) -> str:
    """The paper's finding for Figs. 3-4 measured in one sentence on a frame: the pads' pressure rise against the
    clearance's dynamic pressure, the speed past them, the dead share of their lee and along the edge's faces against
    the open flow's, and whether that is a dead zone (more than DEAD_MARGIN beyond the open flow's dead share)."""
    t = float(frame["attrs"]["time"]) * 1e3
    pads, edges = pad_flow(case, frame), edge_flow(case, frame)
    if not pads["rise"] and not edges["jump"]:
        return f"at {t:.3g} ms: the head has no guide pads or cutting edges ([head] pad_angles, edge_angles)"
    parts, dead = [], []
    rise = float(np.nanmean(pads["rise"])) if np.isfinite(pads["rise"]).any() else math.nan
    if math.isfinite(rise) and pads["dynamic"] > 0:
        wake = _worst(pads["wake_dead"])
        parts.append(f"the guide pads raise the pressure before their rear ends by {rise / 1e5:.2g} bar "
                     f"({rise / pads['dynamic']:.2g} x the 1/2 rho v^2 of the clearance's {pads['approach']:.3g} m/s), "
                     f"the flow passes them at {np.nanmean(pads['past']):.3g} m/s, and their lee in the front gap "
                     f"holds no moving fluid on up to {wake * 100:.3g} % of its volume against "
                     f"{pads['open_dead'] * 100:.3g} % away from them")
        dead.append(wake - pads["open_dead"] > DEAD_MARGIN)
    elif pads["rise"]:
        parts.append("the clearance's flow has not reached the guide pads")
    face = _worst(edges["face_dead"])
    if edges["jump"] and math.isfinite(face):
        parts.append(f"along the cutting edge's faces {face * 100:.3g} % against {edges['gap_dead'] * 100:.3g} % "
                     f"of the whole front gap, {np.nanmean(edges['jump']) / 1e5:+.2g} bar across the blade")
        dead.append(face - edges["gap_dead"] > DEAD_MARGIN)
    verdict = ("a dead zone beyond the open flow's own (by more than "
               f"{DEAD_MARGIN * 100:g} points), which the paper does not report" if any(dead) else
               f"no dead zone beyond the open flow's own by more than {DEAD_MARGIN * 100:g} points, as the paper "
               "finds ('no problematic effects around the guide strips and the cutting edges')")
    return f"at {t:.3g} ms " + "; ".join(parts) + ": " + verdict
