"""LIGGGHTS backend, drag finishing: the deck's context (the phases and
numbers of the Yade script: same cloud, same settling criteria, same rod
motion, same damping alpha), the files it reads, and the reader that turns
what the deck wrote into the run.h5 names of Yade's runs (series
workpiece_force in the workpiece frame, rod_force, bowl_force,
kinetic_energy, unbalanced_force, n_contacts, rod_tip_z, phase; frames;
interaction networks; the rod's per-face contact intensity).

Where the deck differs from the Yade script (besides the contact law, see
liggghts_physics.py):
- the rest criterion's mean contact force is the mean *normal* force (from
  the per-atom virial for ball-ball contacts, the stored wall force for
  ball-wall ones); Yade's includes the tangential part (at most 6 % more at
  mu = 0.34), so LIGGGHTS's unbalanced ratio reads a little higher;
- the rod is pushed in for exactly the steps that bring its tip to the
  target, and the snapshots and the end fall on the exact step; Yade
  checks at its control period (1 ms);
- stiffening (settling.stiffness_scale) changes E in the same stages as
  Yade's control steps; LIGGGHTS recomputes every contact from E, so a
  sticking contact's tangential force grows with the stiffness at once where
  Yade's keeps the force it had.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..errors import ReadError
from .base import Result, Series
from .liggghts import engine_error, read_dump, read_table, write_data_file, write_stl_ascii
from .liggghts_physics import liggghts_beta, restitution_for_beta
from .yade_impact import yade_native_alpha

DATA_FILE = "balls.data"
#: What the LIGGGHTS run does differently from Yade's drag-finishing script (run.h5 attribute "deviation").
DEVIATION = ("LIGGGHTS keeps the total tangential displacement (F_t = -k_t(delta) s) where Yade increments the "
             "force; settling damps forces only (Yade also torques); the rest criterion uses the mean contact "
             "normal force")
PHASES = ("settle", "insert", "relax", "process")
#: Steps of the first process chunk, after which the deck prints its TIMING line (as Yade's script).
TIMING_STEPS = 500
#: Columns of the network dumps (compute pair/gran/local and wall/gran/local: pos id force force_normal
#: force_tangential).
NETWORK_COLUMNS = ("x1", "y1", "z1", "x2", "y2", "z2", "id1", "id2", "id3", "fx", "fy", "fz", "fnx", "fny", "fnz",
                   "ftx", "fty", "ftz")


def damping_restitution(restitution: float) -> float:
    """coefficientRestitution e* that gives LIGGGHTS the damping Yade's drag script runs for e_n, -."""
    return restitution_for_beta(liggghts_beta(yade_native_alpha(restitution)))


def _every(interval: float, step: float) -> int:
    return max(1, round(interval / step))


