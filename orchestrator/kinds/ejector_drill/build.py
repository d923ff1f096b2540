"""The SPH scene of an ejector-drill case (the flow-exit or the drill-head area): the walls (fixed boundary particles
with wall points inside the drill's solids, walls.py; or, with physics.walls = "penalty", the wall meshes with the
adduction holes cut into the head by manifold3d's booleans, every part cut above the scene's buffers), fluid
particles on the scene's Cartesian lattice inside the inlet's channel (the prefill) or in every region (a filled
start), the inlet, the outlets (plain, or columns standing for the passages beyond them: columns.py), the flow
planes and the sensor probes, as a drill/scene.DrillSphScene. SI units.
"""

from __future__ import annotations

import math

import numpy as np

from orchestrator.drill.regions import inlet_layers
from orchestrator.drill.scene import DrillSphScene, assemble_flow_case, filled_sites
from orchestrator.drill.walls import initial_densities, scene_lattice
from orchestrator.kinds.ejector_drill.case import EjectorDrillCase
from orchestrator.kinds.ejector_drill.columns import outlet_columns
from orchestrator.kinds.ejector_drill.layout import Layout, drill_layout
from orchestrator.kinds.ejector_drill.walls import WALL_PARTS, drill_boundary_particles
from orchestrator.kinds.sph_flow.case import SphFlowCase
from orchestrator.kinds.sph_flow.case_open import Inlet, Outlet
from orchestrator.kinds.sph_flow.case_parts import Probe
from orchestrator.kinds.sph_flow.scene import BOUNDARY, FLUID, WallMesh


def wall_meshes(case: EjectorDrillCase, layout: Layout) -> dict:
    """name -> trimesh of the walls: the head with its adduction holes cut (manifold3d), every part cut at
    layout.z_hi (the parts run on to the feed, 0.4 m away)."""
    import trimesh

    meshes = case.geometry().meshes({k: (p.file, p.scale) for k, p in case.parts.items()})
    meshes["head"] = meshes["head"].difference(meshes["adduction_holes"], engine="manifold")
    box = trimesh.creation.box(bounds=[[-layout.r_max - 1e-3, -layout.r_max - 1e-3, layout.z_lo - 1e-3],
                                       [layout.r_max + 1e-3, layout.r_max + 1e-3, layout.z_hi]])
    out = {}
    for name in WALL_PARTS:
        cut = meshes[name].intersection(box, engine="manifold")
        if len(cut.faces):
            out[name] = cut
    return out


def prefill_margin(case: EjectorDrillCase, ring) -> float:
    """Distance (m) of the prefill and the inlet's columns from the channel's walls: none with boundary particles
    (the lattice's sites in the channel are its fluid); with penalty walls the penalty's s (the walls push harder
    below it), or less where the channel is narrower than dx + 2 s (then what leaves one spacing across)."""
    if case.physics.walls == "particles":
        return 0.0
    s = case.physics.wall_penalty.s_over_dx * case.numerics.dx
    return min(s, max(0.0, 0.5 * (ring.r_out - ring.r_in - case.numerics.dx)))


def prefill_points(case: EjectorDrillCase, layout: Layout) -> np.ndarray:
    """Lattice sites (n, 3) m of the scene's lattice (walls.scene_lattice) in the inlet's channel from the inlet
    plane scene.prefill downstream, at least prefill_margin from the channel's walls."""
    dx, ring = case.numerics.dx, layout.channel
    if case.scene.prefill <= 0.0:
        return np.zeros((0, 3))
    z_top = layout.inlet.center[2]
    z_bottom = z_top - case.scene.prefill
    points = scene_lattice(layout, dx, ring.r_out + dx, z_bottom, z_top)
    r = np.hypot(points[:, 0], points[:, 1])
    gap = prefill_margin(case, ring)
    inside = (r >= ring.r_in + gap) & (r < ring.r_out - gap) if gap else ring.contains(points)
    return points[inside]


def inlet_buffer_points(case: EjectorDrillCase, layout: Layout, layers: int) -> np.ndarray:
    """The sites (n, 3) m the engine fills with the inlet's particles at the start: `layers` lattice layers upstream
    of the inlet plane across the channel (its columns are the scene lattice's, walls.lattice_offset)."""
    dx, ring = case.numerics.dx, layout.channel
    z_in = layout.inlet.center[2]
    points = scene_lattice(layout, dx, ring.r_out + dx, z_in, z_in + layers * dx)
    r = np.hypot(points[:, 0], points[:, 1])
    margin = prefill_margin(case, ring)
    return points[(r >= layout.inlet_inner_radius + margin) & (r <= ring.r_out - margin)]


