"""A drill scene as the sph executable runs it: an sph_flow SphScene (its `case` the sph_flow case the deck is
written from, so that sph_flow's adapter writes the deck, the particles and the meshes) that also carries the drill
case it was built from, its layout (where things are), its boundary particles and its inflow. The parts every drill
scene has are built here: the physics terms, the sph_flow case around a kind's inlets, outlets and probes, and the
lattice sites of the fluid regions. SI units."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from orchestrator.case.common import CaseMeta
from orchestrator.drill.walls import WallParticles, scene_lattice
from orchestrator.kinds.sph_flow.case import SphFlowCase
from orchestrator.kinds.sph_flow.case_parts import Domain, Patch, Physics, WallPenalty
from orchestrator.kinds.sph_flow.case_run import SphOutput
from orchestrator.kinds.sph_flow.scene import SphScene


@dataclass(frozen=True, kw_only=True)
class DrillSphScene(SphScene):
    """An SphScene with the drill case it was built from (`drill`), its layout (`layout`: regions, inlet, outlets,
    planes, sensors, box), its boundary particles (`walls`, None with penalty walls) and the volume flow its inlets
    add to the fluid (`inflow`, m^3/s; 0 for a scene that starts filled and moving: what flows in, flows out)."""

    drill: Any
    layout: Any
    walls: WallParticles | None = None
    inflow: float = 0.0


def drill_physics(case) -> Physics:
    """The sph_flow Physics of a drill case's [physics] (terms, artificial viscosity, the penalty scaled with dx)."""
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
                   density_diffusion=case.physics.density_diffusion,
                   wall_penalty=WallPenalty(range=pen.range_over_dx * dx, s=pen.s_over_dx * dx,
                                            psi=pen.pressure * dx * dx) if penalty else None)


def assemble_flow_case(case, layout, inlets: tuple, outlets: tuple, probes: tuple) -> SphFlowCase:
    """A drill scene's sph_flow case from its inlets, outlets and probes (sph_flow's Inlet, Outlet, Probe): the
    layout's flow planes, the output intervals, the box around the layout (r_max, z_lo..z_hi), the fluid the scene
    runs with (case.scene_fluid()) and drill_physics. Assembled with model_construct, its parts validated one by one:
    its walls are the drill's, which an sph_flow case file cannot name."""
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


def filled_sites(layout, dx: float, buffers: bool = True) -> np.ndarray:
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
