"""The sph executable runs SPH flows: the deck's values, the HDF5 input files and the reader of out.h5
(engines.sph starts the executable)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from orchestrator.engines.base import Result, Series
from orchestrator.kinds.base import Adapter
from orchestrator.kinds.sph_flow.case_grains import grain_contact_deck
from orchestrator.kinds.sph_flow.case_impactors import stiffness_scale
from orchestrator.kinds.sph_flow.case_open import rest_pressure
from orchestrator.kinds.sph_flow.resume import FRAME_ARRAYS, merge_parts, part_files, write_resume_input
from orchestrator.runh5 import _plain
from orchestrator.runner import LOG_NAME, tail
from orchestrator.templating import render

TEMPLATE = Path(__file__).resolve().parent / "templates" / "sph.json.j2"
DECK = "deck.json"
OUTPUT = "out.h5"
#: Wall-time interval of the engine's PROGRESS lines, s.
PROGRESS_INTERVAL_S = 1.0


class SphFlow(Adapter):
    """SPH flows as a JSON deck (templates/sph.json.j2) with particles.h5 and meshes.h5."""

    engine = "sph"
    templates = (TEMPLATE,)

    def write_input(self, profile, scene, workdir: Path) -> None:
        write_particles(scene, workdir / "particles.h5")
        if scene.meshes:
            write_meshes(scene, workdir / "meshes.h5")
        (workdir / DECK).write_text(render(TEMPLATE, deck_context(scene, threads=profile.threads)))

    def command(self, profile, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        return [profile.executable or "sph", DECK], profile.environment(scene.case.numerics.thread_wait)

    def read_output(self, profile, scene, workdir: Path) -> Result:
        return read_sph_output(workdir, scene)

    def resume_input(self, profile, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        """Continue the stopped run in workdir from its last frame (resume.py): its deck from that frame's time to the
        case's simulation.duration (later than the run's own with `run --resume --until`)."""
        deck = write_resume_input(Path(workdir), DECK, OUTPUT, t_end=scene.case.simulation.duration)
        return [profile.executable or "sph", deck], profile.environment(scene.case.numerics.thread_wait)


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
    materials = None
    if case.materials:  # the deck's `materials` list replaces its top-level fluid keys
        materials = [json.dumps(m.deck()) for m in scene.materials]
    le = case.lees_edwards
    # N/m: the contact springs' (impactors, eq. G8), from the stiffest material (a scene of the top-level fluid has none)
    scale = stiffness_scale(scene.materials, numerics.dx) if scene.materials else 0.0
    contact = grain_contact_deck(case, scale)
    return {
        "materials": materials,
        "dimension": case.dimension,
        "physics": json.dumps(list(scene.physics)),
        "rho0": num(fluid.density),
        "c0": num(scene.c0),
        "v_max": num(fluid.max_speed),
        "gamma": num(fluid.gamma),
        "background_pressure": num(fluid.background_pressure),
        "min_pressure": None if fluid.min_pressure is None else num(fluid.min_pressure),
        "h": num(scene.h),
        "dx": num(numerics.dx),
        "viscosity": None if fluid.viscosity is None else num(fluid.viscosity),
        "alpha": None if av is None else num(av.alpha),
        "beta": None if av is None else num(av.beta),
        "av_walls": None if av is None or av.walls else "false",
        "viscosity_correction": physics.viscosity_correction,
        "eddy_viscosity_cs": None if physics.eddy_viscosity is None else num(physics.eddy_viscosity),
        "eddy_viscosity_walls": "true" if physics.eddy_viscosity_walls else "false",
        "density_diffusion": None if physics.density_diffusion is None else num(physics.density_diffusion),
        "body_force": None if physics.body_force is None else vec(scene.body_force or physics.body_force),
        "body_force_solids": physics.body_force_on == "all",
        "meshes": [{"name": json.dumps(name), "group": json.dumps("/" + name)} for name in scene.meshes],
        "wall": None if wall is None else {"range": num(wall.range), "s": num(wall.s), "psi": num(wall.psi)},
        "periodic": periodic,
        "lees_edwards": None if le is None else json.dumps(le.deck()),
        "inlets": [_patch_json(p, velocity=p.velocity, layers=p.layers, **p.deck_options()) for p in case.inlets],
        "outlets": [_patch_json(p, layers=p.layers, **p.deck_options(rest_pressure(case))) for p in case.outlets],
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
        "impactors": [json.dumps(imp.deck(scale)) for imp in case.impactors],
        "grains": [json.dumps(g) for g in scene.grains],
        "grain_contact": None if contact is None else json.dumps(contact),
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
    kg/m^3, kind (n) int8 (0 fluid, 1 fixed boundary, 4 a grain's particle; then grain (n) int32, its grain), with [[materials]] material (n) int32 (index into the
    deck's materials) and, when a block names a cylinder wall, wall_point (n,D) m (a boundary particle's nearest
    point of the true wall; NaN rows: none), and the scene's starting state (mode_stress (n, modes D^2) Pa, each
    mode's tensor row by row)."""
    import h5py

    with h5py.File(path, "w") as h5:
        h5["positions"] = np.asarray(scene.positions, dtype=np.float64)
        h5["velocities"] = np.asarray(scene.velocities, dtype=np.float64)
        h5["masses"] = np.asarray(scene.masses, dtype=np.float64)
        h5["densities"] = np.asarray(scene.densities, dtype=np.float64)
        h5["kind"] = np.asarray(scene.kind, dtype=np.int8)
        if scene.case.materials:
            h5["material"] = np.asarray(scene.material, dtype=np.int32)
        if scene.wall_point is not None:
            h5["wall_point"] = np.asarray(scene.wall_point, dtype=np.float64)
        if scene.grain is not None:
            h5["grain"] = np.asarray(scene.grain, dtype=np.int32)
        for name, values in (scene.state or {}).items():  # restored by the engine as a resumed run's (resume.py)
            h5[name] = np.asarray(values, dtype=np.float64).reshape(len(scene.masses), -1)


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
    "shear_stress": "volume average over the fluid of the extra stress tau_xy (PTT materials; in a Lees-Edwards "
                    "cell the sample's shear stress)",
    "first_normal_stress_difference": "volume average over the fluid of tau_xx - tau_yy (PTT materials)",
    "shear_strain": "Lees-Edwards strain gamma(t) of the cell",
    "shear_rate": "Lees-Edwards shear rate gamma_dot(t) of the cell",
    "impactor_": "a rigid impactor's centre, velocity, angular velocity, orientation (quaternion w, x, y, z), the "
                 "particles' contact force on it, its kinetic and contact energy (engines/sph/README.md)",
    "grain_": "a rigid grain's centre of mass, velocity, angular velocity, orientation (quaternion w, x, y, z), the "
              "fluid's force and torque on it (eq. G2) and its contacts' force (eqs. G6-G8, engines/sph/README.md); "
              "_contact_impulse, _contact_peak, _contact_time: over every step since the previous record, the "
              "contacts' impulse, largest force and the time they acted",
}
#: Root attributes of out.h5 copied into run.h5 (engine name -> run.h5 name).
ENGINE_ATTRS = {"n_steps": "n_steps", "dt_mean": "dt", "t_final": "simulated_time", "wall_time_s": "engine_wall_time_s",
                "particle_steps_per_s": "particle_steps_per_s", "physics": "physics", "h": "h", "dx": "dx",
                "dimension": "dimension", "last_good_frame": "last_good_frame"}


