"""The flow around the drill head's guide pads and cutting edges in one run.h5 frame (the paper's Figs. 3-4: "no
problematic effects around the guide strips and the cutting edges"): the pressure the clearance's flow builds in
front of each pad's rear end against its dynamic pressure, the still fluid in each pad's wake against the same window
between the pads, and the still fluid along each cutting edge's faces against the whole front gap. SI units (m, Pa,
m/s); angles in rad; head.py says where the pads and edges are.
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


def _share(mask: np.ndarray) -> float:
    return float(np.mean(mask)) if len(mask) else math.nan


def pad_flow(case, frame: dict) -> dict:
    """The flow at the guide pads (NaN where no fluid is there yet): 'approach' the clearance's mean downward speed
    over the BAND_LAYERS..3 BAND_LAYERS spacings behind the pads' rear ends (m/s), 'dynamic' 1/2 rho approach^2
    (Pa); per pad (lists) 'rise' the mean pressure of the BAND_LAYERS spacings in front of its rear end less that of
    the same band between the pads (Pa), 'wake_still' the still share (|v| < STILL_SHARE v_in) of the fluid in its
    wake, the clearance's width under it from its front end down to the bore bottom, and 'open_still' that of the
    same window midway between the pads and edges (-)."""
    pads = pad_solids(case)
    dx, v_in, c = case.numerics.dx, case.scene.inlet_velocity, case.geometry().front_clearance
    x, v, p = _fluid(frame)
    r, angle, z = np.hypot(x[:, 0], x[:, 1]), np.arctan2(x[:, 1], x[:, 0]), x[:, 2]
    out = {"rise": [], "wake_still": [], "open_still": [], "approach": math.nan, "dynamic": math.nan}
    if not pads:
        return out
    r_h, r_b, top, front = pads[0].r_in, case.network().d_bore / 2, pads[0].z_hi, pads[0].z_lo
    band = BAND_LAYERS * dx
    ring = (r >= r_h) & (r < r_b)
    beside = ring & np.all([_off(angle, pd.mid_angle) > 0.5 * pd.span + band / r_h for pd in pads], axis=0)
    behind = ring & (z >= top + band) & (z < top + 3 * band)
    out["approach"] = -_mean(v[behind, 2])
    out["dynamic"] = 0.5 * case.fluid.density * out["approach"] ** 2
    front_band = ring & (z >= top) & (z < top + band)
    open_rise = _mean(p[front_band & beside])
    still = np.linalg.norm(v, axis=1) < STILL_SHARE * v_in
    wake_z = (z >= front - c) & (z < front)
    free = _open_angles(case, angle)
    for pd in pads:
        mine = _off(angle, pd.mid_angle) < 0.5 * pd.span
        out["rise"].append(_mean(p[front_band & mine]) - open_rise)
        out["wake_still"].append(_share(still[ring & wake_z & mine]))
    out["open_still"] = _share(still[ring & wake_z & free])
    return out


def _open_angles(case, angle: np.ndarray) -> np.ndarray:
    """Mask of the angles (rad) at least a pad's width from every pad and edge: the clearance's open flow."""
    keep = np.ones(len(angle), dtype=bool)
    for solid in (*pad_solids(case), *edge_solids(case)):
        keep &= _off(angle, solid.mid_angle) > 1.5 * solid.span
    return keep


def edge_flow(case, frame: dict) -> dict:
    """The flow at the cutting edges (NaN where no fluid is there yet): per edge (lists) 'jump' the mean pressure
    of the front gap's BAND_LAYERS spacings along its rake face (ahead, toward its chip mouth) less that along its
    back (Pa), 'face_still' the still share along both faces, 'mouth_speed' the mean speed in its chip mouth (m/s);
    'gap_still' the still share of the whole front gap outside the central chip mouth's rim (-)."""
    edges = edge_solids(case)
    out = {"jump": [], "face_still": [], "mouth_speed": [], "gap_still": math.nan}
    if not edges:
        return out
    dx, v_in = case.numerics.dx, case.scene.inlet_velocity
    x, v, p = _fluid(frame)
    r, angle, z = np.hypot(x[:, 0], x[:, 1]), np.arctan2(x[:, 1], x[:, 0]), x[:, 2]
    gap = (r >= edges[0].r_in) & (r < edges[0].r_out) & (z >= edges[0].z_lo) & (z < edges[0].z_hi)
    speed = np.linalg.norm(v, axis=1)
    still = speed < STILL_SHARE * v_in
    out["gap_still"] = _share(still[gap])
    band = BAND_LAYERS * dx / np.maximum(r, dx)  # the band's angle at each particle's radius
    hd = case.head
    mouth = (r >= edges[0].r_in) & (r < hd.edge_mouth_radius) & (z >= 0.0) & (z < hd.edge_mouth_depth)
    for e in edges:  # its rake face at a0 looks ahead, toward its chip mouth

        rake = gap & (np.mod(e.a0 - angle, TAU) < band)
        back = gap & (np.mod(angle - e.a0 - e.span, TAU) < band)
        out["jump"].append(_mean(p[rake]) - _mean(p[back]))
        out["face_still"].append(_share(still[rake | back]))
        ahead = np.mod(e.a0 - angle, TAU) < math.radians(hd.edge_mouth_angle)
        out["mouth_speed"].append(_mean(speed[mouth & ahead]))
    return out


