"""A block's cut to a cylindrical shell (kind "sph_flow"): pipe and annulus walls and fluid on the block's lattice,
and, for a wall, each boundary site's nearest point on the true cylinder (the engine's `wall_point`)."""

from __future__ import annotations

from typing import Annotated, Literal

import numpy as np
from pydantic import Field, model_validator

from orchestrator.case.common import Frozen, NonNegative, Positive

Point3 = Annotated[tuple[float, float, float], Field(description="m")]


class BlockCylinder(Frozen):
    """Keeps the block's sites at distance r from the axis line with inner_radius <= r < radius (3D)."""

    axis: Literal[0, 1, 2] = Field(description="the axis the cylinder runs along (0 x, 1 y, 2 z)")
    center: Point3 = Field(description="a point of the axis line, m")
    radius: Positive = Field(description="outer radius, m (sites at r < radius)")
    inner_radius: NonNegative = Field(0.0, description="inner radius, m (sites at r >= inner_radius), < radius")
    wall: Literal["inner", "outer", "both"] | None = Field(
        None, description="boundary blocks: the face of the shell that the fluid wets, whose no-slip the engine "
                          "places on the true cylinder (each site's nearest point of it, the particle file's "
                          "wall_point): inner (r = inner_radius: a pipe's wall around the fluid), outer (r = radius: "
                          "a core inside the fluid), both (the nearer face: a tube with fluid on both sides); "
                          "default none: the no-slip halfway between the lattice layers (Adami's mirror)")

    @model_validator(mode="after")
    def _radii(self):
        if self.inner_radius >= self.radius:
            raise ValueError(f"inner_radius = {self.inner_radius} m must be below radius = {self.radius} m")
        if self.wall in ("inner", "both") and self.inner_radius <= 0.0:
            raise ValueError(f"wall = {self.wall!r} needs an inner face: inner_radius > 0 (a solid core's wall is "
                             "'outer')")
        return self

    def _radial(self, points):
        off = np.asarray(points, dtype=float) - np.asarray(self.center, dtype=float)
        off[:, self.axis] = 0.0
        return off, np.linalg.norm(off, axis=1)

    def keeps(self, points) -> np.ndarray:
        """Mask of the points (n, 3), m, that lie in the shell."""
        _, r = self._radial(points)
        return (r >= self.inner_radius) & (r < self.radius)

    def wall_points(self, points) -> np.ndarray:
        """Each point's nearest point (n, 3), m, on the wetted face(s) of `wall` (the same axial position, radius of
        the face along the point's radial direction); NaN rows on the axis (no direction) or when wall is None."""
        points = np.asarray(points, dtype=float)
        out = np.full(points.shape, np.nan)
        if self.wall is None:
            return out
        off, r = self._radial(points)
        if self.wall == "inner":
            face = np.full(len(r), self.inner_radius)
        elif self.wall == "outer":
            face = np.full(len(r), self.radius)
        else:
            face = np.where(np.abs(r - self.inner_radius) <= np.abs(self.radius - r), self.inner_radius, self.radius)
        on_axis = r <= 1e-12 * self.radius
        scale = np.divide(face, r, out=np.zeros_like(r), where=~on_axis)
        out[~on_axis] = (points - off + off * scale[:, None])[~on_axis]
        return out