def drill_outlets(case: EjectorDrillCase, layout: Layout) -> tuple:
    """The layout's outlets at their held pressures plus the scene's back pressure, pressure openings with
    scene.backflow, and with scene.columns the passages beyond them as columns (columns.py)."""
    columns = {}
    if case.scene.columns:
        net = case.network()
        columns = outlet_columns(net, case.geometry().head_length, layout.outlets,
                                 case.scene.inlet_velocity * net.annular_gap().area, case.scene.column_inertia)
    pressures = {"mouth": case.scene.mouth_pressure, "leak": case.scene.leak_pressure}
    return tuple(Outlet(name=p.name, center=p.center, normal=p.normal, radius=p.radius,
                        pressure=pressures[role] + case.scene.back_pressure, backflow=case.scene.backflow,
                        **columns.get(role, {}))
                 for role, p in layout.outlets.items())


def _flow_case(case: EjectorDrillCase, layout: Layout) -> SphFlowCase:
    """The sph_flow case the deck is written from (drill/scene.assemble_flow_case): the annular inlet across the
    channel, the outlets, the sensors that lie in the scene."""
    margin = prefill_margin(case, layout.channel)  # no inlet column inside the walls' push (as the prefill)
    inlet = Inlet(name=layout.inlet.name, center=layout.inlet.center, normal=layout.inlet.normal,
                  radius=layout.inlet.radius - margin, velocity=case.scene.inlet_velocity, profile="annular",
                  inner_radius=layout.inlet_inner_radius + margin, pressure="extrapolated",
                  ramp_time=case.scene.ramp_time, layers=inlet_layers(case.numerics.dx, case.numerics.h))
    probes = tuple(Probe(name=k, point=v) for k, v in layout.sensors.items() if layout.in_scene(v))
    return assemble_flow_case(case, layout, (inlet,), drill_outlets(case, layout), probes)


def build_drill_scene(case: EjectorDrillCase) -> DrillSphScene:
    """The scene of an ejector-drill case (see the module docstring)."""
    layout = drill_layout(case)
    flow_case = _flow_case(case, layout)
    rho0, dx = case.fluid.density, case.numerics.dx
    if case.scene.start == "filled":  # at rest everywhere, the inlet ramped (engine eq. OB4)
        points = filled_sites(layout, dx)
        velocity = np.zeros(3)
    else:
        points = prefill_points(case, layout)
        velocity = case.scene.inlet_velocity * np.asarray(layout.inlet.normal)
    n = len(points)
    velocities = np.tile(velocity, (n, 1))
    densities = np.full(n, rho0)
    kind = np.full(n, FLUID, dtype=np.int8)
    wall_point = np.full((n, 3), np.nan)
    walls, meshes = None, {}
    if case.physics.walls == "penalty":
        meshes = {name: WallMesh(name, np.ascontiguousarray(m.vertices, dtype=float),
                                 np.ascontiguousarray(m.faces, dtype=np.int64))
                  for name, m in wall_meshes(case, layout).items()}
    else:
        walls = drill_boundary_particles(case, layout, wall_meshes(case, layout) if case.parts else None)
        occupied = np.vstack([points, inlet_buffer_points(case, layout, flow_case.inlets[0].layers)])
        densities = np.concatenate([initial_densities(walls, case, layout, occupied), densities])
        points = np.vstack([walls.positions, points])
        velocities = np.vstack([np.zeros((walls.n, 3)), velocities])
        kind = np.concatenate([np.full(walls.n, BOUNDARY, dtype=np.int8), kind])
        wall_point = np.vstack([walls.wall_points, wall_point])
        n = len(points)
    ring = layout.channel
    inflow = case.scene.inlet_velocity * math.pi * (ring.r_out ** 2 - layout.inlet_inner_radius ** 2)
    return DrillSphScene(case=flow_case, positions=points, velocities=velocities,
                         masses=np.full(n, rho0 * dx ** 3), densities=densities, kind=kind,
                         block=np.zeros(n, dtype=np.int32), meshes=meshes, h=case.numerics.h, c0=case.c0,
                         timestep=case.timestep_at_rest, physics=flow_case.physics.terms,
                         material=np.zeros(n, dtype=np.int32), materials=(),
                         wall_point=None if walls is None else wall_point,
                         drill=case, layout=layout, walls=walls, inflow=inflow)
