"""The sph executable runs the Taylor bar: its scene is an sph_flow scene, so the sph_flow adapter's deck,
particle file and out.h5 reader apply unchanged (kinds/sph_flow/sph.py)."""

from __future__ import annotations

from orchestrator.kinds.sph_flow.sph import SphFlow


class SphTaylorBar(SphFlow):
    """The Taylor bar on the sph executable (a johnson_cook material and a penalty wall)."""
