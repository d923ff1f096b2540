"""Rigid impactors of an SPH case ([[impactors]]): ideally hard bodies whose surface is a union of spheres (one: a
glass ball; several: a grain's clump), free or kinematic, that push on the particles in compression only
(engines/sph/README.md, "Rigid impactors", eqs. I1-I3). 3D only. SI units (m, kg, s).

The mass and the inertia tensor follow from the density: in closed form for one sphere, by integrating the union
of several on a grid of at least 48 cells across the smallest sphere otherwise (its relative error below 1e-3).
The contact spring is ``stiffness_factor`` x rho0 c0^2 dx of the stiffest material (rho0 c_L^2 dx for a solid: as
stiff as the solid's own particles), so the overlap under a contact pressure p is about p / (rho0 c0^2) dx.
"""

from __future__ import annotations

import math

import numpy as np
from pydantic import Field

from orchestrator.case.common import Frozen, Name, Positive

Vector3 = tuple[float, float, float]


class Impactor(Frozen):
    """One rigid impactor: its spheres, density, initial (or prescribed) motion and contact stiffness."""

    name: Name = Field(description="unique name (series impactor_<name>_*)")
    spheres: tuple[tuple[float, float, float, Positive], ...] = Field(
        min_length=1, max_length=10000, description="x, y, z (m) and radius (m) of each sphere of the surface")
    density: Positive = Field(description="density of the body, kg/m^3")
    velocity: Vector3 = Field((0.0, 0.0, 0.0), description="velocity of the centre of mass, m/s")
    angular_velocity: Vector3 = Field((0.0, 0.0, 0.0), description="angular velocity, rad/s (world axes)")
    kinematic: bool = Field(False, description="true: the motion is prescribed (the force it needs is recorded)")
    stiffness_factor: float = Field(1.0, gt=0.0, le=20.0, description="the contact spring over rho0 c0^2 dx of the "
                                    "stiffest material, -")

    def mass_properties(self) -> tuple[float, np.ndarray, np.ndarray]:
        """(mass kg, centre of mass (3,) m, inertia tensor about it (3, 3) kg m^2)."""
        return mass_properties(np.asarray(self.spheres, dtype=float), self.density)

    def deck(self, stiffness_scale: float) -> dict:
        """The impactor as the deck's JSON object; stiffness_scale = rho0 c0^2 dx of the stiffest material, N/m."""
        mass, centre, inertia = self.mass_properties()
        return {"name": self.name, "mass": mass, "inertia": inertia.tolist(), "centre": centre.tolist(),
                "spheres": [[float(c) for c in s] for s in self.spheres], "velocity": list(map(float, self.velocity)),
                "angular_velocity": list(map(float, self.angular_velocity)), "kinematic": self.kinematic,
                "stiffness": self.stiffness_factor * stiffness_scale}


def mass_properties(spheres: np.ndarray, density: float, cells: int = 48) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass (kg), centre of mass (3,) m and inertia tensor about it (3, 3) kg m^2 of the union of spheres (k, 4)
    (x, y, z, r in m) of uniform density (kg/m^3): closed form for one sphere; otherwise the midpoint rule on a
    grid of `cells` cells across the smallest sphere, in slabs so its memory stays small."""
    if len(spheres) == 1:
        radius = spheres[0, 3]
        mass = density * 4.0 / 3.0 * math.pi * radius**3
        return mass, spheres[0, :3].copy(), 0.4 * mass * radius**2 * np.eye(3)
    lo = (spheres[:, :3] - spheres[:, 3:]).min(axis=0)
    hi = (spheres[:, :3] + spheres[:, 3:]).max(axis=0)
    step = 2.0 * spheres[:, 3].min() / cells
    axes = [lo[k] + (np.arange(math.ceil((hi[k] - lo[k]) / step)) + 0.5) * step for k in range(3)]
    y, z = np.meshgrid(axes[1], axes[2], indexing="ij")
    volume = 0.0
    first = np.zeros(3)
    second = np.zeros((3, 3))
    for x in axes[0]:
        points = np.column_stack([np.full(y.size, x), y.ravel(), z.ravel()])
        inside = np.zeros(len(points), dtype=bool)
        for c in spheres:
            inside |= ((points - c[:3]) ** 2).sum(axis=1) <= c[3] ** 2
        p = points[inside]
        volume += len(p)
        first += p.sum(axis=0)
        second += p.T @ p
    cell = step**3
    mass = density * volume * cell
    centre = first / volume
    covariance = density * cell * (second - volume * np.outer(centre, centre))  # sum m r r^T about the centre
    inertia = np.trace(covariance) * np.eye(3) - covariance + mass * step**2 / 6.0 * np.eye(3)
    return mass, centre, inertia


def check_impactors(impactors, dimension: int) -> None:
    """ValueError naming the key unless the impactors are 3D and uniquely named."""
    names: set[str] = set()
    for i, imp in enumerate(impactors):
        if dimension != 3:
            raise ValueError(f"impactors[{i}]: impactors act in 3D only (domain.dimension = {dimension})")
        if imp.name in names:
            raise ValueError(f"impactors[{i}].name = {imp.name!r} is used twice; names must be unique")
        names.add(imp.name)


def check_clear(impactors, positions: np.ndarray, moving: np.ndarray, dx: float) -> None:
    """ValueError naming the impactor when one starts inside a moving particle (its extent dx/2 included)."""
    for i, imp in enumerate(impactors):
        for k, (x, y, z, r) in enumerate(imp.spheres):
            gap = np.linalg.norm(positions[moving] - np.array([x, y, z]), axis=1) - r - 0.5 * dx
            if gap.size and gap.min() < 0.0:
                raise ValueError(f"impactors[{i}].spheres[{k}] of {imp.name!r} overlaps the particles by "
                                 f"{-gap.min():.4g} m at the start: move it clear (the particles reach dx/2 = "
                                 f"{0.5 * dx:.4g} m beyond their centres)")


def stiffness_scale(materials, dx: float) -> float:
    """rho0 c0^2 dx of the stiffest material (c0: a solid's longitudinal wave speed), N/m."""
    return max(m.rho0 * m.c0**2 for m in materials) * dx
