"""What a LIGGGHTS drag-finishing run wrote into output/, read back into the run.h5 names (liggghts_deck.py writes
the deck)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.engines.base import Result, Series
from orchestrator.engines.liggghts_files import engine_error, read_dump, read_table
from orchestrator.errors import ReadError
from orchestrator.kinds.drag_finishing.impacts import LIGGGHTS_COLUMNS, attach_impacts, impact_rows
from orchestrator.kinds.drag_finishing.liggghts_deck import DEVIATION, NETWORK_COLUMNS
from orchestrator.kinds.drag_finishing.scene import settling_timestep
from orchestrator.runner import LOG_NAME


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
    raw = _read_impacts(out, time_of)
    if raw is not None and (out / "rod_final.vtk").is_file():  # the rod's pose is known at the end only
        attach_impacts(result, raw, case.angular_velocity, result.attrs["simulated_time"])
    result.attrs["deviation"] = DEVIATION
    return result


def _read_impacts(out: Path, time_of) -> dict[str, np.ndarray] | None:
    """The wall contact starts of output/impacts_<chunk>*.dump (impacts.LIGGGHTS_COLUMNS; a step written at the end of
    one chunk and the start of the next counts once), or None without such files."""
    files = sorted(out.glob("impacts_*.dump"), key=lambda p: int(p.stem.split("_")[1]))
    if not files:
        return None
    steps, rows = [], []
    for path in files:
        for step, _, block in read_dump(path):
            steps.append(np.full(len(block), step))
            rows.append(block.reshape(-1, len(LIGGGHTS_COLUMNS)))
    step = np.concatenate(steps).astype(np.int64) if steps else np.zeros(0, np.int64)
    table = np.concatenate(rows) if rows else np.zeros((0, len(LIGGGHTS_COLUMNS)))
    _, keep = np.unique(np.column_stack([step, table[:, 0].astype(np.int64)]), axis=0, return_index=True)
    keep = np.sort(keep)
    raw = impact_rows(table[keep], LIGGGHTS_COLUMNS)
    raw["ball"] = raw["ball"] - 1  # LIGGGHTS ids count from 1
    raw["time"] = np.array([time_of(int(k)) for k in step[keep]])
    return raw


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