def read_sph_output(workdir: Path, scene=None) -> Result:
    """Parse out.h5 of a run (complete, partial or missing) into a Result; meshes from the scene. A resumed run's
    earlier parts (out.1.h5, ...: resume.py) are read first and merged with it."""
    material = None if scene is None or not scene.case.materials else np.asarray(scene.material, dtype=np.int32)
    parts = [_read_part(path, workdir, material) for path in part_files(workdir, OUTPUT)]
    result = merge_parts(parts)
    if scene is not None:
        result.meshes = {name: {"vertices": np.asarray(m.vertices), "faces": np.asarray(m.faces)}
                         for name, m in scene.meshes.items()}
    return result


def _read_part(path: Path, workdir: Path, material) -> tuple[Result, dict]:
    """(Result, out.h5's root attributes) of one engine output file."""
    import h5py

    result = Result()
    attrs: dict = {}
    if not path.is_file():
        result.status = "failed"
        result.message = _engine_error(workdir) or f"the engine wrote no {OUTPUT}"
        return result, attrs
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
                if "mode_stress" in group:  # PTT runs: (n, modes, D, D) Pa, tau_i of every mode
                    d = arrays["positions"].shape[1]
                    arrays["mode_stress"] = np.asarray(group["mode_stress"][()]).reshape(len(arrays["ids"]), -1, d, d)
                arrays.update(_solid_fields(group, len(arrays["ids"]), arrays["positions"].shape[1]))
                if material is not None:
                    arrays["material"] = _frame_material(material, arrays["ids"])
                arrays["step"] = np.int64(group.attrs.get("step", -1))
                result.frames.append((float(group.attrs["time"]), arrays))
    except (OSError, KeyError, ValueError) as exc:
        result.status = "failed"
        result.message = f"cannot read {path}: {exc}"
        return result, attrs
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
    return result, attrs


#: The columns of a solid's `solid_state` in out.h5 (engines/sph/src/materials/solid_state.h) as run.h5 frame arrays.
SOLID_STATE_FIELDS = ("internal_energy", "plastic_strain", "plastic_strain_rate", "temperature", "damage", "stress_zz")


def _solid_fields(group, n: int, dimension: int) -> dict:
    """A solid run's frame fields: the deviatoric stress `stress` (n, D, D) Pa and the named columns of
    `solid_state`: internal_energy J/kg, plastic_strain -, plastic_strain_rate 1/s, temperature K, damage -, and
    in 2D stress_zz Pa (the plane-strain deviator). Empty for a fluid run."""
    if "solid_state" not in group:
        return {}
    state = np.asarray(group["solid_state"][()], dtype=float).reshape(n, len(SOLID_STATE_FIELDS))
    fields = {name: state[:, k] for k, name in enumerate(SOLID_STATE_FIELDS) if dimension == 2 or name != "stress_zz"}
    if "stress" in group:
        fields["stress"] = np.asarray(group["stress"][()], dtype=float).reshape(n, dimension, dimension)
    return fields


def _frame_material(material: np.ndarray, ids: np.ndarray) -> np.ndarray:
    """Each frame particle's material index, int32: out.h5 does not record it, and a particle keeps the
    material of its input row (ids number the input rows); particles added by inlets take material 0 (the
    engine gives them the deck's first material)."""
    ids = np.asarray(ids, dtype=np.int64)
    known = (ids >= 0) & (ids < len(material))
    return np.where(known, material[np.clip(ids, 0, len(material) - 1)], 0).astype(np.int32)


def _engine_error(workdir: Path) -> str:
    """The engine's last 'error: ...' line in the run's log, without the prefix ('' if none)."""

    lines = [line for line in tail(Path(workdir) / LOG_NAME, 200).splitlines() if line.startswith("error: ")]
    return lines[-1].removeprefix("error: ") if lines else ""
