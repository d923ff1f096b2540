"""Resuming a stopped sph run from its last frame (`orchestrator run --resume RUN_DIR`), and merging its parts.

A run stopped by --timeout or a signal writes a last frame at its stop time that holds every particle: ids, kind
(the inlet and outlet buffers too), positions, velocities and densities, and the integrated fields of its
materials (a solid's deviatoric stress and scalars: energy, plastic strain, temperature, damage; a PTT fluid's
per-mode stresses), which the resumed run reads back (engine: restore_fields.h). write_resume_input moves the run's
out.h5 to out.<k>.h5 (the first free k), writes particles_resume.h5 from that frame (each particle's mass,
material and wall point from its input row in particles.h5, or from the inlet for particles the inlets made) and
deck_resume.json (deck.json from t_start = the frame's time, step_start = its step). The engine then continues
into a new out.h5; merge_parts joins the parts' series and frames at each part's start time. Given a later end time
(`run --resume RUN_DIR --until T`), a finished run runs on from its last frame to T the same way.

Not restored, so a resumed run is close to, not bitwise equal to, an uninterrupted one: the rates of the last half
step (recomputed from the frame's state before the first step), the Verlet list and the order of the particles
in memory (sums run in another order), and a column outlet's chamber (eq. OB5), which starts again from its
buffer's particles as at t = 0 (in a steady state their density and speed are the chamber's), and a solid's
kernel correction of eq. KC1 (recomputed from the state). Runs whose state holds more than the frame does are
refused: Lees-Edwards cells (the cell's strain) and rigid impactors (their pose is not particles). A rigid grain is
its particles: the engine builds its body frame from their positions at any start, and its velocity and angular
velocity are those of its particles' rigid motion in the frame (grain_motion), which the resumed deck gives it.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from orchestrator.engines.base import Result, Series
from orchestrator.errors import OrchestratorError

RESUME_DECK = "deck_resume.json"
RESUME_PARTICLES = "particles_resume.h5"
FRAME_ARRAYS = ("ids", "kind", "positions", "velocities", "densities", "pressures")
#: The materials' integrated fields a frame holds and the engine reads back from the particle file.
STATE_ARRAYS = ("stress", "mode_stress", "solid_state")


def part_files(workdir: Path, output: str = "out.h5") -> list[Path]:
    """The run's engine output files in run order: out.1.h5, out.2.h5, ... (parts before each resume), out.h5."""
    workdir, stem, suffix = Path(workdir), Path(output).stem, Path(output).suffix
    numbered = []
    for path in workdir.glob(f"{stem}.*{suffix}"):
        middle = path.name[len(stem) + 1:-len(suffix)]
        if middle.isdigit():
            numbered.append((int(middle), path))
    return [path for _, path in sorted(numbered)] + [workdir / output]


def _last_frame(h5, where: str):
    """(time s, step, group) of the last frame with every array written."""
    frames = h5.get("frames", {})
    for key in sorted(frames, key=int, reverse=True):
        group = frames[key]
        if all(name in group for name in FRAME_ARRAYS):
            return float(group.attrs["time"]), int(group.attrs.get("step", 0)), group
    raise OrchestratorError(f"--resume: {where} holds no complete frame to continue from; start the run again")


def _inlet_particle(deck: dict) -> tuple[float, int]:
    """(mass kg, material index) of a particle an inlet made: rho0 of the inlet's material times dx^D."""
    materials = deck.get("materials") or []
    names = [m["name"] for m in materials]
    used = {inlet.get("material", names[0] if names else "") for inlet in deck.get("inlets", [])}
    if len(used) > 1:
        raise OrchestratorError("--resume: the inlets feed different materials, and a frame does not record which "
                                "inlet made a particle; such runs cannot be resumed")
    index = names.index(used.pop()) if materials and used else 0
    rho0 = float(materials[index]["rho0"]) if materials else float(deck["rho0"])
    return rho0 * float(deck["dx"]) ** int(deck["dimension"]), index


