"""What a LAMMPS MACHDYN Taylor bar run wrote (output/frames.dump, output/series.txt, the screen log), read back into
the frame and series names of the sph executable's solid runs, so that measure_taylor_bar reads both alike.

Frames: ids (from 0, input order), positions, velocities, plastic_strain (MACHDYN's effective plastic strain) and
internal_energy (J/kg: MACHDYN's per-particle energy over the particle's mass; it holds the elastic energy, the plastic
work, the artificial viscosity's heat and the hourglass control's work). No temperature: MACHDYN computes none.
Series: kinetic_energy and internal_energy of the bar (J) and the wall's force on it along +z (N).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from orchestrator.engines.base import Result, Series
from orchestrator.engines.liggghts_files import read_table
from orchestrator.kinds.sph_flow.machdyn_files import (
    DUMP,
    frame_arrays,
    loop_times,
    read_frames,
)
from orchestrator.runner import LOG_NAME, tail

SERIES = "output/series.txt"
SERIES_UNITS = {"kinetic_energy": ("J", "kinetic energy of the bar"),
                "internal_energy": ("J", "MACHDYN's internal energy of the bar (elastic, plastic, viscous, hourglass)"),
                "wall_force": ("N", "force of the wall on the bar along +z")}


def read_taylor_bar_output(workdir: Path, scene, steps: tuple[int, float, int]) -> Result:
    """The Result of a MACHDYN Taylor bar run in workdir (complete or partial). steps: lammps.run_steps (planned
    steps, dt s, steps per frame). Failed on a LAMMPS ERROR, a lost particle count or a missing end."""
    workdir = Path(workdir)
    planned, dt, _ = steps
    n = len(scene.positions)
    mass = float(np.asarray(scene.masses, dtype=float)[0])
    log = tail(workdir / LOG_NAME, 400) if (workdir / LOG_NAME).is_file() else ""
    records = read_frames(workdir / DUMP)
    result = Result()
    result.frames = [(step * dt, frame_arrays(rows, mass)) for step, rows in records if len(rows) == n]
    last = records[-1][0] if records else 0
    result.attrs.update(n_steps=last, dt=dt, simulated_time=last * dt, dx=float(scene.case.numerics.dx),
                        h=float(scene.h), dimension=3)
    result.attrs.update(loop_times(log))
    table = read_table(workdir / SERIES)
    if len(table.get("time", ())):
        result.time = np.asarray(table["time"], dtype=float)
        for name, (unit, meaning) in SERIES_UNITS.items():
            result.series[name] = Series(np.asarray(table[name], dtype=float), unit, meaning)
    errors = [line.strip() for line in log.splitlines() if line.startswith("ERROR")]
    if errors:
        result.status, result.message = "failed", f"LAMMPS stopped with an error: {errors[-1]}"
    elif any(len(rows) != n for _, rows in records):
        result.status, result.message = "failed", "MACHDYN lost particles (det F out of range or out of the box)"
    elif "STATUS finished" not in log or last < planned:
        result.status, result.message = "failed", "LAMMPS ended without finishing its run (stopped or crashed)"
    return result
