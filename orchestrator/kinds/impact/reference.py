"""Impact cases on the reference engine: our numpy DEM (orchestrator.reference.dem, the
paper's contact law) run like any engine, as ``python -m
orchestrator.kinds.impact.reference RUN_DIR`` in its own process (so the
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

from orchestrator.engines.base import Result
from orchestrator.engines.reference import MAX_WALL_TIME_S, SPHERE_STEP_COST_S, STEP_COST_S
from orchestrator.errors import OrchestratorError
from orchestrator.humanize import duration
from orchestrator.kinds.base import Adapter
from orchestrator.kinds.impact.analysis import EVENT_LIMIT
from orchestrator.kinds.impact.physics import energy_scale, poisson_ratio, young_modulus
from orchestrator.kinds.impact.yade import ENERGY_GROWTH, domain_radius, read_impact_output
from orchestrator.reference import contact
from orchestrator.reference.dem import MAX_SPHERES, DemBlewUp, Material, Plane, simulate


class ReferenceImpact(Adapter):
    """Impact scenes on the reference DEM: reference.json (scene_description) run by this module as a child process."""

    engine = "reference"

    def check_scene(self, profile, scene) -> None:
        """Raise OrchestratorError (exit 2) for a scene the reference DEM cannot or should not run."""

        name = scene.case.case.name
        if scene.n_particles > MAX_SPHERES:
            raise OrchestratorError(
                f"the case {name} has {scene.n_particles} spheres; the reference DEM takes at most {MAX_SPHERES}. "
                "Run it on an engine instead: --engine yade")
        estimate = estimated_wall_time(scene)
        if estimate > MAX_WALL_TIME_S:
            raise OrchestratorError(
                f"the case {name} would take the reference DEM about {duration(estimate)} "
                f"({estimated_steps(scene):.3g} steps of {scene.n_particles} spheres; limit "
                f"{duration(MAX_WALL_TIME_S)}). Shorten simulation.duration, raise numerics.timestep_factor, or run "
                "it on an engine: --engine yade")

    def write_input(self, profile, scene, workdir: Path) -> None:
        self.check_scene(profile, scene)
        (workdir / "reference.json").write_text(json.dumps(scene_description(scene), indent=1))

    def command(self, profile, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        return [profile.python, "-u", "-m", "orchestrator.kinds.impact.reference", "."], {"OMP_NUM_THREADS": "1"}

    def read_output(self, profile, scene, workdir: Path) -> Result:
        return read_impact_output(scene, workdir)


def estimated_steps(scene) -> float:
    """Time steps the run will take, -: every step at dt in dense scenes; a few spheres fly between
    contacts in steps as long as the record interval."""
    if scene.n_particles > 10:
        return scene.duration / scene.timestep
    return scene.duration / scene.record_interval + 2000.0 * scene.n_particles

def estimated_wall_time(scene) -> float:
    """Estimated run time on this machine, s."""
    return estimated_steps(scene) * (STEP_COST_S + SPHERE_STEP_COST_S * scene.n_particles)


def scene_description(scene) -> dict:
    """Everything dem.simulate needs, as JSON-able plain values (SI units; E = inf for the rigid wall)."""

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


# ---- the child process: python -m orchestrator.kinds.impact.reference RUN_DIR ----

def run_description(workdir: Path) -> int:
    """Run reference.json of workdir; write output/ like the Yade template does. Returns the exit code."""

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
