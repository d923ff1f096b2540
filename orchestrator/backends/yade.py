"""Yade backend: the drag-finishing and impact scenes as Jinja-rendered Yade scripts.

Profile: Yade is found through its launcher (``yade`` on PATH, or
``$ORCHESTRATOR_YADE``). The script is run by the launcher's own python with
Yade's module directory on PYTHONPATH (Yade's "library mode"): unlike
``yade -n -x script.py`` this opens no TCP ports (the launcher starts a
python prompt on :9000+ and an XMLRPC server on :21000+), so parallel runs
cannot collide, and it starts faster. If the launcher cannot be read, the
backend falls back to ``yade -n -x -j N script.py``.
"""

from __future__ import annotations

import json
import math
import os
import re
import shutil
from functools import cached_property
from pathlib import Path

import numpy as np

from ..errors import OrchestratorError, ReadError
from ..scene.build import settling_timestep
from ..templating import render
from .base import ExecutableBackend, Result, Series

TEMPLATES = {"drag_finishing": "yade/drag_finishing.py.j2", "impact": "yade/impact.py.j2"}
SCRIPT_NAME = {"drag_finishing": "drag_finishing.py", "impact": "impact.py"}


class YadeProfile:
    """Where Yade is on this machine and how to start it."""

    def __init__(self, executable: str | None = None, threads: int = 1):
        self.executable = executable or os.environ.get("ORCHESTRATOR_YADE") or shutil.which("yade")
        self.threads = threads

    @cached_property
    def launcher(self) -> dict:
        """Interpreter, module directory and version read from the launcher script (no engine start)."""
        info = {"python": None, "module_dir": None, "version": None}
        if not self.executable:
            return info
        try:
            text = Path(self.executable).read_text(errors="replace")[:20000]
        except OSError:
            return info
        shebang = text.splitlines()[0] if text else ""
        if shebang.startswith("#!") and "python" in shebang:
            info["python"] = shebang[2:].strip().split()[0]
        m = re.search(r"sys\.path\.insert\(\s*\d+\s*,\s*'([^']+)'\s*\)", text)
        if m and Path(m.group(1)).is_dir():
            info["module_dir"] = m.group(1)
        m = re.search(r"features,version,debugbuild=.*?,\s*'([^']+)'\s*,", text)
        if m:
            info["version"] = m.group(1)
        return info

    def version(self) -> str:
        """Yade's version, e.g. '2023.02a'."""
        if self.launcher["version"]:
            return self.launcher["version"]
        import subprocess

        out = subprocess.run([self.executable, "--version"], capture_output=True, text=True, timeout=60).stdout
        m = re.search(r"Yade version:\s*(\S+)", out)
        return m.group(1) if m else "unknown"

    def command(self, script: str) -> tuple[list[str], dict[str, str]]:
        """Command line and environment that run a Yade script headless."""
        env = {"OMP_NUM_THREADS": str(self.threads), "OMP_WAIT_POLICY": "PASSIVE", "DISPLAY": ""}
        info = self.launcher
        if info["python"] and info["module_dir"] and Path(info["python"]).exists():
            env["PYTHONPATH"] = info["module_dir"]
            return [info["python"], "-u", script], env
        return [self.executable, "-n", "-x", "-j", str(self.threads), script], env


