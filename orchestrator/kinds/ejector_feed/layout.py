"""Where things are in the feed scene (kind ejector_feed): the ejector nozzles that divert V_EN from the annular
gap into the inner tube, with the inner tube before (C1) and behind (C2) them (paper Fig. 5). SI units (m, m^3);
drill axis z, z = 0 the head's front face, the feed at z_n = head_rear_length + tube_length (0.425 m), where the
geometry puts the nozzles (drill/geometry.DrillGeometry._nozzle_layout).

Along z (the gap flows -z toward the head, the inner tube +z toward the chip outlet):

    z_n + inlet_distance        feed inlet: annular velocity inlet across the gap (V_total), normal -z
    z_n                         the nozzle ring: n_ejector_nozzles cylinders of d_ejector_nozzle through the inner
                                tube's wall, their axes inward and nozzle_angle_deg rearward (+z) of the cross-section
    z_n + c2_distance           C2 on the axis, the disc 'mixed' across the tube (V_IB + V_EN)
    z_n + c2_distance + gap     tube outlet (disc, normal +z) holding the network's p_C2
    z_n - c1_distance           C1 on the axis, B mid-gap between two nozzles, the discs 'AG_all' and 'IB'
    z_c1 - 2h - 2dx             tube inlet: parabolic velocity inlet across the bore (V_IB), normal +z
    below its buffer            gap outlet (disc, normal -z) holding the network's gap pressure there

The gap above the outer tube's end (z > z_n) is the feed's chamber in the chuck, which the paper does not show:
modelled as the gap continued (the outer tube's bore carried on), so that the inlet is an annulus of the gap. The
network draws the nozzles from a chamber at p_feed (no cross-flow); here they draw from the gap's flow of 33 m/s,
which must turn by 120 deg into them (the jets point rearward, the gap flows forward): a loss the network's
K_p = 0.1 does not have.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from orchestrator.drill.regions import Plane, Ring, inlet_layers, union_contains


@dataclass(frozen=True)
class Nozzle:
    """A nozzle through the inner tube's wall (r_in..r_out, m): a cylinder of diameter d about the axis from
    (r_out, z) at azimuth `angle` (rad), inward and `tilt` (rad) rearward (+z) of the cross-section; the fluid is
    the part of it in the wall."""

    name: str
    angle: float
    z: float
    d: float
    tilt: float
    r_in: float
    r_out: float

    @property
    def radial(self) -> np.ndarray:
        """Unit vector radially outward at the nozzle's azimuth."""
        return np.array([math.cos(self.angle), math.sin(self.angle), 0.0])

    @property
    def axis(self) -> np.ndarray:
        """Unit vector along the nozzle, inward and rearward (the jet's direction)."""
        return -math.cos(self.tilt) * self.radial + math.sin(self.tilt) * np.array([0.0, 0.0, 1.0])

    @property
    def base(self) -> np.ndarray:
        """The axis's point on the wall's outer face (r_out, z), m."""
        return self.r_out * self.radial + np.array([0.0, 0.0, self.z])

    @property
    def length(self) -> float:
        """Axis length through the wall, (r_out - r_in) / cos(tilt), m."""
        return (self.r_out - self.r_in) / math.cos(self.tilt)

    def span(self, margin: float = 0.0) -> tuple[float, float]:
        """Axial range (s from base, m) that holds the nozzle's part in the wall: its ends are oblique, so the
        cylinder's surface meets the faces up to d/2 tan(tilt) beyond the axis's crossings; plus margin."""
        over = 0.5 * self.d * math.tan(self.tilt) + margin
        return -over, self.length + over

    def volume(self) -> float:
        """pi d^2 / 4 (r_out - r_in) / cos(tilt), m^3: an oblique cylinder between two parallel planes the wall's
        thickness apart (the faces' curvature, r = 8-9.5 mm against d/2 = 0.5 mm, changes it by < 0.5 %)."""
        return 0.25 * math.pi * self.d ** 2 * self.length

    def _local(self, points: np.ndarray):
        rel = points - self.base
        s = rel @ self.axis
        perp = rel - np.outer(s, self.axis)
        return s, perp, np.linalg.norm(perp, axis=1)

    def contains(self, points: np.ndarray) -> np.ndarray:
        """Mask of the points (n, 3) m within d/2 of the axis and in the wall (r_in <= r < r_out)."""
        r = np.hypot(points[:, 0], points[:, 1])
        s, _, dist = self._local(points)
        lo, hi = self.span(self.d)
        return (r >= self.r_in) & (r < self.r_out) & (dist < 0.5 * self.d) & (s >= lo) & (s <= hi)

    def nearest(self, points: np.ndarray) -> np.ndarray:
        """Each point's nearest point (n, 3) m of the nozzle, for the points in the wall (r_in <= r <= r_out);
        +inf rows for the others. The nearest point of the cylinder with its axis clamped to span(d/4) (end caps
        outside the wall): where it falls outside the wall, the segment to it leaves the wall through a face of the
        gap or the bore, whose own nearest point is nearer, so the minimum over the scene's regions (drill/walls.py) is
        the exact nearest wetted point. Points outside the wall are nearer to the gap's or the bore's face than to
        any point of a nozzle (which lies between them), so they need no candidate here."""
        r = np.hypot(points[:, 0], points[:, 1])
        s, perp, dist = self._local(points)
        lo, hi = self.span(0.25 * self.d)
        sc = np.clip(s, lo, hi)
        safe = np.where(dist > 0.0, dist, 1.0)[:, None]
        ring = np.where(dist[:, None] > 0.0, perp / safe, 0.0) * np.minimum(dist, 0.5 * self.d)[:, None]
        out = self.base + np.outer(sc, self.axis) + ring
        out[~((r >= self.r_in) & (r <= self.r_out))] = np.inf
        return out

    def disc(self, grow: float) -> Plane:
        """A disc across the nozzle at the middle of the wall, normal along the jet, radius d/2 + grow (m): it
        reaches into the wall around the nozzle, which holds no fluid, so that it counts the particles sitting at
        the nozzle's surface."""
        c = self.base + 0.5 * self.length * self.axis
        return Plane(self.name, tuple(float(v) for v in c), tuple(float(v) for v in self.axis), 0.5 * self.d + grow)


