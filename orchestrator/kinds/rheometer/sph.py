"""The sph executable runs the rheometer: the sample's scene is an sph_flow scene, so the sph_flow adapter's
deck, particle file and out.h5 reader apply unchanged (kinds/sph_flow/sph.py)."""

from __future__ import annotations

from orchestrator.kinds.sph_flow.sph import SphFlow


class SphRheometer(SphFlow):
    """The rheometer's sample on the sph executable (a JSON deck with Lees-Edwards shear and a PTT material)."""
