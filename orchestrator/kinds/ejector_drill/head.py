"""The drill head's guide pads and cutting edges ([head]): the pads as solid blocks in the head clearance, from the
head body out to the bore (or to pad_height), the cutting edges as solid blades across the front gap from the chip
mouth's rim to the bore, each with its own chip mouth, a pocket cut into the head's face in front of the edge that
opens into the central chip mouth. Each is an annular sector (Sector): the clearance and the front gap are split into
the fluid sectors between them, each with its closed-form volume, membership and nearest point, so the walls' wall
points (drill/walls.wall_points) lie on the pads' and the edges' faces. SI units (m, rad inside, degrees in the
case); drill axis z, z = 0 the head's face, angles counter-clockwise seen from +z, the main cutting edge at 0.

The tool turns clockwise seen from +z (not modelled: drill/case.py): a pad at +84 degrees lies 84 degrees behind
the edge, and the edge's chip mouth lies ahead of it, at negative angles.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from orchestrator.drill.regions import Ring

TAU = 2.0 * math.pi


@dataclass(frozen=True)
class Sector:
    """Fluid or solid between radii r_in and r_out, z_lo <= z < z_hi and the angles a0 .. a0 + span (rad), m."""

    name: str
    r_in: float
    r_out: float
    z_lo: float
    z_hi: float
    a0: float
    span: float

    @property
    def mid_angle(self) -> float:
        """The sector's middle angle, rad."""
        return self.a0 + 0.5 * self.span

    def volume(self) -> float:
        """span / 2 (r_out^2 - r_in^2) (z_hi - z_lo), m^3."""
        return 0.5 * self.span * (self.r_out ** 2 - self.r_in ** 2) * (self.z_hi - self.z_lo)

    def angle_in(self, points: np.ndarray) -> np.ndarray:
        """Mask of the points (n, 3) m whose angle lies within the sector's span."""
        return np.mod(np.arctan2(points[:, 1], points[:, 0]) - self.a0, TAU) < self.span

    def contains(self, points: np.ndarray) -> np.ndarray:
        """Mask of the points (n, 3) m inside."""
        r = np.hypot(points[:, 0], points[:, 1])
        return (self.angle_in(points) & (r >= self.r_in) & (r < self.r_out) & (points[:, 2] >= self.z_lo)
                & (points[:, 2] < self.z_hi))

    def nearest(self, points: np.ndarray) -> np.ndarray:
        """Each point's nearest point (n, 3) m of the sector: within its span the (r, z) clamp at the point's angle,
        outside it the clamp of the point's projection on the nearer side face (a half-plane through the axis)."""
        r = np.hypot(points[:, 0], points[:, 1])
        zc = np.clip(points[:, 2], self.z_lo, self.z_hi)
        safe = np.where(r > 0.0, r, 1.0)
        cos, sin = np.where(r > 0.0, points[:, 0] / safe, 1.0), np.where(r > 0.0, points[:, 1] / safe, 0.0)
        out = np.column_stack([np.clip(r, self.r_in, self.r_out) * cos, np.clip(r, self.r_in, self.r_out) * sin, zc])
        past = np.mod(np.arctan2(points[:, 1], points[:, 0]) - self.a0, TAU) - self.span  # beyond a0 + span
        outside = past > 0.0
        to_end = past < 0.5 * (TAU - self.span)  # nearer the face at a0 + span than the one at a0
        for face, rows in ((self.a0 + self.span, outside & to_end), (self.a0, outside & ~to_end)):
            e = np.array([math.cos(face), math.sin(face)])
            s = np.clip(points[rows, :2] @ e, self.r_in, self.r_out)
            out[rows, 0], out[rows, 1] = s * e[0], s * e[1]
        return out


def _half_angle(width: float, radius: float) -> float:
    """Half the angle (rad) an arc of `width` (m) spans at `radius` (m)."""
    return 0.5 * width / radius


def pad_spans(head, r_b: float) -> list[tuple[float, float]]:
    """(centre, half angle) rad of each guide pad, its width taken as the arc at the bore radius r_b (m)."""
    return [(math.radians(a), _half_angle(head.pad_width, r_b)) for a in head.pad_angles]


def edge_spans(head, r_b: float) -> list[tuple[float, float]]:
    """(centre, half angle) rad of each cutting edge's blade, its width taken as the arc at the bore radius r_b (m)."""
    return [(math.radians(a), _half_angle(head.edge_width, r_b)) for a in head.edge_angles]