@dataclass(frozen=True)
class FeedLayout:
    """The feed scene's regions, open boundaries, planes and sensors (see the module docstring). Shaped like the
    drill kind's Layout where drill/walls.py and drill/probe.py read it (inlet: the feed inlet, whose columns set
    the lattice)."""

    area: str
    regions: tuple  # gap, nozzles, tube: the fluid (flow order)
    wetted: tuple  # the regions with the rings carried on through the open boundaries' buffers
    gap: Ring
    tube: Ring
    nozzles: tuple
    inlet: Plane  # the feed inlet (annular, r_io..r_oi)
    tube_inlet: Plane
    outlets: dict  # 'gap', 'tube' -> Plane
    planes: dict  # 'AG_all' (-z, over the gap and the tube), 'IB' (+z, the tube), 'mixed' (+z), 'nozzle<k>'
    sensors: dict  # 'B', 'C1', 'C2' -> point (m)
    z_nozzles: float
    z_lo: float
    z_hi: float
    r_max: float
    solids: dict  # 'outer_tube', 'inner_tube' -> Ring (the walls: the inner one less the nozzles)

    @property
    def channel(self) -> Ring:
        """The feed inlet's channel (the gap)."""
        return self.gap

    @property
    def inlet_inner_radius(self) -> float:
        """The feed inlet's inner radius (the inner tube's outside), m."""
        return self.gap.r_in

    def wetted_contains(self, points: np.ndarray) -> np.ndarray:
        """Mask of the points in any wetted region."""
        return union_contains(self.wetted, points)

    def contains(self, points: np.ndarray) -> np.ndarray:
        """Mask of the points in any fluid region."""
        return union_contains(self.regions, points)

    def in_scene(self, point) -> bool:
        """True if a point lies in one of the fluid regions."""
        return bool(self.contains(np.asarray([point], dtype=float))[0])

    def fluid_volume(self) -> float:
        """Closed-form volume of the fluid regions, m^3."""
        return sum(r.volume() for r in self.regions)


