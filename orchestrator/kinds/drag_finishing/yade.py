"""Yade runs drag-finishing cases: the script template, its values and the output parser (engines.yade starts Yade)."""

from __future__ import annotations

import json
import math
import zipfile
from pathlib import Path

import numpy as np

from orchestrator.engines.base import Result, Series
from orchestrator.errors import OrchestratorError, ReadError
from orchestrator.kinds.base import Adapter
from orchestrator.kinds.drag_finishing.impacts import ENGINE_COLUMNS, attach_impacts, impact_rows, template_values
from orchestrator.kinds.drag_finishing.schedule import schedule
from orchestrator.templating import render

TEMPLATE = Path(__file__).resolve().parent / "templates" / "yade.py.j2"
SCRIPT = "drag_finishing.py"


class YadeDragFinishing(Adapter):
    """The drag-finishing scene as a Yade script (templates/yade.py.j2) with the scene in scene.npz and STL meshes."""

    engine = "yade"
    templates = (TEMPLATE,)

    def check_scene(self, profile, scene) -> None:
        """Refuse an impact window on a rod that is not a regular prism (impacts.template_values)."""
        template_values(scene)

    def write_input(self, profile, scene, workdir: Path) -> None:
        arrays = {"positions": scene.positions, "radii": scene.radii}
        for name, part in scene.meshes.items():
            arrays[f"{name}_vertices"] = np.asarray(part.mesh.vertices, dtype=float)
            arrays[f"{name}_faces"] = np.asarray(part.mesh.faces, dtype=np.int64)
        np.savez(workdir / "scene.npz", **arrays)
        scene.write_meshes(workdir)
        (workdir / SCRIPT).write_text(render(TEMPLATE, render_context(scene)))

    def command(self, profile, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        return profile.run_command(SCRIPT, workdir)

    def resume_input(self, profile, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        """Command that continues a stopped run from its last checkpoint (output/checkpoint.json, written with
        output.checkpoint_interval): the same script with --resume, after the series rows recorded after the
        checkpoint are dropped."""
        path = workdir / "output" / "checkpoint.json"
        try:
            point = json.loads(path.read_text())
            step = int(point["step"])
            saved = workdir / point["scene"]
        except (OSError, ValueError, KeyError, TypeError):
            raise OrchestratorError(
                f"{workdir} holds no readable checkpoint ({path.relative_to(workdir)}): the run wrote none (set "
                "output.checkpoint_interval) or stopped before the first one; run it again instead") from None
        if point["scene"] not in ("output/checkpoint_0.yade.gz", "output/checkpoint_1.yade.gz") or not saved.is_file():
            raise OrchestratorError(f"{path} names no saved scene of this run; run the case again instead")
        for name in ("series.csv", "impacts.csv"):
            drop_rows_after(workdir / "output" / name, step)
        command, env = self.command(profile, scene, workdir)
        return command + ["--resume"], env

    def planned_steps(self, profile, scene) -> int:
        """Upper bound of the run's time steps (settling counted at its maximum time)."""
        return render_context(scene)["planned_steps"]

    def probe_command(self, profile, scene, workdir: Path, steps: int = 200):
        """The same script on a dense lattice for a few steps."""
        command, env = self.command(profile, scene, workdir)
        return command + ["--probe", str(steps)], env

    def read_output(self, profile, scene, workdir: Path) -> Result:
        return read_drag_finishing_output(scene, workdir)


def render_context(scene) -> dict:
    """Plain values the template needs (SI units)."""
    case = scene.case
    scale = case.numerics.stiffness_scale
    soft = case.settling_stiffness_scale
    materials = [
        {
            "name": name,
            "young": repr(m.young_modulus * soft),
            "poisson": repr(m.poisson_ratio),
            "density": repr(m.density),
            # Per-pair friction comes from the contacts table; this is only Yade's fallback.
            "friction_angle": repr(math.atan(max(c.friction for c in case.contacts))),
        }
        for name, m in sorted(case.materials.items())
    ]
    pairs = case.touching_pairs()
    # ascii(): a Python literal of the names whatever they hold (escapes beyond ASCII too)
    rows = lambda value: ascii(tuple((a, b, value(case.contact(a, b))) for a, b in pairs))  # noqa: E731
    plan = schedule(scene)
    dt, dt_settle, stiffen = plan.dt, plan.dt_settle, plan.stiffen
    return {
        "stiffness_scale": repr(scale),
        "settling_stiffness_scale": repr(soft),
        "stiffen": stiffen,
        "stiffen_factor": repr(scale / soft),
        "stiffen_time": repr(case.settling.stiffen_time),
        "dt_settle": repr(dt_settle),
        "control_every_settle": plan.control_every_settle,
        "record_every_settle": plan.record_every_settle,
        "materials": materials,
        "pairs_en": rows(lambda c: c.restitution),
        "pairs_es": rows(lambda c: c.e_t),
        "pairs_friction_angle": rows(lambda c: math.atan(c.friction)),
        "media_material": case.media.material,
        "bowl_material": case.bowl.material,
        "rod_material": case.workpiece.material,
        "insertion_speed": repr(case.workpiece.insertion_speed),
        "angular_velocity": repr(case.angular_velocity),
        "settling_damping": repr(case.settling.damping),
        "gravity": repr((0.0, 0.0, -9.81)),
        "control_every": plan.control_every,
        "record_every": plan.record_every,
        "dt": repr(dt),
        "settle_max_time": repr(case.settling.max_time),
        "settle_unbalanced": repr(case.settling.unbalanced_force),
        "settle_max_speed": repr(case.settling.max_speed),
        "relax_time": repr(case.settling.relax_time),
        "submersion_depth": repr(case.workpiece.submersion_depth),
        "path_radius": repr(case.workpiece.path_radius),
        "process_duration": repr(case.process.duration),
        "network_times": repr(list(case.output.network_times)),
        "checkpoint_interval": repr(case.output.checkpoint_interval),
        **template_values(scene),
        "bowl_radius": repr(case.bowl.inner_radius),
        "bowl_height": repr(case.bowl.height),
        "planned_steps": plan.planned_steps,
    }


def _load_npz(path: Path) -> dict[str, np.ndarray]:
    try:
        with np.load(path) as data:
            return {k: data[k] for k in data.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile) as exc:
        raise ReadError(f"cannot read {path}: {exc}") from None


def _load_npz_written(path: Path) -> dict[str, np.ndarray] | None:
    """_load_npz, or None for the newest .npz of its directory when it cannot be read: the file Yade was writing
    when a timeout or a signal stopped it (a truncated zip); the data recorded before it is kept. Any other
    unreadable file is a ReadError."""
    try:
        return _load_npz(path)
    except ReadError:
        newest = max(path.parent.glob("*.npz"), key=lambda p: p.stat().st_mtime_ns)
        if newest == path:
            return None
        raise


def drop_rows_after(path: Path, step: int) -> None:
    """Keep the header and the whole rows of a series.csv or impacts.csv recorded at or before step (its last
    column). A stopped script leaves a row cut where its file buffer ended; the cut can fall after an integer field
    (a contact count, a prefix of the step), so a row counts only with its newline and the header's field count:
    kept, the resumed run's first row would be glued onto it."""
    lines = path.read_text().splitlines(keepends=True) if path.is_file() else []
    fields = lines[0].count(",") if lines else 0
    kept = lines[:1] + [line for line in lines[1:] if line.endswith("\n") and line.count(",") == fields
                        and line.strip().split(",")[-1].isdigit() and int(line.strip().split(",")[-1]) <= step]
    path.write_text("".join(kept))


def read_series_csv(path: Path) -> dict[str, np.ndarray]:
    """The template's series.csv as column name -> array (a cut-off last line is dropped)."""
    lines = path.read_text().splitlines()
    if not lines:
        raise ReadError(f"{path} is empty")
    header = lines[0].split(",")
    rows = [line.split(",") for line in lines[1:] if line.count(",") == len(header) - 1]
    data = np.array(rows, dtype=float).reshape(-1, len(header))
    return {name: data[:, i] for i, name in enumerate(header)}


def read_drag_finishing_output(scene, workdir: Path) -> Result:
    """Parse output/ of a drag-finishing Yade run, complete or partial."""
    out = workdir / "output"
    result = Result()
    _read_status(result, out / "status.json")
    if (out / "series.csv").is_file():
        _read_series(result, out / "series.csv")
    _read_networks_and_frames(result, out, len(scene.case.output.network_times))
    final = _load_npz_written(out / "final.npz") if (out / "final.npz").is_file() else None
    _read_meshes(result, scene, final)
    impacts = out / "impacts.csv"
    if impacts.is_file() and (out / "final.npz").is_file():  # the rod's pose is known at the end only
        cols = read_series_csv(impacts)
        raw = impact_rows(np.column_stack([cols[name] for name in ENGINE_COLUMNS]))
        raw["time"] = cols["time"]
        attach_impacts(result, raw, scene.case.angular_velocity, float(final["time"]))
    return result


def _read_status(result: Result, status_path: Path) -> None:
    """Result.status, message and the run's attributes from status.json ("failed" without one)."""
    if not status_path.is_file():
        result.status = "failed"
        result.message = "the engine wrote no status (it was stopped or crashed)"
        return
    status = json.loads(status_path.read_text())
    result.status = status["status"]
    result.message = status["message"]
    result.attrs.update(
        n_steps=int(status["n_steps"]),
        dt=float(status["dt"]),
        simulated_time=float(status["time"]),
        last_phase=status["phase"],
        bed_height=float("nan") if status["bed_height"] is None else float(status["bed_height"]),
        settled=bool(status["settled"]),
        process_start_time=float("nan") if status["process_start_time"] is None else status["process_start_time"],
        engine_wall_time_s=float(status["wall_time_s"]),
    )


def _read_series(result: Result, series_path: Path) -> None:
    """Result.time and Result.series from series.csv."""
    cols = read_series_csv(series_path)
    if "step" in cols and len(cols["step"]) and "n_steps" not in result.attrs:
        result.attrs["n_steps"] = int(cols["step"][-1])  # a stopped run: its last recorded step
    result.time = cols["time"]
    stack = lambda *names: np.column_stack([cols[n] for n in names])  # noqa: E731
    result.series = {
        "phase": Series(cols["phase"].astype(np.int8), "-", "0 settle, 1 insert, 2 relax, 3 process"),
        "workpiece_force": Series(
            stack("wf_normal", "wf_tangential", "wf_vertical"),
            "N",
            "force of the media on the rod in the workpiece frame: [along the rod's velocity, "
            "horizontal outward (radial), vertical]; NaN before the process phase",
        ),
        "rod_force": Series(stack("rod_fx", "rod_fy", "rod_fz"), "N", "force on the rod, global frame"),
        "bowl_force": Series(stack("bowl_fx", "bowl_fy", "bowl_fz"), "N", "force on the bowl, global frame"),
        "kinetic_energy": Series(cols["kinetic_energy"], "J", "translational kinetic energy of the balls"),
        "unbalanced_force": Series(cols["unbalanced_force"], "-", "Yade's unbalanced-force ratio"),
        "n_contacts": Series(cols["n_contacts"].astype(np.int64), "-", "real interactions"),
        "rod_tip_z": Series(cols["rod_tip_z"], "m", "height of the rod tip above the floor"),
    }


def _read_networks_and_frames(result: Result, out: Path, n_networks: int) -> None:
    """Result.contacts from network_<k>.npz, Result.frames from frame_<k>.npz, settled.npz and final.npz (by time);
    the networks stop at the first one missing or cut off."""
    for k in range(n_networks):
        path = out / f"network_{k}.npz"
        if not path.is_file():
            break
        net = _load_npz_written(path)
        if net is None:
            break
        result.contacts.append((float(net["time"]), {
            "id1": net["id1"],
            "id2": net["id2"],
            "normal_force": net["normal_force"],
            "normal_force_vector": net["normal_force_vector"],
            "tangential_force": net["tangential_force"],
            "branch": net["point2"] - net["point1"],
            "point1": net["point1"],
            "point2": net["point2"],
            "body2_role": net["body2_role"],
            "process_time": np.float64(net["process_time"]),
        }))
        frame = out / f"frame_{k}.npz"
        data = _load_npz_written(frame) if frame.is_file() else None
        if data is not None:
            result.frames.append(_frame(data))
    for name in ("settled.npz", "final.npz"):
        data = _load_npz_written(out / name) if (out / name).is_file() else None
        if data is not None:
            result.frames.append(_frame(data))
    result.frames.sort(key=lambda item: item[0])


def _read_meshes(result: Result, scene, final) -> None:
    """Result.meshes: the bowl, and the rod in its final pose with its per-face contact intensity (from final.npz,
    when the run got there)."""
    bowl = scene.meshes["bowl"].mesh
    result.meshes["bowl"] = {"vertices": np.asarray(bowl.vertices), "faces": np.asarray(bowl.faces)}
    rod = scene.meshes["rod"].mesh
    rod_entry = {"vertices": np.asarray(rod.vertices, dtype=float).copy(), "faces": np.asarray(rod.faces)}
    if final is not None:
        soup = final["rod_vertices"]
        rod_entry["vertices"][rod_entry["faces"].ravel()] = soup.reshape(-1, 3)
        rod_entry["contact_intensity"] = final["rod_intensity"]
        rod_entry["contact_count"] = final["rod_contact_count"]
    result.meshes["rod"] = rod_entry


def _frame(data: dict[str, np.ndarray]) -> tuple[float, dict[str, np.ndarray]]:
    return float(data["time"]), {k: data[k] for k in ("positions", "velocities", "radii")}