def head_finding(case, frame: dict) -> str:
    """The paper's finding for Figs. 3-4 measured in one sentence on a frame: the pads' pressure rise against the
    clearance's dynamic pressure, the still fluid in their wakes and along the edges against the open flow's, and
    whether that is a dead zone (more than DEAD_MARGIN beyond the open flow's still share)."""
    t = float(frame["attrs"]["time"]) * 1e3
    pads, edges = pad_flow(case, frame), edge_flow(case, frame)
    if not pads["rise"] and not edges["jump"]:
        return f"at {t:.3g} ms: the head has no guide pads or cutting edges ([head] pad_angles, edge_angles)"
    parts = []
    dead = []
    if pads["rise"] and math.isfinite(pads["dynamic"]) and pads["dynamic"] > 0:
        rise = np.nanmean(pads["rise"])
        wake = np.nanmax(pads["wake_still"]) if np.isfinite(pads["wake_still"]).any() else math.nan
        parts.append(f"the guide pads raise the pressure before their rear ends by {rise / 1e5:.2g} bar "
                     f"({rise / pads['dynamic']:.2g} x the 1/2 rho v^2 of the clearance's {pads['approach']:.3g} m/s) "
                     f"and leave up to {wake * 100:.3g} % of their wakes' fluid still against "
                     f"{pads['open_still'] * 100:.3g} % between them")
        dead.append(wake - pads["open_still"] > DEAD_MARGIN)
    elif pads["rise"]:
        parts.append("the clearance's flow has not reached the guide pads")
    if edges["jump"] and math.isfinite(edges["gap_still"]):
        face = np.nanmax(edges["face_still"]) if np.isfinite(edges["face_still"]).any() else math.nan
        parts.append(f"the cutting edge's faces hold {face * 100:.3g} % still fluid against "
                     f"{edges['gap_still'] * 100:.3g} % in the front gap, {np.nanmean(edges['jump']) / 1e5:+.2g} bar "
                     "across the blade")
        dead.append(face - edges["gap_still"] > DEAD_MARGIN)
    verdict = ("dead zones beyond the open flow's own, which the paper does not report" if any(dead) else
               "no dead zone beyond the open flow's own (by more than "
               f"{DEAD_MARGIN * 100:g} points): the paper's 'no problematic effects around the guide strips and the "
               "cutting edges'")
    return f"at {t:.3g} ms " + "; ".join(parts) + ": " + verdict
