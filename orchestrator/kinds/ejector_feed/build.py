"""The feed scene's SPH input (layout.py says where things are): the boundary particles (walls.py), the fluid regions
filled on the scene's lattice (drill/probe.probe_scene, the filling the timing probe uses), the two velocity inlets
(the gap's V_total, the tube's V_IB) and the two outlets holding the network's pressures (network.py), the flow
discs and the sensors B, C1, C2, as a drill/scene.DrillSphScene. SI units.

The start: every region filled. The inlets enter at full speed from the first step (the engine has no ramp yet),
so the fluid starts moving as they push it, with no split: the gap with V_total all the way down (-z), the tube
with V_IB (+z), each with its inlet's profile (start_velocities), the nozzles at rest; each particle at the density
of the network's pressure of its region (the gap outlet's in the gap, the tube outlet's in the tube, linear in r
through the nozzles). Starting at rest would send a water hammer rho c0 v_gap = 330 bar down the gap at c0 =
1000 m/s and through the nozzles; the start above leaves the nozzles to accelerate under the pressure difference
the network puts across them, so the split V_EN / V_AG is the SPH's own, not the start's.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from orchestrator.drill.probe import probe_scene
from orchestrator.drill.regions import inlet_layers
from orchestrator.drill.scene import DrillSphScene, assemble_flow_case
from orchestrator.drill.walls import scene_lattice
from orchestrator.kinds.ejector_feed.layout import FeedLayout, feed_layout
from orchestrator.kinds.ejector_feed.network import FeedBoundary, feed_boundary
from orchestrator.kinds.ejector_feed.walls import feed_boundary_particles
from orchestrator.kinds.sph_flow.case import SphFlowCase
from orchestrator.kinds.sph_flow.case_open import Inlet, Outlet
from orchestrator.kinds.sph_flow.case_parts import Probe
from orchestrator.kinds.sph_flow.scene import BOUNDARY, FLUID
from orchestrator.reference import sph_flows


def feed_flow_case(case, layout: FeedLayout, boundary: FeedBoundary) -> SphFlowCase:
    """The sph_flow case of the feed scene's deck: the annular feed inlet (the laminar annulus profile) and the
    tube's parabolic inlet, both with the extrapolated buffer pressure; the outlets at the network's pressures."""
    gap, tube = layout.gap, layout.tube
    layers = inlet_layers(case.numerics.dx, case.numerics.h)
    inlets = (Inlet(name=layout.inlet.name, center=layout.inlet.center, normal=layout.inlet.normal, radius=gap.r_out,
                    velocity=boundary.gap_speed, profile="annular", inner_radius=gap.r_in, pressure="extrapolated",
                    layers=layers),
              Inlet(name=layout.tube_inlet.name, center=layout.tube_inlet.center, normal=layout.tube_inlet.normal,
                    radius=tube.r_out, velocity=boundary.tube_speed, profile="parabolic", pressure="extrapolated",
                    layers=layers))
    pressures = {"gap": boundary.gap_outlet_pressure, "tube": boundary.tube_outlet_pressure}
    outlets = tuple(Outlet(name=p.name, center=p.center, normal=p.normal, radius=p.radius, pressure=pressures[role],
                           backflow=case.scene.backflow) for role, p in layout.outlets.items())
    probes = tuple(Probe(name=k, point=v) for k, v in layout.sensors.items())
    return assemble_flow_case(case, layout, inlets, outlets, probes)


def start_pressure(layout: FeedLayout, boundary: FeedBoundary, points: np.ndarray) -> np.ndarray:
    """Gauge pressure (Pa) at t = 0 of particles at points (n, 3) m (boundary particles: their wall points): the
    tube outlet's inside the bore (r <= r_ii), the gap outlet's from the inner tube's outside on (r >= r_io), linear
    in r through the nozzles."""
    r = np.hypot(points[:, 0], points[:, 1])
    share = np.clip((r - layout.tube.r_out) / (layout.gap.r_in - layout.tube.r_out), 0.0, 1.0)
    return boundary.tube_outlet_pressure + share * (boundary.gap_outlet_pressure - boundary.tube_outlet_pressure)


def tait_density(case, pressure: np.ndarray) -> np.ndarray:
    """Density (kg/m^3) of the gauge pressure (Pa), eq. 6 inverted:
    rho0 ((p - p_B) gamma / (rho0 c0^2) + 1)^(1/gamma)."""
    f = case.fluid
    return sph_flows.tait_density(pressure, f.density, case.c0, f.gamma, f.background_pressure)


def annulus_shape(r: np.ndarray, r_in: float, r_out: float) -> np.ndarray:
    """The laminar annulus profile's shape R^2 - r^2 + (R^2 - Ri^2) ln(r/R) / ln(R/Ri), m^2 (the engine's inlet
    profile OB3, engines/sph/src/open_boundaries.h; 0 outside)."""
    r = np.clip(r, r_in, r_out)
    return np.maximum(r_out ** 2 - r ** 2 + (r_out ** 2 - r_in ** 2) * np.log(r / r_out) / np.log(r_out / r_in), 0.0)


def pipe_shape(r: np.ndarray, radius: float) -> np.ndarray:
    """Hagen-Poiseuille's shape 1 - r^2 / R^2 (the engine's parabolic disc profile OB1; 0 outside), -."""
    return np.maximum(1.0 - (r / radius) ** 2, 0.0)


def start_velocities(case, layout: FeedLayout, boundary: FeedBoundary, points: np.ndarray) -> np.ndarray:
    """Velocities (n, 3) m/s at t = 0 of fluid at points (n, 3) m: the inlets' own profiles carried through their
    rings (-z in the gap with the annulus profile of mean gap_speed, +z in the tube with the pipe's of mean
    tube_speed: a plug start met the annular inlet's 1.5 x peak with a hammer rho c0 dv ~ 160 bar), the nozzles at
    rest (the module docstring says why). Each profile is scaled as the engine scales its inlet: the lattice columns
    of its ring carry the mean speed times the ring's area."""
    dx = case.numerics.dx
    z0 = layout.inlet.center[2] - 0.5 * dx  # a layer of the scene's lattice
    columns = scene_lattice(layout, dx, layout.gap.r_out + dx, z0 - 0.5 * dx, z0 + 0.5 * dx)
    rc = np.hypot(columns[:, 0], columns[:, 1])
    gap, tube = layout.gap, layout.tube
    in_gap = (rc >= gap.r_in) & (rc <= gap.r_out)
    gap_scale = boundary.gap_speed * math.pi * (gap.r_out ** 2 - gap.r_in ** 2) / (
        annulus_shape(rc[in_gap], gap.r_in, gap.r_out).sum() * dx * dx)
    tube_scale = boundary.tube_speed * math.pi * tube.r_out ** 2 / (pipe_shape(rc[rc <= tube.r_out], tube.r_out).sum()
                                                                    * dx * dx)
    r = np.hypot(points[:, 0], points[:, 1])
    v = np.zeros_like(points)
    mask = gap.contains(points)
    v[mask, 2] = -gap_scale * annulus_shape(r[mask], gap.r_in, gap.r_out)
    mask = tube.contains(points)
    v[mask, 2] = tube_scale * pipe_shape(r[mask], tube.r_out)
    return v


def build_feed_scene(case) -> DrillSphScene:
    """The feed scene of an EjectorFeedCase (see the module docstring)."""
    layout = feed_layout(case)
    boundary = feed_boundary(case, layout.z_nozzles - layout.outlets["gap"].center[2])
    flow_case = feed_flow_case(case, layout, boundary)
    walls = feed_boundary_particles(case, layout)
    rho0, dx, n = case.fluid.density, case.numerics.dx, walls.n
    only_walls = DrillSphScene(case=flow_case, positions=walls.positions, velocities=np.zeros((n, 3)),
                               masses=np.full(n, rho0 * dx ** 3), densities=np.full(n, rho0),
                               kind=np.full(n, BOUNDARY, dtype=np.int8), block=np.zeros(n, dtype=np.int32),
                               meshes={}, h=case.numerics.h, c0=case.c0, timestep=case.timestep_at_rest,
                               physics=flow_case.physics.terms, material=np.zeros(n, dtype=np.int32), materials=(),
                               wall_point=walls.wall_points, drill=case, layout=layout, walls=walls)
    filled = probe_scene(only_walls, limit=2 ** 62)
    fluid = filled.kind == FLUID
    at = np.where(fluid[:, None], filled.positions, filled.wall_point)
    velocities = np.where(fluid[:, None], start_velocities(case, layout, boundary, filled.positions), 0.0)
    return dataclasses.replace(filled, velocities=velocities,
                               densities=tait_density(case, start_pressure(layout, boundary, at)))
