"""What a LAMMPS SPH run wrote, as the Result the sph executable's reader gives (same frame arrays, same series names
where the physics is the same): the custom dump (id type x y z vx vy vz rho, sorted by id, every record interval) and
the screen log (LAMMPS's errors, its loop time, a stop of `fix halt`).

From each record: kinetic_energy (fluid), max_density_deviation (fluid) and pressure_probe_<name>, which the sph
executable measures itself and LAMMPS does not: here they are computed from the dump the way the executable
does (probes.h: a Shepard-normalised Wendland C2 interpolation of the fluid's Tait pressure within 2h). Frames are
the records nearest to each multiple of output.frame_interval.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from orchestrator.engines.base import Result, Series
from orchestrator.engines.liggghts_files import read_dump
from orchestrator.kinds.sph_flow.sph import SERIES_DESCRIPTIONS
from orchestrator.reference.sph import kernel_value
from orchestrator.runner import LOG_NAME, tail

DUMP = "records.dump"
#: Columns of the dump, in the deck's order.
DUMP_COLUMNS = ("id", "type", "x", "y", "z", "vx", "vy", "vz", "rho")
_LOOP = re.compile(r"Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms")
_CPU_USE = re.compile(r"(\S+)% CPU use with (\d+) MPI tasks")
_HALT = re.compile(r"Fix halt condition for fix-id stability met on step (\d+) with value (\S+)")


def planned_steps(scene) -> int:
    """Steps of the run: the case's duration over the step at rest (SphScene.timestep) rounded up, at most
    numerics.max_steps."""
    steps = max(1, math.ceil(scene.case.simulation.duration / scene.timestep - 1e-9))
    cap = scene.case.numerics.max_steps
    return min(steps, cap) if cap else steps


def run_step(scene) -> float:
    """LAMMPS's fixed step, s: the duration over planned_steps (at most SphScene.timestep; the run ends at the
    duration exactly), or SphScene.timestep when numerics.max_steps cuts the run short."""
    steps = planned_steps(scene)
    whole = max(1, math.ceil(scene.case.simulation.duration / scene.timestep - 1e-9))
    return scene.case.simulation.duration / steps if steps == whole else float(scene.timestep)


def read_records(path: Path) -> list[tuple[int, np.ndarray]]:
    """(step, rows (n, 9) in DUMP_COLUMNS order) of every complete record of a LAMMPS custom dump."""
    records = []
    for step, _, rows in read_dump(path):
        if records and records[-1][0] == step:
            continue  # the deck's final write_dump repeats a record of the last step
        records.append((step, rows.reshape(len(rows), len(DUMP_COLUMNS))))
    return records


def tait_pressure(rho, rho0: float, c0: float):
    """LAMMPS's Tait EOS: rho0 c0^2 / 7 ((rho/rho0)^7 - 1), Pa."""
    return rho0 * c0**2 / 7.0 * ((np.asarray(rho, dtype=float) / rho0) ** 7 - 1.0)


def probe_pressure(point, x, p, volume, h: float, dimension: int, period) -> float:
    """Shepard-normalised pressure at point from fluid particles at x (n, D) with pressures p and volumes m/rho, Pa
    (Wendland C2 of smoothing length h; period: per-axis period, 0 for a bounded axis); NaN when none is within 2h."""
    d = np.asarray(x, dtype=float) - np.asarray(point, dtype=float)
    for axis, length in enumerate(period):
        if length:
            d[:, axis] -= length * np.round(d[:, axis] / length)
    r = np.linalg.norm(d, axis=1)
    near = r < 2.0 * h
    w = volume[near] * kernel_value(r[near], h, dimension)
    return float(np.sum(w * p[near]) / np.sum(w)) if np.sum(w) > 0 else float("nan")


def _frames_at(times: np.ndarray, interval: float) -> list[int]:
    """Indices of the records nearest to 0, interval, 2 interval, ... and the last record, in order."""
    if not len(times):
        return []
    wanted = np.arange(0.0, times[-1] + 0.5 * interval, interval)
    picks = {int(np.argmin(np.abs(times - t))) for t in wanted} | {len(times) - 1}
    return sorted(picks)


