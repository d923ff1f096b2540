"""Why the reference DEM does not run drag-finishing cases (the kind's refusal for --engine reference)."""

from __future__ import annotations

from orchestrator.engines.reference import MAX_WALL_TIME_S, SPHERE_STEP_COST_S, STEP_COST_S
from orchestrator.humanize import duration
from orchestrator.kinds.drag_finishing.schedule import schedule
from orchestrator.reference.dem import MAX_SPHERES


def refusal(scene) -> str:
    """The message for a drag-finishing scene on the reference engine: its size in steps and numpy time, and the
    engines to use."""
    steps = schedule(scene).planned_steps
    estimate = steps * (STEP_COST_S + SPHERE_STEP_COST_S * scene.n_particles)
    size = f"{scene.n_particles} balls for about {steps / 1e6:.3g} million steps: {duration(estimate)} at the least in numpy"
    reason = (f"it is too big ({size})" if estimate > MAX_WALL_TIME_S else f"it has {size}") + \
        " and needs a rod turning through the bed, which the reference does not model"
    return (f"the reference DEM cannot run {scene.case.case.name}: {reason}. The reference runs impact cases (up to "
            f"{MAX_SPHERES} spheres, under {duration(MAX_WALL_TIME_S)}). Run it on an engine instead: --engine yade "
            "or --engine liggghts")
