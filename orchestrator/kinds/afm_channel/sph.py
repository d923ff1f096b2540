"""The sph executable runs the channel: its scene is an sph_flow scene with a fluid, a johnson_cook workpiece and a
grain, so the sph_flow adapter's deck, particle file, out.h5 reader and resume apply unchanged
(kinds/sph_flow/sph.py)."""

from __future__ import annotations

from orchestrator.kinds.sph_flow.sph import SphFlow


class SphAfmChannel(SphFlow):
    """The abrasive-flow channel on the sph executable (a Newtonian medium, a workpiece and a grain)."""