def write_resume_input(workdir: Path, deck_name: str = "deck.json", output: str = "out.h5",
                       t_end: float | None = None) -> str:
    """Write particles_resume.h5 and deck_resume.json that continue the stopped run in workdir from its last frame,
    after moving its output to out.<k>.h5 (a resume whose engine failed before it wrote out.h5: from the last
    out.<k>.h5); returns the deck's name. t_end (s): the end time of the continued run;
    later than the deck's, it also runs a finished run on (default: the deck's). Raises OrchestratorError naming why
    a run cannot be resumed (no output, finished, unstable, Lees-Edwards or impactors, an unknown particle id, an
    end time not after the last frame)."""
    import h5py

    workdir = Path(workdir)
    out, deck_path, input_path = workdir / output, workdir / deck_name, workdir / "particles.h5"
    earlier = [path for path in part_files(workdir, output)[:-1] if path.is_file()]
    if not out.is_file() and earlier:  # the last resume failed before its engine wrote: from the part before it
        out = earlier[-1]
    for path in (out, deck_path, input_path):
        if not path.is_file():
            raise OrchestratorError(f"--resume {workdir}: no {path.name}; there is nothing to continue from, start the "
                                    "run again")
    deck = json.loads(deck_path.read_text())
    if "lees_edwards" in deck:
        raise OrchestratorError("--resume: a Lees-Edwards cell's strain is not in its frames; start the run again")
    if deck.get("impactors"):
        raise OrchestratorError("--resume: the run has rigid impactors, whose pose and spin are not in its frames; "
                                "start the run again")
    with h5py.File(out, "r") as h5:
        status = str(h5.attrs.get("status", "running"))
        if status == "unstable":
            raise OrchestratorError(f"--resume {workdir}: the run went unstable ({h5.attrs.get('message', '')}); "
                                    "continuing from its last frame would repeat that: change the case and start anew")
        time, step, group = _last_frame(h5, str(out))
        if status == "ok" and (t_end is None or t_end <= time * (1.0 + 1e-12)):
            raise OrchestratorError(f"--resume {workdir}: the run finished (t = {h5.attrs.get('t_final', time):.6g} "
                                    "s); there is nothing left to run (--until T runs it on to a later time T, s)")
        frame = {name: np.asarray(group[name][()]) for name in (*FRAME_ARRAYS, *STATE_ARRAYS) if name in group}
    end = t_end if t_end is not None else float(deck["t_end"])
    if time >= end * (1.0 - 1e-12):
        raise OrchestratorError(f"--resume {workdir}: its last frame is at {time:.6g} s, not before the end time "
                                f"{end:.6g} s; nothing is left to run (--until T runs it on to a later time T, s)")
    with h5py.File(input_path, "r") as h5:
        masses = np.asarray(h5["masses"][()])
        material = np.asarray(h5["material"][()]) if "material" in h5 else None
        wall_point = np.asarray(h5["wall_point"][()]) if "wall_point" in h5 else None
        densities = np.asarray(h5["densities"][()]) if "densities" in h5 else None
        grain = np.asarray(h5["grain"][()]) if "grain" in h5 else None
    ids = frame["ids"].astype(np.int64)
    known = ids < len(masses)
    if (ids < 0).any():
        raise OrchestratorError(f"--resume: {out} holds negative particle ids; it is not this run's output")
    row = np.where(known, ids, 0)
    inlet_mass, inlet_material = _inlet_particle(deck) if (~known).any() else (1.0, 0)
    if out.name == output:
        k = 1
        while (workdir / f"{Path(output).stem}.{k}{Path(output).suffix}").exists():
            k += 1
        out.rename(workdir / f"{Path(output).stem}.{k}{Path(output).suffix}")
    if wall_point is not None and densities is not None:
        # a wall particle's density is the fluid's Shepard value at each evaluation (eq. WP3), not a state: older
        # engines integrated it and their frames may hold it drifted (below 0, which the engine refuses)
        walled = known & (frame["kind"] == 1) & np.isfinite(wall_point[row]).all(axis=1)
        frame["densities"] = np.where(walled, densities[row], frame["densities"])
    _write_particles(workdir / RESUME_PARTICLES, deck, frame, ids, row, known,
                     {"masses": masses, "material": material, "wall_point": wall_point, "grain": grain},
                     inlet_mass, inlet_material)
    deck.update(particles_file=RESUME_PARTICLES, t_start=time, step_start=step, t_end=end)
    (workdir / RESUME_DECK).write_text(json.dumps(deck, indent=1))
    return RESUME_DECK


def _write_particles(path: Path, deck: dict, frame: dict, ids, row, known, rows: dict, inlet_mass: float,
                     inlet_material: int) -> None:
    """The resumed run's particle file from the frame's arrays (rows: its input rows' masses, material, wall_point
    and grain, each None when the input had none; a particle an inlet made takes the inlet's mass and material);
    each grain's particles made whole and its motion into the deck's grains."""
    import h5py

    masses, material, wall_point, grain = rows["masses"], rows["material"], rows["wall_point"], rows["grain"]
    if deck.get("grains") and grain is not None:
        for g, spec in enumerate(deck["grains"]):
            mine = known & (frame["kind"] == 4) & (np.where(known, grain[row], -1) == g)
            frame["positions"][mine], spec["velocity"], spec["angular_velocity"] = grain_motion(
                frame["positions"][mine], frame["velocities"][mine], deck.get("periodic"))
    with h5py.File(path, "w") as h5:
        for name in ("positions", "velocities", "densities"):
            h5[name] = frame[name].astype(np.float64)
        h5["kind"] = frame["kind"].astype(np.int8)
        h5["ids"] = ids
        h5["masses"] = np.where(known, masses[row], inlet_mass)
        if material is not None:
            h5["material"] = np.where(known, material[row], inlet_material).astype(np.int32)
        if wall_point is not None:
            h5["wall_point"] = np.where(known[:, None], wall_point[row], np.nan)
        if grain is not None:
            h5["grain"] = np.where(known, grain[row], -1).astype(np.int32)
        for name in STATE_ARRAYS:
            if name in frame:
                h5[name] = frame[name].astype(np.float64).reshape(len(ids), -1)


