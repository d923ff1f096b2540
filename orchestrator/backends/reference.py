"""The reference backend: our numpy DEM (orchestrator.reference.dem, the
paper's contact law) run like any engine, as ``python -m
orchestrator.backends.reference RUN_DIR`` in its own process (so the
runner's log, timeout and Ctrl-C apply), filling the same run.h5 names as
Yade (series, contact events, status).

It takes impact cases up to dem.MAX_SPHERES spheres whose estimated run
time stays under MAX_WALL_TIME_S; anything bigger (the drag-finishing bowl)
is refused before a run directory is made, with the engine to use instead.

Law as in the reference: Hertz, Mindlin no-slip k_t (eq. 5), Tsuji damping
with c_t = c_n, the normal force never pulling, the Coulomb limit on the
force model.coulomb_limit names; alpha from model.damping ("engine" = eq. 10,
the paper's own).
"""

from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

import numpy as np

from ..humanize import duration
from ..errors import OrchestratorError
from .base import Backend, Result

#: Refuse scenes whose estimated run time is longer than this, s.
MAX_WALL_TIME_S = 3600.0
#: Cost model of dem.simulate measured on this machine: per step, s, and per sphere and step, s.
STEP_COST_S, SPHERE_STEP_COST_S = 160e-6, 0.45e-6


class ReferenceBackend(Backend):
    """The reference DEM as a backend (always installed: it is part of the package)."""

    name = "reference"
    case_kinds = ("impact",)

    def __init__(self, executable: str | None = None, threads: int = 1):
        self.python = executable or sys.executable

    def available(self) -> bool:
        return True

    def version(self) -> str:
        from .. import __version__

        return f"orchestrator-{__version__}"

    def where(self) -> str:
        return str(Path(__file__).resolve().parent.parent / "reference")

    def install_hint(self) -> str:
        return "it is part of the orchestrator package"

    def check_available(self) -> None:
        """Always available."""

    def template_files(self, kind: str) -> list[Path]:
        root = Path(self.where())
        return sorted(root.glob("*.py")) + [Path(__file__).resolve()]

    def check_scene(self, scene) -> None:
        """Raise OrchestratorError (exit 2) for a scene the reference DEM cannot or should not run."""
        from ..reference.dem import MAX_SPHERES

        kind = scene.case.case.kind
        name = scene.case.case.name
        if kind != "impact":
            reason = f"it is a {kind} case"
            if kind == "drag_finishing":
                steps = _drag_finishing_steps(scene)
                estimate = steps * (STEP_COST_S + SPHERE_STEP_COST_S * scene.n_particles)
                size = (f"{scene.n_particles} balls for about {steps / 1e6:.3g} million steps: "
                        f"{duration(estimate)} at the least in numpy")
                reason = (f"it is too big ({size})" if estimate > MAX_WALL_TIME_S else f"it has {size}") + \
                    " and needs a rod turning through the bed, which the reference does not model"
            raise OrchestratorError(
                f"the reference DEM cannot run {name}: {reason}. The reference runs impact cases (up to "
                f"{MAX_SPHERES} spheres, under {duration(MAX_WALL_TIME_S)}). Run it on an engine instead: "
                "--engine yade")
        if scene.n_particles > MAX_SPHERES:
            raise OrchestratorError(
                f"the case {name} has {scene.n_particles} spheres; the reference DEM takes at most {MAX_SPHERES}. "
                "Run it on an engine instead: --engine yade")
        estimate = self.estimated_wall_time(scene)
        if estimate > MAX_WALL_TIME_S:
            raise OrchestratorError(
                f"the case {name} would take the reference DEM about {duration(estimate)} "
                f"({self.estimated_steps(scene):.3g} steps of {scene.n_particles} spheres; limit "
                f"{duration(MAX_WALL_TIME_S)}). Shorten simulation.duration, raise numerics.timestep_factor, or run "
                "it on an engine: --engine yade")

    def estimated_steps(self, scene) -> float:
        """Time steps the run will take, -: every step at dt in dense scenes; a few spheres fly between
        contacts in steps as long as the record interval."""
        if scene.n_particles > 10:
            return scene.duration / scene.timestep
        return scene.duration / scene.record_interval + 2000.0 * scene.n_particles

    def estimated_wall_time(self, scene) -> float:
        """Estimated run time on this machine, s."""
        return self.estimated_steps(scene) * (STEP_COST_S + SPHERE_STEP_COST_S * scene.n_particles)

    def write_input(self, scene, workdir: Path) -> None:
        self.check_scene(scene)
        (Path(workdir) / "reference.json").write_text(json.dumps(scene_description(scene), indent=1))

    def command(self, workdir: Path) -> tuple[list[str], dict[str, str]]:
        return [self.python, "-u", "-m", "orchestrator.backends.reference", "."], {"OMP_NUM_THREADS": "1"}

    def read_output(self, scene, workdir: Path) -> Result:
        from .yade_impact import read_impact_output

        return read_impact_output(scene, Path(workdir))


