"""The sph executable runs the cantilever plate: its scene is an sph_flow scene, so the sph_flow adapter's deck,
particle file (which carries each particle's velocity, the mode's) and out.h5 reader apply unchanged."""

from __future__ import annotations

from orchestrator.kinds.sph_flow.sph import SphFlow


class SphCantileverPlate(SphFlow):
    """The cantilever plate on the sph executable (a johnson_cook material and a clamp of boundary particles)."""
