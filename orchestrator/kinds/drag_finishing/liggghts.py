"""LIGGGHTS runs drag-finishing cases: the adapter (deck in liggghts_deck.py, parser in liggghts_output.py, restart
in liggghts_resume.py; engines.liggghts starts LIGGGHTS)."""

from __future__ import annotations

from pathlib import Path

from orchestrator.kinds.base import Adapter
from orchestrator.kinds.drag_finishing.impacts import template_values
from orchestrator.kinds.drag_finishing.liggghts_deck import TEMPLATE, drag_context, write_drag_files
from orchestrator.kinds.drag_finishing.liggghts_output import read_drag_output
from orchestrator.kinds.drag_finishing.liggghts_resume import write_resume_deck
from orchestrator.templating import render

DECK = "drag_finishing.in"


class LiggghtsDragFinishing(Adapter):
    """The drag-finishing scene as a LIGGGHTS deck (templates/liggghts.in.j2), balls.data and ASCII STL meshes."""

    engine = "liggghts"
    templates = (TEMPLATE,)

    def check_scene(self, profile, scene) -> None:
        """Refuse an impact window on a rod that is not a regular prism (impacts.template_values)."""
        template_values(scene)

    def write_input(self, profile, scene, workdir: Path) -> None:
        (workdir / "output").mkdir(exist_ok=True)
        write_drag_files(scene, workdir)
        (workdir / DECK).write_text(render(TEMPLATE, drag_context(scene)))

    def command(self, profile, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        return profile.command(DECK)

    def resume_input(self, profile, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        """Write the deck that continues the stopped run from its last checkpoint (liggghts_resume)."""
        return profile.command(write_resume_deck(scene, workdir))

    def planned_steps(self, profile, scene) -> int:
        """Upper bound of the run's time steps."""
        return int(drag_context(scene)["planned_steps"])

    def read_output(self, profile, scene, workdir: Path):
        return read_drag_output(scene, workdir)