def _drag_finishing_steps(scene) -> float:
    case = scene.case
    return (case.settling.max_time + case.settling.relax_time + case.process.duration) / scene.timestep


def scene_description(scene) -> dict:
    """Everything dem.simulate needs, as JSON-able plain values (SI units; E = inf for the rigid wall)."""
    from ..scene.impact import energy_scale, poisson_ratio, young_modulus
    from .yade_impact import domain_radius

    case = scene.case
    names = sorted(set(scene.sphere_materials) | ({scene.plane_material} if scene.plane_material else set()))
    index = {name: k for k, name in enumerate(names)}
    materials = [{"young_modulus": young_modulus(case, name), "poisson_ratio": poisson_ratio(case, name),
                  "density": case.materials[name].density if name in case.materials else 1.0} for name in names]
    return {
        "positions": scene.positions.tolist(), "velocities": scene.velocities.tolist(),
        "angular_velocities": scene.angular_velocities.tolist(), "radii": scene.radii.tolist(),
        "sphere_material": [index[m] for m in scene.sphere_materials],
        "materials": materials,
        "pair_table": [[index[p.materials[0]], index[p.materials[1]], p.restitution, p.friction]
                       for p in scene.pairs.values()],
        "alpha": [[index[p.materials[0]], index[p.materials[1]], p.alpha] for p in scene.pairs.values()],
        "plane": None if scene.plane_normal is None else {
            "point": scene.plane_point.tolist(), "normal": scene.plane_normal.tolist(),
            "material": index[scene.plane_material]},
        "gravity": scene.gravity.tolist(),
        "damping": "exact" if case.model.damping == "exact" else "eq10",
        "coulomb_limit": case.model.coulomb_limit,
        "dt": scene.timestep, "t_end": scene.duration, "record_every": scene.record_interval,
        "domain_radius": domain_radius(scene),
        "energy_scale": energy_scale(case),
    }


# ---- the child process: python -m orchestrator.backends.reference RUN_DIR ----

def run_description(workdir: Path) -> int:
    """Run reference.json of workdir; write output/ like the Yade template does. Returns the exit code."""
    from ..analysis.impact import EVENT_LIMIT
    from ..reference.dem import DemBlewUp, Material, Plane, simulate
    from .yade_impact import ENERGY_GROWTH

    workdir = Path(workdir)
    spec = json.loads((workdir / "reference.json").read_text())
    out = workdir / "output"
    out.mkdir(exist_ok=True)
    started = time.perf_counter()
    materials = [Material(m["young_modulus"], m["poisson_ratio"], m["density"]) for m in spec["materials"]]
    planes = [] if spec["plane"] is None else [Plane(spec["plane"]["point"], spec["plane"]["normal"],
                                                     spec["plane"]["material"], name="plane")]
    pairs = {(a, b): (e, mu) for a, b, e, mu in spec["pair_table"]}
    steps_planned = int(math.ceil(spec["t_end"] / spec["dt"]))
    print(f"PROGRESS step=0 of {steps_planned} phase=impact t=0", flush=True)
    status, message = "ok", ""
    try:
        run = simulate(spec["positions"], spec["velocities"], spec["radii"], spec["sphere_material"], materials, pairs,
                       angular_velocities=spec["angular_velocities"], planes=planes, gravity=spec["gravity"],
                       damping=spec["damping"], coulomb_limit=spec["coulomb_limit"], dt=spec["dt"], t_end=spec["t_end"],
                       record_every=spec["record_every"], free_flight_dt_max=spec["record_every"])
    except DemBlewUp as exc:
        run = exc.partial
        status = "unstable"
        message = str(exc).split(":")[0]
    columns = series_columns(spec, run)
    if status == "ok":
        status, message = stability_verdict(spec, columns, ENERGY_GROWTH, spec["domain_radius"])
    np.savez(out / "series.npz", **columns)
    if len(spec["radii"]) <= EVENT_LIMIT:
        np.savez(out / "events.npz", **{name: np.asarray(values, float) for name, values in run["contacts"].items()})
    (out / "status.json").write_text(json.dumps({
        "status": status, "message": message, "n_steps": int(run["steps"]), "dt": spec["dt"],
        "time": float(columns["time"][-1]) if len(columns["time"]) else 0.0,
        "wall_time_s": time.perf_counter() - started}, indent=1))
    print(f"PROGRESS step={steps_planned} of {steps_planned} phase=impact t={spec['t_end']:.6g}", flush=True)
    print(f"STATUS {status} {message}", flush=True)
    return 0 if status == "ok" else 3