def read_lammps_output(workdir: Path, scene) -> Result:
    """The Result of a LAMMPS run in workdir: frames (ids, kind, positions, velocities, densities, pressures), the
    series of the module's docstring, the attributes of the sph reader (n_steps, dt, simulated_time,
    engine_wall_time_s, h, dx, dimension, physics), engine_cpu_time_s (the CPU time of the run loop summed over the
    ranks, s, from LAMMPS's "% CPU use" line) and the status (failed on a LAMMPS ERROR or a missing dump,
    unstable when `fix halt` stopped it at max_density_deviation)."""
    case = scene.case
    dim, dt = scene.dimension, run_step(scene)
    rho0, c0 = float(case.fluid.density), float(scene.c0)
    records = read_records(Path(workdir) / DUMP)
    log = tail(Path(workdir) / LOG_NAME, 400)
    result = Result()
    result.attrs.update(dt=dt, h=float(scene.h), dx=float(case.numerics.dx), dimension=int(dim),
                        physics=list(scene.physics), n_steps=records[-1][0] if records else 0,
                        simulated_time=(records[-1][0] * dt) if records else 0.0)
    loops = _LOOP.findall(log)
    if loops:
        wall, _, steps, atoms = loops[-1]
        result.attrs.update(engine_wall_time_s=float(wall),
                            particle_steps_per_s=int(steps) * int(atoms) / float(wall) if float(wall) > 0 else 0.0)
        use = _CPU_USE.findall(log)
        if use:
            percent, ranks = use[-1]
            result.attrs["engine_cpu_time_s"] = float(wall) * float(percent) / 100.0 * int(ranks)
    _status(result, log, records, case.numerics.max_density_deviation)
    if not records:
        return result
    period = [case.domain.hi[a] - case.domain.lo[a] if a in case.domain.periodic else 0.0 for a in range(dim)]
    times = np.array([step * dt for step, _ in records])
    names = {f"pressure_probe_{probe.name}": probe.point for probe in case.output.probes}
    values: dict[str, list[float]] = {"kinetic_energy": [], "max_density_deviation": [], **{n: [] for n in names}}
    frames = set(_frames_at(times, case.output.frame_interval))
    mass = float(np.asarray(scene.masses)[0])
    for k, (step, rows) in enumerate(records):
        arrays = _arrays(rows, dim, rho0, c0)
        fluid = arrays["kind"] == 0
        rho, p = arrays["densities"][fluid], arrays["pressures"][fluid]
        values["kinetic_energy"].append(0.5 * mass * float(np.sum(arrays["velocities"][fluid] ** 2)))
        values["max_density_deviation"].append(float(np.max(np.abs(rho / rho0 - 1.0))) if rho.size else 0.0)
        for name, point in names.items():
            values[name].append(probe_pressure(point, arrays["positions"][fluid], p, mass / rho, scene.h, dim, period))
        if k in frames:
            arrays["step"] = np.int64(step)
            result.frames.append((float(times[k]), arrays))
    result.time = times
    units = {"kinetic_energy": "J", "max_density_deviation": "-"}
    for name, series in values.items():
        description = next((text for key, text in SERIES_DESCRIPTIONS.items() if name.startswith(key)), "")
        result.series[name] = Series(np.asarray(series, dtype=float), units.get(name, "Pa"), description)
    return result


def _arrays(rows: np.ndarray, dim: int, rho0: float, c0: float) -> dict[str, np.ndarray]:
    """One record as the sph reader's frame arrays (ids from 0 in input order; kind 0 fluid, 1 boundary)."""
    rho = rows[:, 8]
    return {"ids": rows[:, 0].astype(np.int64) - 1, "kind": np.where(rows[:, 1] == 1, 0, 1).astype(np.int8),
            "positions": rows[:, 2:2 + dim].copy(), "velocities": rows[:, 5:5 + dim].copy(), "densities": rho.copy(),
            "pressures": tait_pressure(rho, rho0, c0)}


def _status(result: Result, log: str, records, limit: float) -> None:
    errors = [line.strip() for line in log.splitlines() if line.startswith("ERROR")]
    halted = _HALT.search(log)
    if errors:
        result.status, result.message = "failed", errors[-1]
    elif halted:
        result.status = "unstable"
        result.message = (f"max |rho/rho0 - 1| = {float(halted.group(2)):.3g} above numerics.max_density_deviation = "
                          f"{limit:g} at step {halted.group(1)}")
    elif not records:
        result.status, result.message = "failed", f"LAMMPS wrote no {DUMP}"
    elif "DONE steps=" not in log:
        result.status, result.message = "failed", "LAMMPS ended without finishing its run"