class YadeBackend(ExecutableBackend):
    """Template (Yade scripts under templates/yade/) plus profile (YadeProfile)."""

    name = "yade"
    case_kinds = ("drag_finishing", "impact")
    label, env_var, not_found, templates = "Yade", "ORCHESTRATOR_YADE", "no 'yade' on PATH", TEMPLATES

    def __init__(self, executable: str | None = None, threads: int = 1):
        self.profile = YadeProfile(executable, threads)
        self._kind = "drag_finishing"  # set by write_input; command() runs that kind's script

    def version(self) -> str:
        return self.profile.version()

    def install_hint(self) -> str:
        return "install it with 'sudo apt-get install yade' (Debian 12 / Ubuntu), or run 'make demo'"

    # ---- input ----
    def render_context(self, scene) -> dict:
        """Plain values the template needs (SI units)."""
        if scene.case.case.kind == "impact":
            from .yade_impact import impact_context

            return impact_context(scene)
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
        dt = scene.timestep
        dt_settle = settling_timestep(case)
        stiffen = scale != soft or dt != dt_settle

        def every(interval: float, step: float) -> int:
            return max(1, round(interval / step))

        record_every = every(case.output.record_interval, dt)
        record_every_settle = every(case.output.record_interval, dt_settle)
        settle_steps = case.settling.max_time / dt_settle
        insert_steps = (case.workpiece.submersion_depth + 2 * case.media.radius) / case.workpiece.insertion_speed
        insert_steps /= dt_settle
        relax_steps = case.settling.relax_time / dt_settle
        if stiffen:
            relax_steps += (case.settling.stiffen_time + case.settling.relax_time) / dt
        planned = settle_steps + insert_steps + relax_steps + case.process.duration / dt
        return {
            "stiffness_scale": repr(scale),
            "settling_stiffness_scale": repr(soft),
            "stiffen": stiffen,
            "stiffen_factor": repr(scale / soft),
            "stiffen_time": repr(case.settling.stiffen_time),
            "dt_settle": repr(dt_settle),
            "control_every_settle": min(record_every_settle, every(1e-3, dt_settle)),
            "record_every_settle": record_every_settle,
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
            "control_every": min(record_every, every(1e-3, dt)),
            "record_every": record_every,
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
            "bowl_radius": repr(case.bowl.inner_radius),
            "bowl_height": repr(case.bowl.height),
            "planned_steps": int(planned),
        }

    def write_input(self, scene, workdir: Path) -> None:
        kind = scene.case.case.kind
        self._kind = kind
        workdir = Path(workdir)
        if kind == "impact":
            from .yade_impact import write_impact_input

            write_impact_input(scene, workdir, render(TEMPLATES[kind], self.render_context(scene)))
            return
        arrays = {"positions": scene.positions, "radii": scene.radii}
        for name, part in scene.meshes.items():
            arrays[f"{name}_vertices"] = np.asarray(part.mesh.vertices, dtype=float)
            arrays[f"{name}_faces"] = np.asarray(part.mesh.faces, dtype=np.int64)
        np.savez(workdir / "scene.npz", **arrays)
        scene.write_meshes(workdir)
        (workdir / SCRIPT_NAME[kind]).write_text(render(TEMPLATES[kind], self.render_context(scene)))

    def command(self, workdir: Path, kind: str | None = None) -> tuple[list[str], dict[str, str]]:
        command, env = self.profile.command(SCRIPT_NAME[kind or self._kind])
        # Yade makes a scratch directory per process; keep it inside the run, not in /tmp.
        scratch = Path(workdir) / "tmp"
        scratch.mkdir(exist_ok=True)
        return command, {**env, "TMPDIR": str(scratch.resolve())}

    def resume_input(self, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        """Command that continues a stopped drag-finishing run from its last checkpoint (output/checkpoint.json,
        written with output.checkpoint_interval): the same script with --resume, after the series rows recorded
        after the checkpoint are dropped."""
        if scene.case.case.kind != "drag_finishing":
            raise OrchestratorError(f"only drag-finishing runs resume; this run is of kind {scene.case.case.kind}")
        workdir = Path(workdir)
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
        _drop_rows_after(workdir / "output" / "series.csv", step)
        command, env = self.command(workdir, "drag_finishing")
        return command + ["--resume"], env

    def planned_steps(self, scene) -> int:
        """Upper bound of the run's time steps (settling counted at its maximum time)."""
        if scene.case.case.kind == "impact":
            return 0  # short runs of a few spheres: no timing probe
        return self.render_context(scene)["planned_steps"]

    def probe_command(self, workdir: Path, kind: str = "drag_finishing", steps: int = 200):
        """Command of the timing probe: the same script on a dense lattice for a few steps."""
        command, env = self.command(workdir, kind)
        return command + ["--probe", str(steps)], env

    # ---- output ----
    def read_output(self, scene, workdir: Path) -> Result:
        if scene.case.case.kind == "impact":
            from .yade_impact import read_impact_output, yade_deviations

            result = read_impact_output(scene, Path(workdir))
            if yade_deviations(scene.case):
                result.attrs["deviation"] = yade_deviations(scene.case)
            return result
        return read_drag_finishing_output(scene, Path(workdir))


def _load_npz(path: Path) -> dict[str, np.ndarray]:
    try:
        with np.load(path) as data:
            return {k: data[k] for k in data.files}
    except (OSError, ValueError) as exc:
        raise ReadError(f"cannot read {path}: {exc}") from None


def _drop_rows_after(path: Path, step: int) -> None:
    """Keep the header and the rows of series.csv recorded at or before step (its last column)."""
    lines = path.read_text().splitlines(keepends=True) if path.is_file() else []
    kept = lines[:1] + [line for line in lines[1:] if line.strip().split(",")[-1].isdigit()
                        and int(line.strip().split(",")[-1]) <= step]
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
    status_path = out / "status.json"
    if status_path.is_file():
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
    else:
        result.status = "failed"
        result.message = "the engine wrote no status (it was stopped or crashed)"
    series_path = out / "series.csv"
    if series_path.is_file():
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
    for k in range(len(scene.case.output.network_times)):
        path = out / f"network_{k}.npz"
        if not path.is_file():
            break
        net = _load_npz(path)
        result.contacts.append(
            (
                float(net["time"]),
                {
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
                },
            )
        )
        frame = out / f"frame_{k}.npz"
        if frame.is_file():
            result.frames.append(_frame(_load_npz(frame)))
    for name in ("settled.npz", "final.npz"):
        if (out / name).is_file():
            result.frames.append(_frame(_load_npz(out / name)))
    result.frames.sort(key=lambda item: item[0])
    bowl = scene.meshes["bowl"].mesh
    result.meshes["bowl"] = {"vertices": np.asarray(bowl.vertices), "faces": np.asarray(bowl.faces)}
    rod = scene.meshes["rod"].mesh
    rod_entry = {"vertices": np.asarray(rod.vertices, dtype=float).copy(), "faces": np.asarray(rod.faces)}
    last = out / "final.npz"
    if last.is_file():
        final = _load_npz(last)
        soup = final["rod_vertices"]
        rod_entry["vertices"][rod_entry["faces"].ravel()] = soup.reshape(-1, 3)
        rod_entry["contact_intensity"] = final["rod_intensity"]
        rod_entry["contact_count"] = final["rod_contact_count"]
    result.meshes["rod"] = rod_entry
    return result


def _frame(data: dict[str, np.ndarray]) -> tuple[float, dict[str, np.ndarray]]:
    return float(data["time"]), {k: data[k] for k in ("positions", "velocities", "radii")}