def feed_layout(case) -> FeedLayout:
    """The feed scene's layout of an EjectorFeedCase."""
    g = case.geometry()
    n = g.network
    sc, dx, h = case.scene, case.numerics.dx, case.numerics.h
    r_ii, r_io, r_oi, r_oo = n.d_inner_tube_id / 2, n.d_inner_tube_od / 2, n.d_outer_tube_id / 2, n.d_outer_tube_od / 2
    z_n = g.head_length + n.tube_length
    buffer = inlet_layers(dx, h) * dx + 2 * h  # an open boundary's buffer (the inlets' layers) and the kernel support
    z_in = z_n + sc.inlet_distance
    z_c1 = z_n - sc.c1_distance
    # the tube inlet on the lattice of the feed inlet (its layers lie a whole number of spacings apart: drill/walls.py),
    # 2h + 2dx below C1 so that C1's kernel support holds fluid only
    z_tin = z_in - dx * math.ceil((z_in - (z_c1 - 2 * h - 2 * dx)) / dx)
    z_gout = z_tin - buffer - dx  # the gap outlet's disc covers the bore too: below the tube inlet's buffer
    z_c2 = z_n + sc.c2_distance
    z_tout = z_c2 + 2 * h + 2 * dx
    gap = Ring("annular_gap", r_io, r_oi, z_gout, z_in)
    tube = Ring("inner_tube", 0.0, r_ii, z_tin, z_tout)
    tilt = math.radians(g.nozzle_angle_deg)
    nozzles = tuple(Nozzle(f"nozzle{k}", 2 * math.pi * k / n.n_ejector_nozzles, z_n, n.d_ejector_nozzle, tilt,
                           r_ii, r_io) for k in range(n.n_ejector_nozzles))
    top = max(z_in, z_tout) + buffer
    wetted = (replace(gap, z_lo=z_gout - buffer, z_hi=z_in + buffer), *nozzles,
              replace(tube, z_lo=z_tin - buffer, z_hi=z_tout + buffer))
    mid_inner_wall, mid_outer_wall = 0.5 * (r_ii + r_io), 0.5 * (r_oi + r_oo)
    # the discs midway between two lattice layers (z_in + (k + 1/2) dx): a layer lying in a disc's plane at the start
    # is counted by AG_all (-z) but not by IB (+z) when it moves off (+-1000 l/min in the first record at dx = 0.4 mm)
    z_ag, z_mixed = (z_in - dx * round((z_in - z) / dx) for z in (z_c1, z_c2))
    planes = {"AG_all": Plane("AG_all", (0.0, 0.0, z_ag), (0.0, 0.0, -1.0), mid_outer_wall),
              "IB": Plane("IB", (0.0, 0.0, z_ag), (0.0, 0.0, 1.0), mid_inner_wall),
              "mixed": Plane("mixed", (0.0, 0.0, z_mixed), (0.0, 0.0, 1.0), mid_inner_wall)}
    planes.update({z.name: z.disc(0.5 * dx) for z in nozzles})
    mid_gap, between = 0.5 * (r_io + r_oi), math.pi / n.n_ejector_nozzles
    sensors = {"B": (mid_gap * math.cos(between), mid_gap * math.sin(between), z_c1), "C1": (0.0, 0.0, z_c1),
               "C2": (0.0, 0.0, z_c2)}
    reach = 2 * h + 2 * dx  # the walls reach 2h beyond the wetted regions (drill/walls.py); two layers more
    z_lo, z_hi = z_gout - buffer - reach, top + reach
    solids = {"outer_tube": Ring("outer_tube", r_oi, r_oo, z_lo, z_in + buffer + reach),
              "inner_tube": Ring("inner_tube", r_ii, r_io, z_lo, z_hi)}
    return FeedLayout(area="feed", regions=(gap, *nozzles, tube), wetted=wetted, gap=gap, tube=tube, nozzles=nozzles,
                      inlet=Plane("feed_inlet", (0.0, 0.0, z_in), (0.0, 0.0, -1.0), r_oi),
                      tube_inlet=Plane("tube_inlet", (0.0, 0.0, z_tin), (0.0, 0.0, 1.0), r_ii),
                      outlets={"gap": Plane("gap_outlet", (0.0, 0.0, z_gout), (0.0, 0.0, -1.0), r_oi),
                               "tube": Plane("tube_outlet", (0.0, 0.0, z_tout), (0.0, 0.0, 1.0), r_ii)},
                      planes=planes, sensors=sensors, z_nozzles=z_n, z_lo=z_lo, z_hi=z_hi, r_max=r_oo + reach,
                      solids=solids)
