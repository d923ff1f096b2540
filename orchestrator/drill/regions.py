"""The fluid regions and patches a drill scene is made of: rings of revolution, radial holes and disc patches, each
with its closed-form volume and membership test, and the depth of an inlet's buffer. SI units (m, m^3); drill axis
z, z = 0 the head's front face."""

from __future__ import annotations

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


def inlet_layers(dx: float, h: float, skin: float = 0.1) -> int:
    """Buffer layers of a drill scene's inlet: 3, or more where the particles the inlet adds (`layers` dx behind
    its plane) would lie within the Verlet list's range 2h (1 + skin) of it (h = 1.5 dx: 4). Beyond it with dx/4
    to spare, the engine lets them wait for the next list build (engines/sph open_boundaries.h) instead of
    rebuilding the list for each one (dx, h in m; skin: the engine's neighbour_skin, a fraction of 2h)."""
    return max(3, math.ceil(2.0 * h * (1.0 + skin) / dx + 0.25))
