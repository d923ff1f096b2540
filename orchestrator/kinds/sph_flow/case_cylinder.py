"""A block's cut to a cylindrical shell (kind "sph_flow"): pipe and annulus walls and fluid on the block's lattice."""

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

    @model_validator(mode="after")
    def _radii(self):
        if self.inner_radius >= self.radius:
            raise ValueError(f"inner_radius = {self.inner_radius} m must be below radius = {self.radius} m")
        return self

    def keeps(self, points) -> np.ndarray:
        """Mask of the points (n, 3), m, that lie in the shell."""
        off = np.asarray(points, dtype=float) - np.asarray(self.center, dtype=float)
        off[:, self.axis] = 0.0
        r = np.linalg.norm(off, axis=1)
        return (r >= self.inner_radius) & (r < self.radius)
