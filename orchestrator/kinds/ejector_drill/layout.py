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

from orchestrator.drill.regions import Hole, Plane, Ring, inlet_layers, union_contains
from orchestrator.kinds.ejector_drill.head import clearance_regions, front_regions


@dataclass(frozen=True)
class Layout:
    """The scene's regions, patches, planes and sensors (see the module docstring)."""

    area: str
    regions: tuple  # Ring, Hole and head.Sector, disjoint except where a hole crosses the groove (counted once:
    # see volume)
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


def drill_layout(case) -> Layout:
    """The layout of an EjectorDrillCase's scene: the area's regions, inlet, outlets, planes and sensors
    (_flow_exit or _drill_head) with the chip mouth, the front gap and the planes both areas have."""
    g, dx, h = case.geometry(), case.numerics.dx, case.numerics.h
    n, sc = g.network, case.scene
    r_m, r_b = n.d_chip_mouth / 2, n.d_bore / 2
    mouth = Ring("chip_mouth", 0.0, r_m, 0.0, sc.mouth_depth)
    front = front_regions(case)
    part = AREAS[sc.area](case, g, mouth, front)
    # the deck lists the outlets, planes and probes in these orders
    part["outlets"] = {"mouth": Plane("mouth", (0.0, 0.0, sc.mouth_depth), (0.0, 0.0, 1.0), r_m), **part["outlets"]}
    part["planes"] = {"IB": Plane("IB", (0.0, 0.0, 0.5 * sc.mouth_depth), (0.0, 0.0, 1.0), r_m), **part["planes"],
                      "front": Plane("front", (0.0, 0.0, part.pop("z_front")), (0.0, 0.0, -1.0), r_b + 2 * h)}
    part["sensors"] = {"C1": (0.0, 0.0, g.head_length + n.tube_length - 0.02),
                       "C2": (0.0, 0.0, g.head_length + n.tube_length + n.mixing_length), **part["sensors"]}
    part["extended"]["chip_mouth"] = sc.mouth_depth + (3 * dx + 2 * h)  # an outlet's buffer (3 layers) and 2h
    extended = part.pop("extended")
    wetted = tuple(dataclasses.replace(r, z_hi=extended[r.name]) if r.name in extended else r
                   for r in part["regions"])
    # the walls reach 2h beyond the wetted regions (walls.py); the meshes are cut two layers above that
    z_hi = max(r.z_hi for r in wetted if isinstance(r, Ring)) + 2 * h + 2 * dx
    return Layout(area=sc.area, wetted=wetted, z_lo=-g.front_clearance - g.workpiece_wall, z_hi=z_hi,
                  r_max=r_b + g.workpiece_wall, **part)


def _mid_gap(n) -> float:
    """The annular gap's mid radius, m."""
    return 0.5 * (n.d_inner_tube_od / 2 + n.d_outer_tube_id / 2)


def _mid_clearance(n) -> float:
    """The head clearance's mid radius, m."""
    return 0.5 * (n.d_head_body / 2 + n.d_bore / 2)


