"""SPH backend: our engines/sph executable, run as ``sph deck.json``.

Profile: the executable is $ORCHESTRATOR_SPH, else <repo>/engines/sph/build/sph
(a source checkout after ``make sph``), else ``sph`` on PATH; its version
comes from ``sph --version``.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from functools import cached_property
from pathlib import Path

import numpy as np

from ..errors import OrchestratorError
from ..templating import render
from .base import ExecutableBackend, Result, Series

TEMPLATE = "sph/deck.json.j2"
DECK = "deck.json"
OUTPUT = "out.h5"
#: libgomp spin iterations before an idle thread sleeps, with numerics.thread_wait = "spin" (-): 10^4
#: measured best on 2 cores (2D dam break, 2 threads over 1: 10^3 1.70, 10^4 1.90, 10^5 1.69).
SPIN_COUNT = "10000"
#: Wall-time interval of the engine's PROGRESS lines, s.
PROGRESS_INTERVAL_S = 1.0

#: The executable built in a source checkout by `make sph`.
BUILT_EXECUTABLE = Path(__file__).resolve().parent.parent.parent / "engines" / "sph" / "build" / "sph"


class SphProfile:
    """Where the sph executable is on this machine and how to start it."""

    def __init__(self, executable: str | None = None, threads: int = 1, thread_wait: str = "passive"):
        self.executable = executable or os.environ.get("ORCHESTRATOR_SPH") or _default_executable()
        self.threads = threads
        self.thread_wait = thread_wait

    @cached_property
    def version(self) -> str:
        """The executable's version, e.g. 'sph 0.1.0' -> '0.1.0' ('unknown' when it cannot say)."""
        if not self.executable:
            return "unknown"
        try:
            out = subprocess.run([self.executable, "--version"], capture_output=True, text=True, timeout=30)
        except (OSError, subprocess.TimeoutExpired):
            return "unknown"
        words = (out.stdout or out.stderr).split()
        return words[-1] if words else "unknown"

    def environment(self) -> dict[str, str]:
        """Environment of a run: its threads and how idle threads wait (numerics.thread_wait).

        passive: OMP_WAIT_POLICY=PASSIVE (sleep at once; the machine may be shared). spin:
        OMP_WAIT_POLICY=ACTIVE with GOMP_SPINCOUNT=SPIN_COUNT, a bounded spin (about 10 us) before
        sleeping, for cores of its own. The executable reads the policy too (its light loops stay
        serial on small scenes under passive waiting).
        """
        if self.thread_wait == "spin":
            return {"OMP_NUM_THREADS": str(self.threads), "OMP_WAIT_POLICY": "ACTIVE", "GOMP_SPINCOUNT": SPIN_COUNT}
        return {"OMP_NUM_THREADS": str(self.threads), "OMP_WAIT_POLICY": "PASSIVE"}


def _default_executable() -> str | None:
    if BUILT_EXECUTABLE.is_file():
        return str(BUILT_EXECUTABLE)
    return shutil.which("sph")


class SphBackend(ExecutableBackend):
    """Template (templates/sph/deck.json.j2 and HDF5 inputs) plus profile (SphProfile)."""

    name = "sph"
    case_kinds = ("sph_flow",)
    label, env_var = "the sph executable", "ORCHESTRATOR_SPH"
    not_found = f"neither {BUILT_EXECUTABLE} nor 'sph' on PATH"
    templates = {"sph_flow": TEMPLATE}

    def __init__(self, executable: str | None = None, threads: int = 1):
        self.profile = SphProfile(executable, threads)

    def version(self) -> str:
        return self.profile.version

    def install_hint(self) -> str:
        return "build it with 'make sph' (needs g++, cmake, libeigen3-dev, libhdf5-dev, nlohmann-json3-dev)"


    def check_scene(self, scene) -> None:
        """Raise OrchestratorError (exit 2) for a scene that is not an SPH flow."""
        kind = scene.case.case.kind
        if kind not in self.case_kinds:
            from . import engines_for_kind

            raise OrchestratorError(f"the sph engine runs {', '.join(self.case_kinds)} cases, not {kind} cases; "
                                    f"use --engine {' or '.join(engines_for_kind(kind)) or 'another engine'}")

    # ---- input ----
    def render_context(self, scene) -> dict:
        """Deck values, each JSON-encoded (numbers as repr, vectors as lists), SI units."""
        return deck_context(scene, threads=self.profile.threads)

    def write_input(self, scene, workdir: Path) -> None:
        workdir = Path(workdir)
        self.profile.thread_wait = scene.case.numerics.thread_wait  # the environment of command()
        write_particles(scene, workdir / "particles.h5")
        if scene.meshes:
            write_meshes(scene, workdir / "meshes.h5")
        (workdir / DECK).write_text(render(TEMPLATE, self.render_context(scene)))

    def command(self, workdir: Path) -> tuple[list[str], dict[str, str]]:
        return [self.profile.executable or "sph", DECK], self.profile.environment()

    # ---- output ----
    def read_output(self, scene, workdir: Path) -> Result:
        return read_sph_output(Path(workdir), scene)


