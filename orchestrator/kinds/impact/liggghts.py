"""LIGGGHTS runs impact cases: the adapter (deck and contact-law mapping in liggghts_deck.py, parser in
liggghts_output.py; engines.liggghts starts LIGGGHTS)."""

from __future__ import annotations

from pathlib import Path

from orchestrator.kinds.base import Adapter
from orchestrator.kinds.impact.liggghts_deck import TEMPLATE, check_impact_scene, impact_context, write_impact_files
from orchestrator.kinds.impact.liggghts_output import read_impact_output
from orchestrator.templating import render

DECK = "impact.in"


class LiggghtsImpact(Adapter):
    """Impact scenes as a LIGGGHTS deck (templates/liggghts.in.j2) with the spheres in spheres.data."""

    engine = "liggghts"
    templates = (TEMPLATE,)

    def check_scene(self, profile, scene) -> None:
        """Refuse what LIGGGHTS-PUBLIC 3.8 cannot run (liggghts_deck.check_impact_scene)."""
        check_impact_scene(scene)

    def write_input(self, profile, scene, workdir: Path) -> None:
        (workdir / "output").mkdir(exist_ok=True)
        write_impact_files(scene, workdir)
        (workdir / DECK).write_text(render(TEMPLATE, impact_context(scene)))

    def command(self, profile, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        return profile.command(DECK)

    def read_output(self, profile, scene, workdir: Path):
        return read_impact_output(scene, workdir)