def grain_motion(positions, velocities, periodic=None) -> tuple[np.ndarray, list[float], list[float]]:
    """A grain's particles (equal masses) in a frame: their positions made whole across the periodic box (each
    within half a box length of the first's; the engine builds a grain from unwrapped particles), the velocity of
    their centre and their angular velocity, omega = I^-1 sum r x v about the centre (exact for a rigid motion
    v = V + omega x r), m/s and rad/s."""
    x, v = np.array(positions, dtype=float), np.asarray(velocities, dtype=float)
    if periodic:
        for axis, lo, hi in zip(periodic["axes"], periodic["lo"], periodic["hi"]):
            length = float(hi) - float(lo)
            x[:, axis] -= length * np.round((x[:, axis] - x[0, axis]) / length)
    r, velocity = x - x.mean(axis=0), v.mean(axis=0)
    inertia = np.eye(3) * np.sum(r * r) - r.T @ r
    omega = np.linalg.solve(inertia, np.cross(r, v - velocity).sum(axis=0))
    return x, velocity.tolist(), omega.tolist()


def merge_parts(parts: list[tuple[Result, dict]]) -> Result:
    """One Result from a run's parts in run order, each (Result, its out.h5 root attributes): series rows and frames
    of a part up to the next part's start time, then the next part's after it (its first row and frame repeat the
    state it started from); steps and wall times summed, the mean step weighted by steps, status and message the
    last part's."""
    merged = parts[0][0]
    if len(parts) == 1:
        return merged
    steps = [int(result.attrs.get("n_steps", 0)) for result, _ in parts]
    walls = [float(result.attrs.get("engine_wall_time_s", 0.0)) for result, _ in parts]
    dts = [float(result.attrs.get("dt", 0.0)) for result, _ in parts]
    rates = [float(result.attrs.get("particle_steps_per_s", 0.0)) for result, _ in parts]
    for result, attrs in parts[1:]:
        if "t_start" not in attrs:  # a part that wrote nothing readable: its status, the earlier parts' data
            merged.status, merged.message = result.status, result.message
            continue
        start = float(attrs["t_start"])
        cut = start * (1.0 + 1e-9) + 1e-300
        keep_old = merged.time <= cut if merged.time is not None else None
        keep_new = result.time > cut if result.time is not None else None
        if keep_old is not None and keep_new is not None:
            names = list(dict.fromkeys([*merged.series, *result.series]))
            series = {}
            for name in names:
                old, new = merged.series.get(name), result.series.get(name)
                template = old if old is not None else new
                pick = lambda s, keep, n: (np.asarray(s.values)[keep] if s is not None else  # noqa: E731
                                           np.full((n, *np.shape(template.values)[1:]), np.nan))
                series[name] = Series(np.concatenate([pick(old, keep_old, int(keep_old.sum())),
                                                      pick(new, keep_new, int(keep_new.sum()))]),
                                      template.units, template.description)
            merged.series = series
            merged.time = np.concatenate([merged.time[keep_old], result.time[keep_new]])
        kept = [frame for frame in merged.frames if frame[0] <= cut]
        dropped = sum(1 for frame in result.frames if frame[0] <= cut)
        merged.frames = kept + [frame for frame in result.frames if frame[0] > cut]
        attrs_new = dict(result.attrs)
        if "last_good_frame" in attrs_new:
            attrs_new["last_good_frame"] = len(kept) + int(attrs_new["last_good_frame"]) - dropped
        merged.attrs.update(attrs_new)
        merged.status, merged.message = result.status, result.message
    total = sum(steps)
    merged.attrs["n_steps"] = total
    if total:
        merged.attrs["dt"] = sum(n * dt for n, dt in zip(steps, dts)) / total
    merged.attrs["engine_wall_time_s"] = sum(walls)
    if sum(walls) > 0 and all(math.isfinite(x) for x in rates):
        merged.attrs["particle_steps_per_s"] = sum(p * w for p, w in zip(rates, walls)) / sum(walls)
    merged.attrs["engine_parts"] = len(parts)
    return merged
