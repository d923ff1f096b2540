"""The SPH scene of an ejector-drill case: the walls (fixed boundary particles with wall points inside the drill's
solids, walls.py; or, with physics.walls = "penalty", the wall meshes with the adduction holes cut into the head by
manifold3d's booleans, every part cut above the scene's buffers), fluid particles on the scene's Cartesian lattice
inside the inlet's channel (the prefill), the inlet, the outlets, the flow planes and the sensor probes, as an
sph_flow SphScene so that sph_flow's adapter writes the deck (kinds/sph_flow/sph.py). SI units.

(This module is the kind's scene builder; it lives in layer 7 beside the layout because the geometry's meshes and
the sph_flow adapter's scene type are both needed.)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from orchestrator.case.common import CaseMeta
from orchestrator.kinds.ejector_drill.columns import outlet_columns
from orchestrator.kinds.ejector_drill.case import EjectorDrillCase
from orchestrator.kinds.ejector_drill.layout import Layout, drill_layout, inlet_layers
from orchestrator.kinds.sph_flow.case import SphFlowCase
from orchestrator.reference.drill_network import LITRE_PER_MIN
from orchestrator.kinds.sph_flow.case_open import Inlet, Outlet
from orchestrator.kinds.sph_flow.case_parts import Domain, Patch, Physics, Probe, SphOutput, WallPenalty
from orchestrator.kinds.ejector_drill.walls import (WALL_PARTS, WallParticles, boundary_particles, initial_densities,
                                                    scene_lattice)
from orchestrator.kinds.sph_flow.scene import BOUNDARY, FLUID, SphScene, WallMesh


@dataclass(frozen=True)
class DrillSphScene:
    """What the sph executable runs for an ejector-drill case: `flow` (an sph_flow SphScene) and its layout."""

    case: EjectorDrillCase
    flow: SphScene
    layout: Layout
    walls: WallParticles | None = None  # the boundary particles (None with penalty walls)

    @property
    def n_particles(self) -> int:
        """Particles in the input (the boundary particles and the prefill; the inlet adds more at run time)."""
        return self.flow.n_particles

    @property
    def n_fluid(self) -> int:
        """Fluid particles in the input (the prefill)."""
        return self.flow.n_fluid

    @property
    def timestep(self) -> float:
        """The CFL step at rest, s."""
        return self.flow.timestep


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


def filled_sites(layout: Layout, dx: float, buffers: bool = True) -> np.ndarray:
    """The scene lattice's sites (n, 3) m in the fluid regions, region after region in flow order (the layout lists
    them so), then (buffers) those in the outlets' buffers: the wetted regions beyond the fluid regions, except the
    inlet channel's part upstream of the inlet plane (the engine's inlet buffer)."""
    points = scene_lattice(layout, dx, layout.r_max, layout.z_lo, layout.z_hi)
    chosen, taken = [], np.zeros(len(points), dtype=bool)
    regions = list(layout.regions)
    if buffers:
        regions += [r for r in layout.wetted if r.name != layout.channel.name]
    for region in regions:
        inside = region.contains(points) & ~taken
        taken |= inside
        chosen.append(points[inside])
    return np.concatenate(chosen)


def inlet_buffer_points(case: EjectorDrillCase, layout: Layout, layers: int) -> np.ndarray:
    """The sites (n, 3) m the engine fills with the inlet's particles at the start: `layers` lattice layers upstream
    of the inlet plane across the channel (its columns are the scene lattice's, walls.lattice_offset)."""
    dx, ring = case.numerics.dx, layout.channel
    z_in = layout.inlet.center[2]
    points = scene_lattice(layout, dx, ring.r_out + dx, z_in, z_in + layers * dx)
    r = np.hypot(points[:, 0], points[:, 1])
    margin = prefill_margin(case, ring)
    return points[(r >= layout.inlet_inner_radius + margin) & (r <= ring.r_out - margin)]


def drill_physics(case: EjectorDrillCase) -> Physics:
    """The sph_flow Physics of the case's [physics] (terms, artificial viscosity, the penalty scaled with dx)."""
    dx = case.numerics.dx
    pen = case.physics.wall_penalty
    penalty = case.physics.walls == "penalty"
    terms = ["wall_penalty"] if penalty else []
    if case.physics.morris_viscosity:
        terms.insert(0, "morris_viscosity")
    if case.physics.artificial_viscosity is not None:
        terms.insert(0, "artificial_viscosity")
    return Physics(terms=tuple(terms), artificial_viscosity=case.physics.artificial_viscosity,
                   eddy_viscosity=case.physics.eddy_viscosity,
                   eddy_viscosity_walls=case.physics.eddy_viscosity_walls,
                   wall_penalty=WallPenalty(range=pen.range_over_dx * dx, s=pen.s_over_dx * dx,
                                            psi=pen.pressure * dx * dx) if penalty else None)


def _flow_case(case: EjectorDrillCase, layout: Layout) -> SphFlowCase:
    """The sph_flow case the deck is written from: its parts validated one by one (the whole is assembled with
    model_construct: its walls are the drill's meshes, which an sph_flow case file cannot name)."""
    margin = prefill_margin(case, layout.channel)  # no inlet column inside the walls' push (as the prefill)
    inlet = Inlet(name=layout.inlet.name, center=layout.inlet.center, normal=layout.inlet.normal,
                  radius=layout.inlet.radius - margin, velocity=case.scene.inlet_velocity, profile="annular",
                  inner_radius=layout.inlet_inner_radius + margin, pressure="extrapolated",
                  ramp_time=case.scene.ramp_time, layers=inlet_layers(case.numerics.dx, case.numerics.h))
    pressures = {"mouth": case.scene.mouth_pressure, "leak": case.scene.leak_pressure}
    probes = tuple(Probe(name=k, point=v) for k, v in layout.sensors.items() if layout.in_scene(v))
    return assemble_flow_case(case, layout, (inlet,), pressures, probes)


def assemble_flow_case(case, layout, inlets: tuple, pressures: dict, probes: tuple) -> SphFlowCase:
    """A drill scene's sph_flow case from its inlets, the outlets' held pressures (role -> Pa, the layout's outlets)
    and its probes: the layout's flow planes, the output intervals, the box around the layout (r_max, z_lo..z_hi),
    drill_physics. Assembled with model_construct: its walls are the drill's, which an sph_flow case cannot name."""
    columns = {}
    if case.scene.columns:
        net = case.network()
        flow = (case.scene.inlet_velocity * net.annular_gap().area if case.scene.inlet_velocity
                else case.scene.network_flow * LITRE_PER_MIN)  # m^3/s: the scene's inflow
        columns = outlet_columns(net, case.geometry().head_length, layout.outlets, flow, case.scene.column_inertia)
    back = case.scene.back_pressure
    outlets = tuple(Outlet(name=p.name, center=p.center, normal=p.normal, radius=p.radius,
                           pressure=pressures[role] + back, backflow=case.scene.backflow, **columns.get(role, {}))
                    for role, p in layout.outlets.items())
    planes = tuple(Patch(name=p.name, center=p.center, normal=p.normal, radius=p.radius)
                   for p in layout.planes.values())
    output = SphOutput(frame_interval=case.output.frame_interval, series_interval=case.output.series_interval,
                       probes=probes, flow_planes=planes)
    r = layout.r_max
    domain = Domain(dimension=3, lo=(-r, -r, layout.z_lo), hi=(r, r, layout.z_hi))
    meta = CaseMeta.model_construct(kind="sph_flow", name=case.case.name, description=case.case.description,
                                    engine="sph", seed=0)
    return SphFlowCase.model_construct(case=meta, domain=domain, fluid=case.scene_fluid(), materials=(),
                                       physics=drill_physics(case), blocks=(), walls=(), inlets=inlets,
                                       outlets=outlets, numerics=case.numerics, simulation=case.simulation,
                                       output=output, expected=())


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
        walls = boundary_particles(case, layout, wall_meshes(case, layout) if case.parts else None)
        occupied = np.vstack([points, inlet_buffer_points(case, layout, flow_case.inlets[0].layers)])
        densities = np.concatenate([initial_densities(walls, case, layout, occupied), densities])
        points = np.vstack([walls.positions, points])
        velocities = np.vstack([np.zeros((walls.n, 3)), velocities])
        kind = np.concatenate([np.full(walls.n, BOUNDARY, dtype=np.int8), kind])
        wall_point = np.vstack([walls.wall_points, wall_point])
        n = len(points)
    flow = SphScene(case=flow_case, positions=points, velocities=velocities,
                    masses=np.full(n, rho0 * dx ** 3), densities=densities, kind=kind,
                    block=np.zeros(n, dtype=np.int32), meshes=meshes, h=case.numerics.h, c0=case.c0,
                    timestep=case.timestep_at_rest, physics=flow_case.physics.terms,
                    material=np.zeros(n, dtype=np.int32), materials=(),
                    wall_point=None if walls is None else wall_point)
    return DrillSphScene(case=case, flow=flow, layout=layout, walls=walls)