def series_columns(spec: dict, run: dict) -> dict[str, np.ndarray]:
    """The recorded states as the named columns of the Yade template (time, energies, forces, per-sphere states)."""
    from ..reference import contact

    positions = np.asarray(run["positions"], float).reshape(len(run["time"]), -1, 3)
    velocities = np.asarray(run["velocities"], float).reshape(positions.shape)
    spins = np.asarray(run["angular_velocities"], float).reshape(positions.shape)
    radii = np.asarray(spec["radii"], float)
    density = np.array([spec["materials"][k]["density"] for k in spec["sphere_material"]])
    masses = density * 4.0 / 3.0 * math.pi * radii**3
    gravity = np.asarray(spec["gravity"], float)
    columns = {"time": np.asarray(run["time"], float), "kinetic_energy": np.asarray(run["kinetic_energy"], float),
               "potential_energy": -np.einsum("s,nsk,k->n", masses, positions, gravity),
               "n_contacts": np.asarray(run["contact_count"], float)}
    wall = np.asarray(run["wall_force"], float).reshape(len(run["time"]), -1, 3)
    wall_force = wall[:, 0, :] if wall.shape[1] else np.zeros((len(run["time"]), 3))
    normal_force = np.zeros(len(run["time"]))
    overlap = np.zeros(len(run["time"]))
    if spec["plane"] is not None:
        n = np.asarray(spec["plane"]["normal"], float)
        normal_force += np.abs(wall_force @ n)
        depth = radii[None, :] - (positions - np.asarray(spec["plane"]["point"], float)) @ n
        overlap = np.maximum(overlap, depth.max(axis=1, initial=0.0))
    alpha = {(a, b): value for a, b, value in spec["alpha"]} | {(b, a): value for a, b, value in spec["alpha"]}
    materials = spec["materials"]
    for i in range(len(radii)):
        for j in range(i + 1, len(radii)):
            branch = positions[:, j] - positions[:, i]
            distance = np.linalg.norm(branch, axis=1)
            depth = radii[i] + radii[j] - distance
            if not np.any(depth > 0):
                continue
            unit = branch / distance[:, None]
            rate = -np.einsum("nk,nk->n", velocities[:, j] - velocities[:, i], unit)
            a, b = spec["sphere_material"][i], spec["sphere_material"][j]
            e_eq = contact.effective_modulus(materials[a]["young_modulus"], materials[a]["poisson_ratio"],
                                             materials[b]["young_modulus"], materials[b]["poisson_ratio"])
            r_eq = radii[i] * radii[j] / (radii[i] + radii[j])
            m_eq = masses[i] * masses[j] / (masses[i] + masses[j])
            # reconstructed from the recorded state with the law itself (the DEM keeps no per-pair force series)
            normal_force += contact.normal_force(depth, rate, contact.hertz_stiffness(e_eq, r_eq), m_eq,
                                                 alpha.get((a, b)) or 0.0)
            overlap = np.maximum(overlap, depth)
    columns.update(normal_force=normal_force, max_overlap=np.maximum(overlap, 0.0))
    for c, name in enumerate("xyz"):
        columns[f"wall_f{name}"] = wall_force[:, c]
    for k in range(len(radii)):
        for c, name in enumerate("xyz"):
            columns[f"pos_{k}_{name}"] = positions[:, k, c]
            columns[f"vel_{k}_{name}"] = velocities[:, k, c]
            columns[f"spin_{k}_{name}"] = spins[:, k, c]
    return columns


def stability_verdict(spec: dict, columns: dict, energy_growth: float, domain: float) -> tuple[str, str]:
    """('ok', '') or ('unstable', what went wrong), by the checks the Yade template makes."""
    energy = columns["kinetic_energy"] + columns["potential_energy"]
    if not np.all(np.isfinite(energy)):
        return "unstable", "a sphere position or velocity became NaN"
    # kinetic + potential energy can only fall (dissipation) or go into the contacts' springs
    grown = np.flatnonzero(energy - energy[0] > energy_growth * spec["energy_scale"])
    if len(grown):
        k = grown[0]
        return "unstable", (f"the kinetic plus potential energy grew by {energy[k] - energy[0]:.3g} J, "
                            f"{100 * (energy[k] - energy[0]) / spec['energy_scale']:.3g} % of what the scene can "
                            f"release, by t = {columns['time'][k]:.6g} s")
    start = np.asarray(spec["positions"], float)
    n = len(start)
    pos = np.stack([np.column_stack([columns[f"pos_{k}_{c}"] for c in "xyz"]) for k in range(n)], axis=1)
    far = np.linalg.norm(pos - start[None], axis=2).max(axis=1)
    if np.any(far > domain):
        k = int(np.argmax(far > domain))
        return "unstable", (f"a sphere left the domain ({far[k]:.3g} m from its start, farther than the scene's "
                            f"energy allows, {domain:.3g} m) at t = {columns['time'][k]:.6g} s")
    return "ok", ""


if __name__ == "__main__":
    sys.exit(run_description(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(".")))
