"""What a LAMMPS MACHDYN crater run wrote (output/frames.dump, output/series.txt, the screen log), read back into the
frame and series names of the sph executable's crater runs, so that measure_crater reads both alike.

Frames: the target's particles (its held support included, the sphere's left out): ids (from 0, input order), kind
(0 moving, 1 held, as the scene's), positions, velocities, plastic_strain (MACHDYN's effective plastic strain) and
internal_energy (J/kg: MACHDYN's per-particle energy over the particle's mass: elastic energy, plastic work, the
artificial viscosity's heat and the hourglass control's work). No temperature: MACHDYN computes none.
Series: impactor_sphere_position (its centre), _velocity, _force (the total force on it: the contact's), its
_kinetic_energy and _contact_energy (the Hertz contact's elastic energy), the target's kinetic and internal energy.
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
#: Series of the run: name -> (columns of the series file, unit, meaning).
SERIES_COLUMNS = {
    "impactor_sphere_position": (("x", "y", "z"), "m", "the sphere's centre"),
    "impactor_sphere_velocity": (("vx", "vy", "vz"), "m/s", "the sphere's velocity"),
    "impactor_sphere_force": (("fx", "fy", "fz"), "N", "the contact force on the sphere"),
    "impactor_sphere_kinetic_energy": (("sphere_kinetic",), "J", "the sphere's kinetic energy"),
    "impactor_sphere_contact_energy": (("contact_energy",), "J", "the Hertz contact's elastic energy"),
    "target_kinetic_energy": (("target_kinetic",), "J", "kinetic energy of the target"),
    "target_internal_energy": (("target_internal",), "J", "MACHDYN's internal energy of the target (elastic, "
                                                          "plastic, viscous, hourglass)"),
}


def read_series(path: Path) -> tuple[np.ndarray, dict[str, Series]]:
    """(time s, series by name) of the series file; (empty, {}) without records."""
    table = read_table(path) if Path(path).is_file() and Path(path).stat().st_size else {}
    if not len(table.get("time", ())):
        return np.zeros(0), {}
    series = {}
    for name, (columns, unit, meaning) in SERIES_COLUMNS.items():
        values = np.column_stack([np.asarray(table[c], dtype=float) for c in columns])
        series[name] = Series(values if len(columns) > 1 else values[:, 0], unit, meaning)
    return np.asarray(table["time"], dtype=float), series


def read_crater_output(workdir: Path, scene, steps: tuple[int, float, int]) -> Result:
    """The Result of a MACHDYN crater run in workdir (complete or partial). steps: machdyn.run_steps (planned
    steps, dt s, steps per frame). Failed on a LAMMPS ERROR, a lost particle or a missing end."""
    workdir = Path(workdir)
    planned, dt, _ = steps
    n = len(scene.positions)
    masses = np.asarray(scene.masses, dtype=float)
    log = tail(workdir / LOG_NAME, 400) if (workdir / LOG_NAME).is_file() else ""
    records = read_frames(workdir / DUMP)
    result = Result()
    result.frames = [(step * dt, frame_arrays(rows, masses, scene.kind)) for step, rows in records if len(rows) == n]
    last = records[-1][0] if records else 0
    result.attrs.update(n_steps=last, dt=dt, simulated_time=last * dt, dx=float(scene.case.numerics.dx),
                        h=float(scene.h), dimension=3)
    result.attrs.update(loop_times(log))
    time, series = read_series(workdir / SERIES)
    if len(time):
        result.time, result.series = time, series
    errors = [line.strip() for line in log.splitlines() if line.startswith("ERROR")]
    if errors:
        result.status, result.message = "failed", f"LAMMPS stopped with an error: {errors[-1]}"
    elif any(len(rows) != n for _, rows in records):
        result.status, result.message = "failed", "MACHDYN lost particles (det F out of range or out of the box)"
    elif "STATUS finished" not in log or last < planned:
        result.status, result.message = "failed", "LAMMPS ended without finishing its run (stopped or crashed)"
    return result