def _flow_exit(case, g, mouth: Ring, front: tuple) -> dict:
    """The flow-exit area's own parts of the Layout (paper Fig. 2; the module docstring): the gap from its inlet,
    the collector, the holes with their planes, the head (with the pads: head.py) and tube/bore clearances with the
    leak outlet, AG and rear planes, sensors A and B; front: the front gap's regions (head.front_regions)."""
    n, sc, dx, h = g.network, case.scene, case.numerics.dx, case.numerics.h
    r_io, r_oi, r_oo = n.d_inner_tube_od / 2, n.d_outer_tube_id / 2, n.d_outer_tube_od / 2
    r_h, r_b, L, z_hole = n.d_head_body / 2, n.d_bore / 2, g.head_length, g.hole_z
    z_in = z_hole + sc.inlet_distance
    z_leak = z_in + sc.leak_margin
    channel = Ring("annular_gap", r_io, r_oi, g.groove_start, z_in)
    r_g = g.groove_outer_radius
    holes = tuple(Hole(f"hole{k}", 2 * math.pi * k / n.n_holes, z_hole, n.d_hole, r_g, r_h) for k in range(n.n_holes))
    collector = (Ring("collector", r_oi, r_g, g.groove_start, g.collector_top),) if r_g > r_oi else ()
    clearance, pad_pieces = clearance_regions(case, L)
    regions = (channel, *collector, *holes, clearance, *pad_pieces, *front, mouth,
               Ring("tube_clearance", r_oo, r_b, L, z_leak))
    z_ag = z_in - 0.5 * (z_in - L)
    # the AG disc reaches into the outer tube's wall, which holds no fluid, so that it counts the gap's particles
    # that sit slightly past the wall's surface (up to 0.5 dx with boundary particles, more with the penalty)
    # exactly as the rear disc does; the rear disc reaches 2h into the workpiece (the depth of its boundary
    # particles) for the same reason: in the filled quick run 16 of the 1,608 particles that left the control
    # volume upward over its last 0.1 ms did so at r 15.0-15.1 mm, past a disc of the bore's radius
    planes = {"AG": Plane("AG", (0.0, 0.0, z_ag), (0.0, 0.0, -1.0), 0.5 * (r_oi + r_oo)),
              "rear": Plane("rear", (0.0, 0.0, z_ag), (0.0, 0.0, 1.0), r_b + 2 * h)}
    for hole in holes:
        e = (math.cos(hole.angle), math.sin(hole.angle), 0.0)
        s = 0.5 * (r_oi + r_h)
        planes[hole.name] = Plane(hole.name, (s * e[0], s * e[1], z_hole), e, 0.5 * n.d_hole)
    between = math.pi / n.n_holes
    sensors = {"A": (_mid_clearance(n), 0.0, z_hole),
               "B": (_mid_gap(n) * math.cos(between), _mid_gap(n) * math.sin(between), z_ag)}
    buffer = 3 * dx + 2 * h  # an outlet's buffer (3 layers) and the kernel support behind it
    return dict(regions=regions, channel=channel, inlet=Plane("gap_inlet", (0.0, 0.0, z_in), (0.0, 0.0, -1.0), r_oi),
                inlet_inner_radius=r_io, outlets={"leak": Plane("leak", (0.0, 0.0, z_leak), (0.0, 0.0, 1.0), r_b)},
                planes=planes, sensors=sensors, z_front=0.5 * (sc.mouth_depth + z_hole - 0.5 * n.d_hole),
                extended={"annular_gap": z_in + (inlet_layers(dx, h) * dx + 2 * h), "tube_clearance": z_leak + buffer})


def _drill_head(case, g, mouth: Ring, front: tuple) -> dict:
    """The drill-head area's own parts of the Layout (Figs. 3-4): the head clearance from its inlet forward (split
    round the guide pads: head.py), the front gap's regions (head.front_regions), sensors A and B."""
    n, sc, dx, h = g.network, case.scene, case.numerics.dx, case.numerics.h
    r_h, r_b = n.d_head_body / 2, n.d_bore / 2
    z_in = g.hole_z - sc.inlet_distance
    channel, pad_pieces = clearance_regions(case, z_in)
    sensors = {"A": (_mid_clearance(n), 0.0, min(g.hole_z, z_in - 2 * dx)),
               "B": (_mid_gap(n), 0.0, g.head_length + 0.5 * sc.inlet_distance)}
    return dict(regions=(channel, *pad_pieces, *front, mouth), channel=channel,
                inlet=Plane("clearance_inlet", (0.0, 0.0, z_in), (0.0, 0.0, -1.0), r_b), inlet_inner_radius=r_h,
                outlets={}, planes={}, sensors=sensors, z_front=0.5 * (sc.mouth_depth + z_in),
                extended={"head_clearance": z_in + (inlet_layers(dx, h) * dx + 2 * h)})


#: The scene of each [scene] area: its own parts of the Layout.
AREAS = {"flow_exit": _flow_exit, "drill_head": _drill_head}
