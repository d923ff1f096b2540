"""Resume a stopped LIGGGHTS drag-finishing run from its last checkpoint.

With output.checkpoint_interval set, the deck writes a restart file every that much process time (two files in
turn, so one is always whole) and then output/checkpoint.txt: which file, the step, the time and the variables
the deck carries between phases. `orchestrator run --resume RUN_DIR` renders the same template in resume mode
(drag_finishing_resume.in): read_restart (which brings back the balls, the meshes where they were, the rod's
move/mesh state and the ball-ball and ball-mesh contact histories), the process stiffness and time step, the
clock offset (LIGGGHTS restarts time at 0) and the process chunks after the checkpoint's. Rows the stopped run
recorded after the checkpoint are dropped from output/series.txt first, so the series continues without a gap or
a repeat.

What is not restored, so a resumed run is close to, not bitwise equal to, an uninterrupted one (LIGGGHTS's
read_restart documentation): granular pair styles evaluate the first step after a restart with full-step
velocities where the uninterrupted run uses half-step ones.
"""

from __future__ import annotations

from pathlib import Path

from orchestrator.errors import OrchestratorError
from orchestrator.kinds.drag_finishing.liggghts_deck import TEMPLATE, drag_context
from orchestrator.templating import render

CHECKPOINT = Path("output") / "checkpoint.txt"
RESUME_DECK = "drag_finishing_resume.in"
RESTART_FILES = ("output/checkpoint_0.restart", "output/checkpoint_1.restart")
KEYS = ("chunk", "restart", "step", "time", "t_process", "settled", "bed_height", "stiffen_step", "tip")


def read_checkpoint(workdir: Path) -> dict[str, str]:
    """output/checkpoint.txt of a run ('key value' lines) as text values; OrchestratorError if there is none."""
    path = Path(workdir) / CHECKPOINT
    if not path.is_file():
        raise OrchestratorError(
            f"{workdir} holds no checkpoint ({CHECKPOINT}): the run wrote none (set output.checkpoint_interval) or "
            "stopped before the first one; run it again instead")
    values = dict(line.partition(" ")[::2] for line in path.read_text().splitlines() if line.strip())
    missing = [key for key in KEYS if not values.get(key, "").strip()]
    if not missing and values["restart"].strip() not in RESTART_FILES:
        missing = ["restart (one of the deck's own restart files)"]
    if missing or not (Path(workdir) / values["restart"].strip()).is_file():
        raise OrchestratorError(f"{path} is incomplete (missing {', '.join(missing) or values['restart']}); "
                                "run the case again instead")
    return {key: values[key].strip() for key in KEYS}


def truncate_series(path: Path, last_step: int) -> int:
    """Drop the rows of a series.txt recorded after last_step (comment lines stay); returns how many."""
    lines = Path(path).read_text().splitlines(keepends=True) if Path(path).is_file() else []
    kept = [line for line in lines if line.startswith("#") or not line.strip()
            or (step := _step_of(line)) is not None and step <= last_step]
    Path(path).write_text("".join(kept))
    return len(lines) - len(kept)


def _step_of(line: str) -> int | None:
    try:
        return int(float(line.split()[0]))
    except (ValueError, IndexError):
        return None


def resume_context(scene, workdir: Path) -> dict:
    """The drag deck's context (liggghts_deck.drag_context) in resume mode from the run's last checkpoint."""
    context = drag_context(scene)
    point = read_checkpoint(workdir)
    for key in ("step", "time", "t_process", "settled", "bed_height", "stiffen_step", "tip"):
        float(point[key])  # numbers only reach the deck
    context["resume"] = {**point, "chunk": int(point["chunk"])}
    return context


def write_resume_deck(scene, workdir: Path) -> str:
    """Write workdir/drag_finishing_resume.in and trim output/series.txt to the checkpoint; returns the deck name."""
    workdir = Path(workdir)
    context = resume_context(scene, workdir)
    truncate_series(workdir / "output" / "series.txt", int(float(context["resume"]["step"])))
    (workdir / RESUME_DECK).write_text(render(TEMPLATE, context))
    return RESUME_DECK