def deck_context(scene, threads: int = 1) -> dict:
    """The template's values for a scene: numbers via repr, lists and texts via json (SI units)."""
    case = scene.case
    fluid, physics, numerics, output = case.fluid, case.physics, case.numerics, case.output
    num = repr
    vec = lambda values: json.dumps([float(v) for v in values])  # noqa: E731
    periodic = None
    if case.domain.periodic:
        axes = list(case.domain.periodic)
        periodic = {"axes": json.dumps(axes), "lo": vec(case.domain.lo[a] for a in axes),
                    "hi": vec(case.domain.hi[a] for a in axes)}
    av = physics.artificial_viscosity
    wall = physics.wall_penalty
    return {
        "dimension": case.dimension,
        "physics": json.dumps(list(scene.physics)),
        "rho0": num(fluid.density),
        "c0": num(scene.c0),
        "v_max": num(fluid.max_speed),
        "gamma": num(fluid.gamma),
        "background_pressure": num(fluid.background_pressure),
        "h": num(scene.h),
        "dx": num(numerics.dx),
        "viscosity": None if fluid.viscosity is None else num(fluid.viscosity),
        "alpha": None if av is None else num(av.alpha),
        "beta": None if av is None else num(av.beta),
        "body_force": None if physics.body_force is None else vec(physics.body_force),
        "meshes": [{"name": json.dumps(name), "group": json.dumps("/" + name)} for name in scene.meshes],
        "wall": None if wall is None else {"range": num(wall.range), "s": num(wall.s), "psi": num(wall.psi)},
        "periodic": periodic,
        "inlets": [_patch_json(p, velocity=p.velocity, layers=p.layers) for p in case.inlets],
        "outlets": [_patch_json(p, layers=p.layers) for p in case.outlets],
        "dt": None if numerics.dt is None else num(numerics.dt),
        "time_step": {k: num(v) for k, v in numerics.adaptive.items()},
        "max_steps": numerics.max_steps,
        "max_density_deviation": num(numerics.max_density_deviation),
        "t_end": num(case.simulation.duration),
        "threads": int(threads),
        "frame_interval": num(output.frame_interval),
        "series_interval": num(output.series_interval or output.frame_interval),
        "progress_interval": num(PROGRESS_INTERVAL_S),
        "probes": [json.dumps({"name": p.name, "point": [float(c) for c in p.point]}) for p in output.probes],
        "flow_planes": [_patch_json(p) for p in output.flow_planes],
    }


def _patch_json(patch, **extra) -> str:
    """A disc or rectangle patch (flow plane, inlet, outlet) as the deck's JSON object."""
    item = {"name": patch.name, "center": [float(c) for c in patch.center],
            "normal": [float(c) for c in patch.normal]}
    if patch.radius is not None:
        item["radius"] = float(patch.radius)
    else:
        if patch.u is not None:
            item["u"] = [float(c) for c in patch.u]
        item["half_extents"] = [float(c) for c in patch.half_extents]
    item.update({k: (float(v) if isinstance(v, float) else v) for k, v in extra.items()})
    return json.dumps(item)


def write_particles(scene, path: Path) -> None:
    """The particle input file: positions (n,D) m, velocities (n,D) m/s, masses (n) kg, densities (n)
    kg/m^3, kind (n) int8 (0 fluid, 1 fixed boundary)."""
    import h5py

    with h5py.File(path, "w") as h5:
        h5["positions"] = np.asarray(scene.positions, dtype=np.float64)
        h5["velocities"] = np.asarray(scene.velocities, dtype=np.float64)
        h5["masses"] = np.asarray(scene.masses, dtype=np.float64)
        h5["densities"] = np.asarray(scene.densities, dtype=np.float64)
        h5["kind"] = np.asarray(scene.kind, dtype=np.int8)


