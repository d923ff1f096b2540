"""Where things are in an ejector-drill SPH scene: the fluid regions (solids of revolution and the holes, with their
closed-form volumes), the inlet and outlets, the flow planes that measure V_AG, V_IB, V_loss and the holes' flow,
and the sensor points of Fig. 5 (A, B, C1, C2). SI units (m, m^3); drill axis z, z = 0 the head's front face.

flow_exit (paper Fig. 2): the annular gap from the inlet plane down to the groove, the adduction holes, the
clearance between head body and bore (forward to the head face, rearward into the tube/bore clearance), the front
gap before the head face and the chip mouth up to its outlet; the tube/bore clearance ends in the leak outlet.
drill_head (Figs. 3-4): the head clearance from the inlet plane forward, the front gap and the chip mouth.
The feed (ejector nozzles, C1, C2, V_EN) is 0.4 m away from either scene and is not in it.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np


def union_contains(regions, points: np.ndarray) -> np.ndarray:
    """Mask of the points (n, 3) m inside any of the regions (each with a contains(points) mask)."""
    mask = np.zeros(len(points), dtype=bool)
    for region in regions:
        mask |= region.contains(points)
    return mask


@dataclass(frozen=True)
class Ring:
    """Fluid between radii r_in and r_out for z_lo <= z <= z_hi, m."""

    name: str
    r_in: float
    r_out: float
    z_lo: float
    z_hi: float

    def volume(self) -> float:
        """pi (r_out^2 - r_in^2) (z_hi - z_lo), m^3."""
        return math.pi * (self.r_out ** 2 - self.r_in ** 2) * (self.z_hi - self.z_lo)

    def contains(self, points: np.ndarray) -> np.ndarray:
        """Mask of the points (n, 3) m inside."""
        r = np.hypot(points[:, 0], points[:, 1])
        return (r >= self.r_in) & (r < self.r_out) & (points[:, 2] >= self.z_lo) & (points[:, 2] < self.z_hi)


@dataclass(frozen=True)
class Hole:
    """A radial hole of diameter d at angle `angle` (rad) and height z, from r_in to r_out, m."""

    name: str
    angle: float
    z: float
    d: float
    r_in: float
    r_out: float

    def volume(self) -> float:
        """pi d^2 / 4 (r_out - r_in), m^3 (the straight cylinder between the two radii)."""
        return 0.25 * math.pi * self.d ** 2 * (self.r_out - self.r_in)

    def contains(self, points: np.ndarray) -> np.ndarray:
        """Mask of the points within the cylinder along the hole's axis from r_in less the sagitta (d/2)^2 / (2 r_in)
        to r_out: the hole is drilled through the wall of radius r_in, so its rim there lies up to the sagitta
        below r_in along the axis (the overlap with the region inside r_in is that region's already)."""
        e = np.array([math.cos(self.angle), math.sin(self.angle), 0.0])
        s = points @ e
        off = points - np.outer(s, e) - np.array([0.0, 0.0, self.z])
        start = self.r_in - 0.125 * self.d ** 2 / self.r_in
        return (s >= start) & (s < self.r_out) & (np.linalg.norm(off, axis=1) < 0.5 * self.d)


@dataclass(frozen=True)
class Plane:
    """A disc patch: centre (m), normal (the direction counted positive), radius (m)."""

    name: str
    center: tuple[float, float, float]
    normal: tuple[float, float, float]
    radius: float


@dataclass(frozen=True)
class Layout:
    """The scene's regions, patches, planes and sensors (see the module docstring)."""

    area: str
    regions: tuple  # Ring and Hole, disjoint except where a hole crosses the groove (counted once: see volume)
    wetted: tuple  # the regions with the inlet's channel and the outlets' rings carried on through their buffers:
    # where fluid (and inlet and outlet particles) can be, which the boundary particles surround (walls.py)
    channel: Ring  # the inlet's channel (prefilled from the inlet plane downstream)
    inlet: Plane
    inlet_inner_radius: float
    outlets: dict  # role ('mouth', 'leak') -> Plane
    planes: dict  # role -> Plane: 'AG' (-z in the gap), 'rear' (+z over the bore at the AG plane), 'IB' (+z in
    # the mouth), 'front' (-z over the bore ahead of the holes), 'hole<k>' (radially out)
    sensors: dict  # 'A', 'B', 'C1', 'C2' -> point (m)
    z_lo: float
    z_hi: float  # the walls are cut here (above every buffer)
    r_max: float

    def wetted_contains(self, points: np.ndarray) -> np.ndarray:
        """Mask of the points in any wetted region (the fluid regions and the open boundaries' buffers)."""
        return union_contains(self.wetted, points)

    def in_scene(self, point) -> bool:
        """True if a sensor point lies in one of the scene's fluid regions."""
        return bool(any(r.contains(np.asarray([point], dtype=float))[0] for r in self.regions))

    def fluid_volume(self) -> float:
        """Closed-form volume of the fluid regions, m^3 (the holes counted from the groove's outer wall)."""
        return sum(r.volume() for r in self.regions)

    def contains(self, points: np.ndarray) -> np.ndarray:
        """Mask of the points in any fluid region."""
        return union_contains(self.regions, points)


def inlet_layers(dx: float, h: float, skin: float = 0.1) -> int:
    """Buffer layers of a drill scene's inlet: 3, or more where the particles the inlet adds (`layers` dx behind
    its plane) would lie within the Verlet list's range 2h (1 + skin) of it (h = 1.5 dx: 4). Beyond it with dx/4
    to spare, the engine lets them wait for the next list build (engines/sph open_boundaries.h) instead of
    rebuilding the list for each one (dx, h in m; skin: the engine's neighbour_skin, a fraction of 2h)."""
    return max(3, math.ceil(2.0 * h * (1.0 + skin) / dx + 0.25))


def drill_layout(case) -> Layout:
    """The layout of an EjectorDrillCase's scene."""
    g = case.geometry()
    n = g.network
    sc, dx, h = case.scene, case.numerics.dx, case.numerics.h
    r_m, r_ii, r_io = n.d_chip_mouth / 2, n.d_inner_tube_id / 2, n.d_inner_tube_od / 2
    r_oi, r_oo, r_h, r_b = n.d_outer_tube_id / 2, n.d_outer_tube_od / 2, n.d_head_body / 2, n.d_bore / 2
    L, z_g, z_hole, c = g.head_length, g.groove_start, g.hole_z, g.front_clearance
    buffer = 3 * dx + 2 * h  # an outlet's buffer (3 layers) and the kernel support behind it
    in_buffer = inlet_layers(dx, h) * dx + 2 * h  # the inlet's
    mouth = Ring("chip_mouth", 0.0, r_m, 0.0, sc.mouth_depth)
    front = Ring("front_gap", 0.0, r_b, -c, 0.0)
    mid_gap, mid_clear = 0.5 * (r_io + r_oi), 0.5 * (r_h + r_b)
    outlets = {"mouth": Plane("mouth", (0.0, 0.0, sc.mouth_depth), (0.0, 0.0, 1.0), r_m)}
    planes = {"IB": Plane("IB", (0.0, 0.0, 0.5 * sc.mouth_depth), (0.0, 0.0, 1.0), r_m)}
    sensors = {"C1": (0.0, 0.0, L + n.tube_length - 0.02), "C2": (0.0, 0.0, L + n.tube_length + n.mixing_length)}
    if sc.area == "flow_exit":
        z_in = z_hole + sc.inlet_distance
        z_leak = z_in + sc.leak_margin
        channel = Ring("annular_gap", r_io, r_oi, z_g, z_in)
        r_g = g.groove_outer_radius
        holes = tuple(Hole(f"hole{k}", 2 * math.pi * k / n.n_holes, z_hole, n.d_hole, r_g, r_h)
                      for k in range(n.n_holes))
        collector = (Ring("collector", r_oi, r_g, z_g, g.collector_top),) if r_g > r_oi else ()
        regions = (channel, *collector, *holes, Ring("head_clearance", r_h, r_b, 0.0, L), front, mouth,
                   Ring("tube_clearance", r_oo, r_b, L, z_leak))
        inlet = Plane("gap_inlet", (0.0, 0.0, z_in), (0.0, 0.0, -1.0), r_oi)
        inner = r_io
        outlets["leak"] = Plane("leak", (0.0, 0.0, z_leak), (0.0, 0.0, 1.0), r_b)
        z_ag = z_in - 0.5 * (z_in - L)
        # the AG disc reaches into the outer tube's wall, which holds no fluid, so that it counts the gap's particles
        # that sit slightly past the wall's surface (up to 0.5 dx with boundary particles, more with the penalty)
        # exactly as the rear disc does; the rear disc reaches 2h into the workpiece (the depth of its boundary
        # particles) for the same reason: in the filled quick run 16 of the 1,608 particles that left the control
        # volume upward over its last 0.1 ms did so at r 15.0-15.1 mm, past a disc of the bore's radius
        planes["AG"] = Plane("AG", (0.0, 0.0, z_ag), (0.0, 0.0, -1.0), 0.5 * (r_oi + r_oo))
        planes["rear"] = Plane("rear", (0.0, 0.0, z_ag), (0.0, 0.0, 1.0), r_b + 2 * h)
        for hole in holes:
            e = (math.cos(hole.angle), math.sin(hole.angle), 0.0)
            s = 0.5 * (r_oi + r_h)
            planes[hole.name] = Plane(hole.name, (s * e[0], s * e[1], z_hole), e, 0.5 * n.d_hole)
        sensors["A"] = (mid_clear, 0.0, z_hole)
        sensors["B"] = (mid_gap * math.cos(math.pi / n.n_holes), mid_gap * math.sin(math.pi / n.n_holes), z_ag)
        z_front = 0.5 * (sc.mouth_depth + z_hole - 0.5 * n.d_hole)
        extended = {"annular_gap": z_in + in_buffer, "chip_mouth": sc.mouth_depth + buffer,
                    "tube_clearance": z_leak + buffer}
    else:
        z_in = z_hole - sc.inlet_distance
        channel = Ring("head_clearance", r_h, r_b, 0.0, z_in)
        regions = (channel, front, mouth)
        inlet = Plane("clearance_inlet", (0.0, 0.0, z_in), (0.0, 0.0, -1.0), r_b)
        inner = r_h
        sensors["A"] = (mid_clear, 0.0, min(z_hole, z_in - 2 * dx))
        sensors["B"] = (mid_gap, 0.0, L + 0.5 * sc.inlet_distance)
        z_front = 0.5 * (sc.mouth_depth + z_in)
        extended = {"head_clearance": z_in + in_buffer, "chip_mouth": sc.mouth_depth + buffer}
    planes["front"] = Plane("front", (0.0, 0.0, z_front), (0.0, 0.0, -1.0), r_b + 2 * h)  # into the wall, as 'rear'
    wetted = tuple(dataclasses.replace(r, z_hi=extended[r.name]) if r.name in extended else r for r in regions)
    # the walls reach 2h beyond the wetted regions (walls.py); the meshes are cut two layers above that
    z_hi = max(r.z_hi for r in wetted if isinstance(r, Ring)) + 2 * h + 2 * dx
    return Layout(area=sc.area, regions=regions, wetted=wetted, channel=channel, inlet=inlet, inlet_inner_radius=inner,
                  outlets=outlets, planes=planes, sensors=sensors, z_lo=-c - g.workpiece_wall, z_hi=z_hi,
                  r_max=r_b + g.workpiece_wall)