def _between(name: str, spans, r_in, r_out, z_lo, z_hi) -> tuple[Sector, ...]:
    """The fluid sectors between the solid angular spans [(centre, half)] (sorted round the axis)."""
    ordered = sorted(((c - h) % TAU, 2 * h) for c, h in spans)
    out = []
    for k, (a0, span) in enumerate(ordered):
        start = a0 + span
        nxt = ordered[(k + 1) % len(ordered)][0] + (TAU if k + 1 == len(ordered) else 0.0)
        out.append(Sector(f"{name}{k}", r_in, r_out, z_lo, z_hi, start, nxt - start))
    return tuple(out)


def pad_solids(case) -> tuple[Sector, ...]:
    """The guide pads as solid sectors: from the head body (d_head_body / 2) out by pad_height (None: to the bore),
    from pad_offset behind the face rearward over pad_length, m."""
    n, hd = case.network(), case.head
    r_h, r_b = n.d_head_body / 2, n.d_bore / 2
    top = r_b if hd.pad_height is None else r_h + hd.pad_height
    return tuple(Sector(f"pad{k}", r_h, top, hd.pad_offset, hd.pad_offset + hd.pad_length, c - h, 2 * h)
                 for k, (c, h) in enumerate(pad_spans(hd, r_b)))


def edge_solids(case) -> tuple[Sector, ...]:
    """The cutting edges' blades as solid sectors across the front gap (z = -front_clearance .. 0), from the chip
    mouth's rim (d_chip_mouth / 2) to the bore, m."""
    n, g = case.network(), case.geometry()
    r_m, r_b = n.d_chip_mouth / 2, n.d_bore / 2
    return tuple(Sector(f"edge{k}", r_m, r_b, -g.front_clearance, 0.0, c - h, 2 * h)
                 for k, (c, h) in enumerate(edge_spans(case.head, r_b)))


def edge_mouths(case) -> tuple[Sector, ...]:
    """Each cutting edge's chip mouth: a fluid pocket in the head's face ahead of the edge's rake face (negative
    angles), from the central chip mouth's rim out to edge_mouth_radius and edge_mouth_depth deep, m."""
    n, hd = case.network(), case.head
    span = math.radians(hd.edge_mouth_angle)
    return tuple(Sector(f"edge_mouth{k}", n.d_chip_mouth / 2, hd.edge_mouth_radius, 0.0, hd.edge_mouth_depth,
                        c - h - span, span) for k, (c, h) in enumerate(edge_spans(hd, n.d_bore / 2)))


def clearance_regions(case, z_top: float) -> tuple[Ring, tuple]:
    """(the head clearance's top ring from the pads' rear ends to z_top, named 'head_clearance', the inlet's channel
    in the drill-head scene; the fluid pieces below it: the sectors between the pads, over a pad lower than the
    clearance, and the ring between the face and the pads), m. Without pads the top ring is the whole clearance."""
    n, hd = case.network(), case.head
    r_h, r_b = n.d_head_body / 2, n.d_bore / 2
    pads = pad_solids(case)
    if not pads:
        return Ring("head_clearance", r_h, r_b, 0.0, z_top), ()
    z_lo, z_hi = hd.pad_offset, hd.pad_offset + hd.pad_length
    pieces = _between("pad_gap", pad_spans(hd, r_b), r_h, r_b, z_lo, z_hi)
    if pads[0].r_out < r_b:
        pieces += tuple(Sector(f"over_pad{k}", p.r_out, r_b, z_lo, z_hi, p.a0, p.span) for k, p in enumerate(pads))
    if z_lo > 0.0:
        pieces += (Ring("pad_front", r_h, r_b, 0.0, z_lo),)
    return Ring("head_clearance", r_h, r_b, z_hi, z_top), pieces


def front_regions(case) -> tuple:
    """The front gap ahead of the face (z = -front_clearance .. 0): the whole disc without cutting edges; with them
    the disc inside the chip mouth's rim and the sectors between the blades, then the edges' chip mouths, m."""
    n, g = case.network(), case.geometry()
    r_m, r_b, c = n.d_chip_mouth / 2, n.d_bore / 2, g.front_clearance
    if not case.head.edge_angles:
        return (Ring("front_gap", 0.0, r_b, -c, 0.0),)
    return (Ring("front_gap", 0.0, r_m, -c, 0.0), *_between("front_sector", edge_spans(case.head, r_b), r_m, r_b,
                                                            -c, 0.0), *edge_mouths(case))


