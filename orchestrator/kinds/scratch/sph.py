"""The sph executable runs the scratch: its scene is an sph_flow scene with a rigid impactor, so the sph_flow
adapter's deck, particle file and out.h5 reader apply unchanged (kinds/sph_flow/sph.py)."""

from __future__ import annotations

from orchestrator.kinds.sph_flow.sph import SphFlow


class SphScratch(SphFlow):
    """The grain scratch on the sph executable (a johnson_cook target and a rigid grain)."""
