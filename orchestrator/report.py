"""`orchestrator analyze RUN_DIR`: the run's kind prints its comparison with the case's references and draws its
pictures (kinds.<kind>: Kind.analyze)."""

from __future__ import annotations

from pathlib import Path

from orchestrator.errors import ReadError
from orchestrator.kinds import get_kind
from orchestrator.runh5 import read_run, stored_case


def analyze_run(run_dir, render: bool = True) -> dict:
    """Print the run's comparison table and write its PNG pictures into run_dir; returns {name: path}.

    render=False leaves out the pyvista renderings (networks, meshes).
    """
    run_dir = Path(run_dir)
    run = read_run(run_dir)
    case = stored_case(run, run_dir)
    attrs = run["attrs"]
    missing = [key for key in ("status", "engine", "engine_version", "n_particles", "n_steps", "wall_time_s")
               if key not in attrs]
    if missing:
        raise ReadError(f"{run_dir}: run.h5 lacks the attribute {missing[0]!r}; it was not written by "
                        "'orchestrator run' (or is damaged)")
    return get_kind(case.case.kind).analysis(run_dir, run, case, render)