def write_meshes(scene, path: Path) -> None:
    """The wall meshes: one group /<name> per wall with vertices (nv,D) m and faces (nf,D) int64."""
    import h5py

    with h5py.File(path, "w") as h5:
        for name, mesh in scene.meshes.items():
            group = h5.create_group(name)
            group["vertices"] = np.asarray(mesh.vertices, dtype=np.float64)
            group["faces"] = np.asarray(mesh.faces, dtype=np.int64)


#: Descriptions of the series the executable writes (by name or prefix).
SERIES_DESCRIPTIONS = {
    "pressure_probe_": "Shepard-normalised kernel interpolation of the fluid pressure at the probe "
                       "(NaN when no fluid within 2h)",
    "flow_rate_": "fluid volume crossing the patch along its normal per unit time, since the last record",
    "inflow_": "fluid volume added by the inlet per unit time",
    "outflow_": "fluid volume removed by the outlet per unit time",
    "wall_force_": "penalty force of the fluid on the wall mesh (eq. 14)",
    "kinetic_energy": "kinetic energy of the fluid",
    "max_density_deviation": "max |rho/rho0 - 1| over the fluid",
}
#: Root attributes of out.h5 copied into run.h5 (engine name -> run.h5 name).
ENGINE_ATTRS = {"n_steps": "n_steps", "dt_mean": "dt", "t_final": "simulated_time", "wall_time_s": "engine_wall_time_s",
                "particle_steps_per_s": "particle_steps_per_s", "physics": "physics", "h": "h", "dx": "dx",
                "dimension": "dimension", "last_good_frame": "last_good_frame"}
FRAME_ARRAYS = ("ids", "kind", "positions", "velocities", "densities", "pressures")


def read_sph_output(workdir: Path, scene=None) -> Result:
    """Parse out.h5 of a run (complete, partial or missing) into a Result; meshes from the scene."""
    import h5py

    from ..runh5 import _plain

    result = Result()
    path = Path(workdir) / OUTPUT
    if scene is not None:
        result.meshes = {name: {"vertices": np.asarray(m.vertices), "faces": np.asarray(m.faces)}
                         for name, m in scene.meshes.items()}
    if not path.is_file():
        result.status = "failed"
        result.message = _engine_error(workdir) or f"the engine wrote no {OUTPUT}"
        return result
    try:
        with h5py.File(path, "r") as h5:
            attrs = {k: _plain(v) for k, v in h5.attrs.items()}
            result.attrs.update({ENGINE_ATTRS[k]: v for k, v in attrs.items() if k in ENGINE_ATTRS})
            series = h5.get("series", {})
            if "time" in series:
                result.time = np.asarray(series["time"][()], dtype=float)
            for name in series:
                if name == "time":
                    continue
                ds = series[name]
                description = next((text for key, text in SERIES_DESCRIPTIONS.items() if name.startswith(key)), "")
                result.series[name] = Series(np.asarray(ds[()]), _plain(ds.attrs.get("units", "")), description)
            frames = h5.get("frames", {})
            for key in sorted(frames, key=int):
                group = frames[key]
                if not all(name in group for name in FRAME_ARRAYS):
                    break  # a frame cut off while it was written
                arrays = {name: np.asarray(group[name][()]) for name in FRAME_ARRAYS}
                arrays["step"] = np.int64(group.attrs.get("step", -1))
                result.frames.append((float(group.attrs["time"]), arrays))
    except (OSError, KeyError, ValueError) as exc:
        result.status = "failed"
        result.message = f"cannot read {path}: {exc}"
        return result
    status = attrs.get("status", "running")
    message = attrs.get("message", "")
    if status == "ok":
        result.status, result.message = "ok", message
    elif status == "unstable":
        result.status, result.message = "unstable", message
    elif status == "terminated":
        result.status, result.message = "failed", message or "stopped by a signal"
    else:
        result.status = "failed"
        result.message = _engine_error(workdir) or "the engine ended without finishing (status 'running' in out.h5)"
    return result


def _engine_error(workdir: Path) -> str:
    """The engine's last 'error: ...' line in the run's log, without the prefix ('' if none)."""
    from ..runner import LOG_NAME, tail

    lines = [line for line in tail(Path(workdir) / LOG_NAME, 200).splitlines() if line.startswith("error: ")]
    return lines[-1].removeprefix("error: ") if lines else ""