def _overlaps(spans, angles, key: str, what: str) -> None:
    """ValueError naming head.<key> and two of its `angles` (degrees) when their angular spans [(centre, half)] rad
    overlap."""
    for i, (a, ha) in enumerate(spans):
        for j, (b, hb) in enumerate(spans[i + 1:], start=i + 1):
            gap = abs((a - b + math.pi) % TAU - math.pi)
            if gap < ha + hb:
                raise ValueError(f"head.{key} = {angles[i]:g} and {angles[j]:g} degrees: the {what} overlap "
                                 f"({math.degrees(gap):.3g} degrees apart, {math.degrees(ha + hb):.3g} needed)")


def check_head(case, z_end: float, end: str) -> None:
    """ValueError naming the [head] key whose pad or edge does not fit: a pad higher than the head clearance, or
    leaving a gap to the bore thinner than a lattice spacing, narrower than a spacing at the head body, reaching
    z_end (m; `end` says what is there), overlapping another; a blade or chip mouth overlapping another, a blade
    thinner than a spacing at the mouth's rim, a chip mouth outside the head or past the mouth's flow plane IB."""
    n, hd, dx = case.network(), case.head, case.numerics.dx
    r_m, r_h, r_b = n.d_chip_mouth / 2, n.d_head_body / 2, n.d_bore / 2
    if (hd.pad_angles or hd.edge_angles) and case.physics.walls != "particles":
        raise ValueError("head.pad_angles, head.edge_angles: the pads and cutting edges are boundary particles; they "
                         "need physics.walls = 'particles'")
    if hd.pad_angles:
        clearance = r_b - r_h
        if hd.pad_height is not None:
            if hd.pad_height > clearance * (1 + 1e-9):
                raise ValueError(f"head.pad_height = {hd.pad_height * 1e3:g} mm does not fit in the head clearance "
                                 f"(d_bore - d_head_body) / 2 = {clearance * 1e3:g} mm")
            if 0.0 < clearance - hd.pad_height < dx * (1 - 1e-9):
                over = (clearance - hd.pad_height) * 1e3
                raise ValueError(f"head.pad_height = {hd.pad_height * 1e3:g} mm leaves {over:.3g} mm over the pad, "
                                 f"less than numerics.dx = {dx * 1e3:g} mm; allowed: the clearance "
                                 f"({clearance * 1e3:g} mm, bearing on the bore) or <= {(clearance - dx) * 1e3:.4g} mm")
        if hd.pad_width * r_h / r_b < dx * (1 - 1e-9):
            raise ValueError(f"head.pad_width = {hd.pad_width * 1e3:g} mm is narrower than numerics.dx = {dx * 1e3:g} "
                             "mm at the head body")
        if hd.pad_offset + hd.pad_length > z_end:
            raise ValueError(f"head.pad_length = {hd.pad_length * 1e3:g} mm from head.pad_offset = "
                             f"{hd.pad_offset * 1e3:g} mm reaches past {end} at {z_end * 1e3:.4g} mm behind the face")
        _overlaps(pad_spans(hd, r_b), hd.pad_angles, "pad_angles", "guide pads")
    if hd.edge_angles:
        if hd.edge_width * r_m / r_b < dx * (1 - 1e-9):
            raise ValueError(f"head.edge_width = {hd.edge_width * 1e3:g} mm at the bore is "
                             f"{hd.edge_width * r_m / r_b * 1e3:.3g} mm at the chip mouth's rim, less than "
                             f"numerics.dx = {dx * 1e3:g} mm")
        spans = edge_spans(hd, r_b)
        mouth = math.radians(hd.edge_mouth_angle)
        _overlaps([(c - 0.5 * mouth, h + 0.5 * mouth) for c, h in spans], hd.edge_angles, "edge_angles",
                  "cutting edges with their chip mouths")
        if not r_m + dx <= hd.edge_mouth_radius <= r_h - 2 * dx:
            raise ValueError(f"head.edge_mouth_radius = {hd.edge_mouth_radius * 1e3:g} mm must lie between the chip "
                             f"mouth's rim + dx ({(r_m + dx) * 1e3:.4g} mm) and the head body - 2 dx "
                             f"({(r_h - 2 * dx) * 1e3:.4g} mm)")
        ib = 0.5 * case.scene.mouth_depth
        if hd.edge_mouth_depth > ib:
            raise ValueError(f"head.edge_mouth_depth = {hd.edge_mouth_depth * 1e3:g} mm reaches past the chip mouth's "
                             f"flow plane IB at scene.mouth_depth / 2 = {ib * 1e3:g} mm")