def drag_context(scene) -> dict:
    """Plain values the drag-finishing deck needs (SI units)."""
    from ..scene.build import settling_timestep

    case = scene.case
    scale, soft = case.numerics.stiffness_scale, case.settling_stiffness_scale
    names = (case.media.material, case.bowl.material, case.workpiece.material)
    mats = [case.materials[n] for n in names]
    restitution = np.ones((3, 3))
    friction = np.zeros((3, 3))
    for k in (0, 1, 2):  # media-media, media-bowl, media-rod
        pair = case.contact(names[0], names[k])
        restitution[0, k] = restitution[k, 0] = damping_restitution(pair.restitution)
        friction[0, k] = friction[k, 0] = pair.friction
    dt, dt_settle = scene.timestep, settling_timestep(case)
    stiffen = scale != soft or dt != dt_settle
    record_every, record_every_settle = _every(case.output.record_interval, dt), \
        _every(case.output.record_interval, dt_settle)
    control_every = min(record_every, _every(1e-3, dt))
    stages = max(1, round(case.settling.stiffen_time / (control_every * dt)))
    relax_steps_settle = _every(case.settling.relax_time, dt_settle) if case.settling.relax_time > 0 else 0
    relax_steps = _every(case.settling.relax_time, dt) if case.settling.relax_time > 0 else 0
    process_steps = _every(case.process.duration, dt)
    after_insert = relax_steps_settle + (stages * control_every + relax_steps if stiffen else 0) + process_steps
    insert_steps = (case.workpiece.submersion_depth + 2 * case.media.radius) / case.workpiece.insertion_speed / dt_settle
    planned = case.settling.max_time / dt_settle + insert_steps + after_insert
    return {
        "media_material": names[0], "bowl_material": names[1], "rod_material": names[2],
        "stiffness_scale": repr(scale),
        "settling_stiffness_scale": repr(soft),
        "young_settle": [repr(m.young_modulus * soft) for m in mats],
        "poisson": [repr(m.poisson_ratio) for m in mats],
        "restitution": [repr(float(v)) for v in restitution.ravel()],
        "friction": [repr(float(v)) for v in friction.ravel()],
        "skin": repr(0.2 * case.media.radius),
        "solid_volume": repr(float(np.sum(4.0 / 3.0 * np.pi * scene.radii**3))),
        "settling_damping": repr(case.settling.damping),
        "settle_max_time": repr(case.settling.max_time),
        "settle_unbalanced": repr(case.settling.unbalanced_force),
        "settle_max_speed": repr(case.settling.max_speed),
        "tip_start": repr(float(np.asarray(scene.meshes["rod"].mesh.vertices)[:, 2].min())),
        "submersion_depth": repr(case.workpiece.submersion_depth),
        "insertion_speed": repr(case.workpiece.insertion_speed),
        "angular_velocity": repr(case.angular_velocity),
        "rotation_period": repr(2.0 * math.pi / case.angular_velocity),
        "dt": repr(dt), "dt_settle": repr(dt_settle),
        "stiffen": stiffen, "stiffen_factor": repr(scale / soft), "stiffen_time": repr(case.settling.stiffen_time),
        "stiffen_stages": stages, "stage_steps": control_every,
        "relax_time": repr(case.settling.relax_time),
        "relax_steps_settle": relax_steps_settle, "relax_steps": relax_steps,
        "record_every": record_every, "record_every_settle": record_every_settle,
        "control_every_settle": min(record_every_settle, _every(1e-3, dt_settle)),
        "progress_every": max(100, int(planned) // 400),
        "steps_after_insert": after_insert,
        "planned_steps": int(planned),
        "process_chunks": process_chunks(process_steps, [round(t / dt) for t in case.output.network_times],
                                         checkpoint_every(case, dt)),
        "resume": None,
    }


def checkpoint_every(case, dt: float) -> int | None:
    """Process steps between checkpoints (output.checkpoint_interval), or None."""
    interval = case.output.checkpoint_interval
    return None if interval is None else _every(interval, dt)


def process_chunks(total: int, network_steps: list[int], checkpoint_steps: int | None = None) -> list[dict]:
    """The process phase as runs: [{steps, timing, networks, checkpoint}], cut at each network snapshot's step
    (from the process start), after the first TIMING_STEPS steps (the timing line) and every checkpoint_steps
    (a restart file is written after a chunk whose checkpoint is True; never after the last one)."""
    checkpoints = set(range(checkpoint_steps, total, checkpoint_steps)) if checkpoint_steps else set()
    cuts = sorted({min(TIMING_STEPS, total), total, *(min(s, total) for s in network_steps if s > 0), *checkpoints})
    chunks, done = [], 0
    for cut in cuts:
        chunks.append({"steps": cut - done, "timing": not chunks,
                       "networks": [k for k, s in enumerate(network_steps) if min(max(s, 0), total) == cut],
                       "checkpoint": cut in checkpoints})
        done = cut
    if 0 in network_steps:  # a snapshot at the start of the process: a zero-step run writes it
        chunks.insert(0, {"steps": 0, "timing": False, "networks": [k for k, s in enumerate(network_steps) if s <= 0],
                          "checkpoint": False})
    return chunks


def write_drag_files(scene, workdir: Path) -> None:
    """balls.data (the scene's cloud) and bowl.stl, rod.stl (the scene's meshes, ASCII) into workdir."""
    case = scene.case
    workdir = Path(workdir)
    bowl_r, height = case.bowl.inner_radius, case.bowl.height
    rod = np.asarray(scene.meshes["rod"].mesh.vertices)
    top = max(float(np.max(scene.positions[:, 2] + scene.radii)), float(rod[:, 2].max()))
    # a ball outside [-2R, 2R] or below -H/2 has left the bowl (as in the Yade script): LIGGGHTS loses it
    box = np.array([[-2 * bowl_r, 2 * bowl_r], [-2 * bowl_r, 2 * bowl_r], [-0.5 * height, top + 0.5 * height]])
    rho = case.materials[case.media.material].density
    write_data_file(workdir / DATA_FILE, box, 3, np.ones(scene.n_particles, int), scene.radii,
                    np.full(scene.n_particles, rho), scene.positions)
    for name in ("bowl", "rod"):
        mesh = scene.meshes[name].mesh
        write_stl_ascii(workdir / f"{name}.stl", mesh.vertices, mesh.faces, name)


# ---- output ----
def read_status(path: Path) -> dict[str, str]:
    """output/status.txt ('key value' lines, rewritten at every phase change) as a dict."""
    if not path.is_file():
        return {}
    out = {}
    for line in path.read_text().splitlines():
        key, _, value = line.partition(" ")
        out[key] = value.strip()
    return out


def read_vtk_cells(path: Path) -> dict[str, np.ndarray]:
    """A legacy ASCII VTK polydata written by dump mesh/vtk: 'points' (n,3) and every CELL_DATA field."""
    tokens = Path(path).read_text().split()
    out: dict[str, np.ndarray] = {}
    try:
        k = tokens.index("POINTS")
        n = int(tokens[k + 1])
        out["points"] = np.array(tokens[k + 3: k + 3 + 3 * n], dtype=float).reshape(n, 3)
        k = tokens.index("CELL_DATA")
        cells = int(tokens[k + 1])
        k = tokens.index("FieldData", k)
        fields = int(tokens[k + 1])
        k += 2
        for _ in range(fields):
            name, width, count = tokens[k], int(tokens[k + 1]), int(tokens[k + 2])
            values = np.array(tokens[k + 4: k + 4 + width * count], dtype=float)
            out[name] = values.reshape(count, width) if width > 1 else values
            k += 4 + width * count
    except (ValueError, IndexError) as exc:
        raise ReadError(f"cannot read {path}: {exc}") from None
    if cells and any(len(v) != cells for name, v in out.items() if name != "points"):
        raise ReadError(f"{path} is cut off")
    return out


def face_forces(cells: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """(mesh face index, |force| N) per cell of a mesh dump: area x sqrt(sigma_n^2 + sigma_t^2)."""
    force = cells["area"] * np.hypot(cells["normal_stress_average"], cells["shear_stress_average"])
    return cells["meshid"].astype(np.int64), force


def read_drag_output(scene, workdir: Path) -> Result:
    """Parse output/ of a drag-finishing LIGGGHTS run, complete or partial."""
    from ..runner import LOG_NAME
    from ..scene.build import settling_timestep

    workdir = Path(workdir)
    out = workdir / "output"
    case = scene.case
    result = Result()
    status = read_status(out / "status.txt")
    log = (workdir / LOG_NAME).read_text(errors="replace") if (workdir / LOG_NAME).is_file() else ""
    error = engine_error(log)
    dt, dt_settle = scene.timestep, settling_timestep(case)
    stiffen_step = int(float(status.get("stiffen_start_step", -1)))
    process_start = float(status.get("process_start_time", -1))
    process_start = process_start if process_start >= 0 else math.nan

    def time_of(step: int) -> float:
        if stiffen_step < 0 or step <= stiffen_step:
            return step * dt_settle
        return stiffen_step * dt_settle + (step - stiffen_step) * dt

    cols = read_table(out / "series.txt", key="step")
    if cols and len(cols["step"]):
        _fill_series(result, cols, process_start, case.angular_velocity)
    last_step = max(int(cols["step"][-1]) if cols and len(cols["step"]) else 0, int(float(status.get("step", 0))))
    bed = float(status.get("bed_height", -1))
    result.attrs.update(
        n_steps=last_step, dt=dt, simulated_time=time_of(last_step),
        last_phase=status.get("phase", "settle"), bed_height=bed if bed > 0 else math.nan,
        settled=status.get("settled", "0").strip() in ("1", "1.0"), process_start_time=process_start)
    if "Lost atoms" in error:
        result.status = "unstable"
        result.message = (f"a ball left the bowl (LIGGGHTS: {error}): contacts were too stiff for the time step or "
                          "a mesh let it through; lower numerics.timestep_factor")
    elif error:
        result.status, result.message = "failed", f"LIGGGHTS stopped with an error: {error}"
    elif status.get("status") != "ok":
        result.status = "failed"
        result.message = f"the engine was stopped in phase {status.get('phase', 'settle')} (no final status)"
    _read_networks(result, scene, out, time_of, process_start)
    for name in ("settled", "final"):
        frame = _read_frame(out / f"{name}.dump", time_of)
        if frame is not None:
            result.frames.append(frame)
    result.frames.sort(key=lambda item: item[0])
    result.meshes = _read_meshes(scene, out, cols)
    result.attrs["deviation"] = DEVIATION
    return result


def _fill_series(result: Result, cols: dict[str, np.ndarray], process_start: float, omega: float) -> None:
    time = cols["time"]
    phase = cols["phase"].astype(np.int8)
    rod = np.column_stack([cols["rod_fx"], cols["rod_fy"], cols["rod_fz"]])
    workpiece = np.full_like(rod, np.nan)
    process = phase == 3
    if np.isfinite(process_start):
        theta = omega * (time[process] - process_start)  # the rod starts at angle 0 (+x)
        along = np.column_stack([-np.sin(theta), np.cos(theta)])
        outward = np.column_stack([np.cos(theta), np.sin(theta)])
        workpiece[process, 0] = np.einsum("ij,ij->i", rod[process, :2], along)
        workpiece[process, 1] = np.einsum("ij,ij->i", rod[process, :2], outward)
        workpiece[process, 2] = rod[process, 2]
    result.time = time
    result.series = {
        "phase": Series(phase, "-", "0 settle, 1 insert, 2 relax, 3 process"),
        "workpiece_force": Series(workpiece, "N", "force of the media on the rod in the workpiece frame: [along the "
                                  "rod's velocity, horizontal outward (radial), vertical]; NaN before the process "
                                  "phase"),
        "rod_force": Series(rod, "N", "force on the rod, global frame"),
        "bowl_force": Series(np.column_stack([cols["bowl_fx"], cols["bowl_fy"], cols["bowl_fz"]]), "N",
                             "force on the bowl, global frame"),
        "kinetic_energy": Series(cols["kinetic_energy"], "J", "translational kinetic energy of the balls"),
        "unbalanced_force": Series(cols["unbalanced_force"], "-", "mean resultant force on a ball over the mean "
                                   "contact normal force"),
        "n_contacts": Series(np.rint(cols["n_contacts"]).astype(np.int64), "-", "ball-ball and ball-wall contacts"),
        "rod_tip_z": Series(cols["rod_tip_z"], "m", "height of the rod tip above the floor"),
    }


def _read_frame(path: Path, time_of) -> tuple[float, dict[str, np.ndarray]] | None:
    snapshots = read_dump(path)
    if not snapshots:
        return None
    step, columns, rows = snapshots[-1]
    col = {name: rows[:, k] for k, name in enumerate(columns)}
    return time_of(step), {
        "positions": np.column_stack([col["x"], col["y"], col["z"]]),
        "velocities": np.column_stack([col["vx"], col["vy"], col["vz"]]),
        "radii": col["radius"],
    }


def _read_networks(result: Result, scene, out: Path, time_of, process_start: float) -> None:
    n_balls = scene.n_particles
    n_bowl = len(scene.meshes["bowl"].mesh.faces)
    for k in range(len(scene.case.output.network_times)):
        pairs, walls = read_dump(out / f"network_{k}_pairs.dump"), read_dump(out / f"network_{k}_walls.dump")
        if not pairs or not walls:
            break
        step = pairs[-1][0]
        blocks = []
        for (_, _, rows), is_wall in ((pairs[-1], False), (walls[-1], True)):
            col = {name: rows[:, i] for i, name in enumerate(NETWORK_COLUMNS)}
            a = np.column_stack([col["x1"], col["y1"], col["z1"]])
            b = np.column_stack([col["x2"], col["y2"], col["z2"]])
            force = {key: np.column_stack([col[key + c] for c in "xyz"]) for key in ("fn", "ft")}
            if is_wall:  # (contact point, ball) with the force on the ball
                ball, point1, point2 = col["id3"].astype(np.int64) - 1, b, a
                other = n_balls + col["id2"].astype(np.int64) + np.where(col["id1"] > 0, n_bowl, 0)
                role = np.where(col["id1"] > 0, 2, 1).astype(np.int8)
            else:  # (ball i, ball j) with the force on i
                ball, point1, point2 = col["id1"].astype(np.int64) - 1, a, b
                other, role = col["id2"].astype(np.int64) - 1, np.zeros(len(rows), np.int8)
            branch = point2 - point1
            unit = branch / np.maximum(np.linalg.norm(branch, axis=1), 1e-300)[:, None]
            blocks.append({"id1": ball, "id2": other, "normal_force": -np.einsum("ij,ij->i", force["fn"], unit),
                           "normal_force_vector": -force["fn"], "tangential_force": -force["ft"], "branch": branch,
                           "point1": point1, "point2": point2, "body2_role": role})
        merged = {key: np.concatenate([blk[key] for blk in blocks]) for key in blocks[0]}
        merged["process_time"] = np.float64(time_of(step) - process_start)
        result.contacts.append((time_of(step), merged))
        frame = _read_frame(out / f"frame_{k}.dump", time_of)
        if frame is not None:
            result.frames.append(frame)


def _read_meshes(scene, out: Path, cols: dict[str, np.ndarray]) -> dict[str, dict[str, np.ndarray]]:
    """The bowl, and the rod at its final place with the contact intensity per face (sum of |F| x record
    interval from the insertion on, N s) and the number of records in contact."""
    bowl = scene.meshes["bowl"].mesh
    rod = scene.meshes["rod"].mesh
    faces = np.asarray(rod.faces)
    entry = {"vertices": np.asarray(rod.vertices, dtype=float).copy(), "faces": faces}
    intensity = np.zeros(len(faces))
    count = np.zeros(len(faces), dtype=np.int64)
    steps = np.asarray(cols.get("step", np.zeros(0)), dtype=np.int64)
    times = cols.get("time", np.zeros(0))
    files = sorted(out.glob("rod_[0-9]*.vtk"), key=lambda p: int(p.stem.split("_")[1]))
    for path in files:
        step = int(path.stem.split("_")[1])
        row = np.searchsorted(steps, step)
        if row == 0 or row >= len(steps) or steps[row] != step:
            continue  # not a recorded step (a cut-off series)
        face, force = face_forces(read_vtk_cells(path))
        intensity[face] += force * (times[row] - times[row - 1])
        count[face[force > 0]] += 1
    if files:
        entry["contact_intensity"], entry["contact_count"] = intensity, count
    final = out / "rod_final.vtk"
    if final.is_file():
        cells = read_vtk_cells(final)
        soup = cells["points"].reshape(-1, 3, 3)[np.argsort(cells["meshid"].astype(np.int64))]
        entry["vertices"][faces.ravel()] = soup.reshape(-1, 3)
    return {"bowl": {"vertices": np.asarray(bowl.vertices), "faces": np.asarray(bowl.faces)}, "rod": entry}
