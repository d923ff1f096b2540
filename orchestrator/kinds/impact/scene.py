"""The scene of an impact case: sphere arrays, the wall, gravity, the time step and the contact pairs' physics
(built once for every engine; the physics and the choice of the time step are in physics.py). SI units."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from orchestrator.kinds.impact.case import ImpactCase
from orchestrator.kinds.impact.physics import STANDARD_GRAVITY, PairPhysics, critical_timestep, pair_physics  # noqa: F401


@dataclass(frozen=True)
class ImpactScene:
    """What every engine needs to run an impact case (SI units)."""

    case: ImpactCase
    positions: np.ndarray  # (n,3) m
    velocities: np.ndarray  # (n,3) m/s
    angular_velocities: np.ndarray  # (n,3) rad/s
    radii: np.ndarray  # (n,) m
    sphere_materials: tuple[str, ...]
    plane_point: np.ndarray | None  # (3,) m
    plane_normal: np.ndarray | None  # (3,) unit
    plane_material: str | None
    gravity: np.ndarray  # (3,) m/s^2
    timestep: float  # s
    critical_timestep: float  # s
    duration: float  # s
    record_interval: float  # s
    pairs: dict[tuple[str, str], PairPhysics]
    meshes: dict = field(default_factory=dict)

    @property
    def n_particles(self) -> int:
        """Number of spheres."""
        return len(self.radii)

    def pair(self, a: str, b: str) -> PairPhysics:
        """Constants of the material pair (a, b), order free."""
        return self.pairs[tuple(sorted((a, b)))]

    def plane_triangle(self, reach: float) -> np.ndarray:
        """Corners (3, 3), m, of an equilateral triangle in the plane (for engines that take a wall as a mesh),
        centred under the spheres, whose inscribed circle covers what they can reach: 2 reach (m) plus four
        times the spheres' spread about that centre."""
        normal, point = self.plane_normal, self.plane_point
        u = np.cross(normal, [1.0, 0.0, 0.0] if abs(normal[0]) < 0.9 else [0.0, 1.0, 0.0])
        u /= np.linalg.norm(u)
        w = np.cross(normal, u)
        centre = self.positions.mean(axis=0)
        centre = centre - ((centre - point) @ normal) * normal
        size = 2.0 * reach + 4.0 * float(np.linalg.norm(self.positions - centre, axis=1).max())
        return np.array([centre + size * (math.cos(a) * u + math.sin(a) * w)
                         for a in (0.0, 2 * math.pi / 3, 4 * math.pi / 3)])


def build_impact(case: ImpactCase) -> ImpactScene:
    """The ImpactScene of a validated impact case."""
    critical = critical_timestep(case)
    dt = case.numerics.timestep if case.numerics.timestep is not None else case.numerics.timestep_factor * critical
    dt = min(dt, case.simulation.duration)
    record = case.output.record_interval or case.simulation.duration / 1000.0
    plane = case.plane
    pairs = pair_physics(case)
    return ImpactScene(
        case=case,
        positions=np.array([s.position for s in case.spheres], float).reshape(-1, 3),
        velocities=np.array([s.velocity for s in case.spheres], float).reshape(-1, 3),
        angular_velocities=np.array([s.angular_velocity for s in case.spheres], float).reshape(-1, 3),
        radii=np.array([s.radius for s in case.spheres], float),
        sphere_materials=tuple(s.material for s in case.spheres),
        plane_point=None if plane is None else np.array(plane.point, float),
        plane_normal=None if plane is None else np.array(plane.unit_normal, float),
        plane_material=None if plane is None else plane.material,
        gravity=np.array([0.0, 0.0, -STANDARD_GRAVITY if case.simulation.gravity else 0.0]),
        timestep=float(dt),
        critical_timestep=critical,
        duration=case.simulation.duration,
        record_interval=float(min(record, case.simulation.duration)),
        pairs=pairs,
    )
