"""The scratch's scene: the target box as an SPH case of kind sph_flow (one johnson_cook material on a cubic
lattice, its top face at z = 0, on `held_layers` layers of fixed particles) and the grain as a free rigid impactor
(engines/sph/README.md, "Rigid impactors"): a central sphere of radius R = D / (2 (1 + c)) and four corner spheres of
radius c R centred on its surface at the corners of a tetrahedron, one corner leading, forward and down. The
grain starts a quarter dx above the top particles' extent, placed so that its lowest point, carried along the
velocity, meets the top face at x = target.entry from the -x face. SI units."""

from __future__ import annotations

import math

import numpy as np

from orchestrator.kinds.scratch.case import ScratchCase
from orchestrator.kinds.sph_flow.case import SphFlowCase
from orchestrator.kinds.sph_flow.case_impact import impact_case
from orchestrator.kinds.sph_flow.case_impactors import mass_properties
from orchestrator.kinds.sph_flow.scene import SphScene, build_sph_flow

#: The gap between the grain's lowest point and the top particles' extent at the start, in dx.
START_GAP = 0.25


def direction(case: ScratchCase) -> np.ndarray:
    """The unit vector of the grain's velocity: along +x and down, at grain.angle from the surface."""
    a = math.radians(case.grain.angle)
    return np.array([math.cos(a), 0.0, -math.sin(a)])


def leading(case: ScratchCase) -> np.ndarray:
    """The unit vector from the grain's centre to its leading corner: forward and down, halfway between the
    velocity and -z, so that the corner is the grain's lowest point and cuts first."""
    a = math.radians(0.5 * (case.grain.angle + 90.0))
    return np.array([math.cos(a), 0.0, -math.sin(a)])


def clump(case: ScratchCase) -> np.ndarray:
    """(5, 4) x, y, z, r (m) of the grain's spheres about its central sphere's centre: the central one first, then
    the leading corner (scene.leading) and three corners at the tetrahedron's angle arccos(-1/3) from it."""
    g = case.grain
    big = 0.5 * g.size / (1.0 + g.corner)
    d = leading(case)
    side = np.array([0.0, 1.0, 0.0])
    third = np.cross(d, side)
    cos_t, sin_t = -1.0 / 3.0, math.sqrt(8.0) / 3.0
    corners = [d] + [cos_t * d + sin_t * (math.cos(p) * side + math.sin(p) * third)
                     for p in (0.0, 2.0 * math.pi / 3.0, 4.0 * math.pi / 3.0)]
    rows = [[0.0, 0.0, 0.0, big]] + [[*(big * u), g.corner * big] for u in corners]
    return np.array(rows)


def grain_spheres(case: ScratchCase) -> np.ndarray:
    """(5, 4) x, y, z, r (m) of the grain's spheres at the start, in the box's frame (top face z = 0, the box from
    -size/2 to size/2 along x and y)."""
    spheres = clump(case)
    lowest = int(np.argmin(spheres[:, 2] - spheres[:, 3]))
    gap = START_GAP * case.numerics.dx
    low_x, low_z = spheres[lowest, 0], spheres[lowest, 2] - spheres[lowest, 3]
    run_in = gap / math.tan(math.radians(case.grain.angle))  # x the lowest point travels to drop by the gap
    x0 = -0.5 * case.target.size[0] + case.target.entry - run_in - low_x
    spheres[:, 0] += x0
    spheres[:, 2] += gap - low_z
    return spheres


def grain_mass(case: ScratchCase) -> float:
    """The grain's mass, kg (the union of its spheres at its density)."""
    return mass_properties(clump(case), case.grain.density)[0]


def flow_case(case: ScratchCase) -> SphFlowCase:
    """The sph_flow case of the target, its held support and the grain."""
    impactor = {"name": "grain", "spheres": grain_spheres(case).tolist(), "density": case.grain.density,
                "velocity": (case.grain.speed * direction(case)).tolist()}
    return impact_case(case, impactor, case.grain.speed, "grain scratch")


def build_scratch(case: ScratchCase) -> SphScene:
    """The target's particles, the grain and the deck's settings (an sph_flow scene)."""
    return build_sph_flow(flow_case(case))
