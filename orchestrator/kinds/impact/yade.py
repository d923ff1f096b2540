"""Yade runs impact cases: the template context, and the reader of output/.

How the paper's contact law maps onto Yade 2023's parameters: orchestrator.dem.yade_law. With
model.damping = "exact" or "eq10" the script gets that mapping's betan and betas, and each new contact's k_t0
set to eq. 5's (from its second step on); "engine" passes e_n to Yade's en/es unchanged. With this mapping Yade
and the reference DEM run with model.coulomb_limit = "elastic" agree to 0.04 % on oblique rebounds of ceramic on
steel; the Coulomb rule is what remains.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from orchestrator.dem import RIGID_POISSON, RIGID_STIFFNESS_FACTOR
from orchestrator.dem.yade_law import yade_damping_parameters
from orchestrator.engines.base import Result, Series
from orchestrator.errors import ReadError
from orchestrator.kinds.base import Adapter
from orchestrator.kinds.impact.analysis import EVENT_LIMIT
from orchestrator.kinds.impact.case import RIGID
from orchestrator.kinds.impact.physics import (
    effective_young,
    energy_scale,
    fastest_closing_speeds,
    poisson_ratio,
    sphere_mass,
    young_modulus,
)
from orchestrator.reference import closed_form, contact
from orchestrator.reference.dem_forces import EVENT_FIELDS
from orchestrator.templating import render

#: A contact whose overlap passes this fraction of the sphere radius is taken as a blow-up (as the reference DEM).
MAX_OVERLAP_FRACTION = 0.2
#: Relative growth of the total energy (without contacts) taken as a blow-up.
ENERGY_GROWTH = 0.01


def yade_deviations(case) -> str:
    """What Yade runs differently from what the case asks ('' if nothing)."""
    if case.model.coulomb_limit == "total" and any(c.friction > 0 for c in case.contacts):
        return ("model.coulomb_limit = 'total' asked; Yade bounds only the elastic tangential force and adds the "
                "dash-pot on top while a contact sticks (its Law2_ScGeom_MindlinPhys_Mindlin has no other rule)")
    return ""


def _yade_materials(scene) -> dict[str, tuple[float, float, float]]:
    """name -> (E, nu, rho) as given to Yade (the rigid wall made very stiff)."""

    case = scene.case
    scale = case.numerics.stiffness_scale
    out = {name: (m.young_modulus * scale, m.poisson_ratio, m.density) for name, m in sorted(case.materials.items())}
    used = set(scene.sphere_materials) | ({scene.plane_material} if scene.plane_material else set())
    out = {name: value for name, value in out.items() if name in used}
    if scene.plane_material == RIGID:
        stiffest = max(out[name][0] for name in set(scene.sphere_materials))
        out[RIGID] = (RIGID_STIFFNESS_FACTOR * stiffest, RIGID_POISSON, 1000.0)
    return out


def _plane_context(scene, reach: float) -> dict | None:
    if scene.plane_normal is None:
        return None
    normal, point = scene.plane_normal, scene.plane_point
    context = {"point": repr(tuple(float(v) for v in point)), "normal": repr(tuple(float(v) for v in normal)),
               "material": scene.plane_material, "axis": None}
    axis = int(np.argmax(np.abs(normal)))
    if abs(abs(normal[axis]) - 1.0) < 1e-12:
        context.update(axis=axis, position=repr(float(point[axis])), sense=1 if normal[axis] > 0 else -1)
        return context
    corners = [tuple(float(c) for c in corner) for corner in scene.plane_triangle(reach)]
    context["corners"] = repr(corners)
    return context


def domain_radius(scene) -> float:
    """How far a sphere can get from its start in the run without gaining energy, times 2, plus 10 radii, m."""

    wall_speed, _ = fastest_closing_speeds(scene.case)
    g = float(np.linalg.norm(scene.gravity))
    return 2.0 * (float(wall_speed.max()) * scene.duration + 0.5 * g * scene.duration**2) + 10.0 * float(scene.radii.max())


def impact_context(scene) -> dict:
    """Plain values the impact template needs (SI units)."""

    case = scene.case
    materials = _yade_materials(scene)
    pairs = sorted(scene.pairs.values(), key=lambda p: p.materials)
    # ascii(): a Python literal of the names whatever they hold (escapes beyond ASCII too)
    rows = lambda value: ascii(tuple((p.materials[0], p.materials[1], value(p)) for p in pairs))  # noqa: E731
    betan, betas, kso = {}, {}, {}
    for p in pairs:
        a, b = p.materials
        normal = 4.0 / 3.0 * p.effective_young
        paper_shear = float(contact.mindlin_stiffness_coefficient(1.0, *_elastic(case, a), *_elastic(case, b)))
        kso[p.materials] = paper_shear
        if p.alpha is not None:
            betan[p.materials], betas[p.materials] = yade_damping_parameters(p.alpha, normal, paper_shear)
    dt = scene.timestep
    record_every = max(1, round(scene.record_interval / dt))
    return {
        "stiffness_scale": repr(case.numerics.stiffness_scale),
        "rigid_factor": repr(RIGID_STIFFNESS_FACTOR),
        "materials": [{"name": name, "young": repr(e), "poisson": repr(nu), "density": repr(rho)}
                      for name, (e, nu, rho) in materials.items()],
        "native_damping": case.model.damping == "engine",
        "pairs_friction_angle": rows(lambda p: math.atan(p.friction)),
        "pairs_en": rows(lambda p: p.restitution),
        "pairs_es": rows(lambda p: p.tangential_restitution),
        "pairs_betan": rows(lambda p: betan.get(p.materials, 0.0)),
        "pairs_betas": rows(lambda p: betas.get(p.materials, 0.0)),
        "pairs_kso": rows(lambda p: kso[p.materials]),
        "plane": _plane_context(scene, domain_radius(scene)),
        "gravity": repr(tuple(float(g) for g in scene.gravity)),
        "dt": repr(dt),
        "n_steps": max(1, math.ceil(scene.duration / dt - 1e-9)),
        "duration": repr(scene.duration),
        "record_every": record_every,
        "max_overlap_fraction": repr(MAX_OVERLAP_FRACTION),
        "energy_growth": repr(ENERGY_GROWTH),
        "domain_radius": repr(domain_radius(scene)),
        "energy_scale": repr(energy_scale(scene.case)),
        "event_limit": EVENT_LIMIT,
    }


def _elastic(case, name) -> tuple[float, float]:

    return young_modulus(case, name), poisson_ratio(case, name)


TEMPLATE = Path(__file__).resolve().parent / "templates" / "yade.py.j2"
SCRIPT = "impact.py"


class YadeImpact(Adapter):
    """Impact scenes as a Yade script (templates/yade.py.j2) with the spheres in scene.npz."""

    engine = "yade"
    templates = (TEMPLATE,)

    def write_input(self, profile, scene, workdir: Path) -> None:
        """scene.npz (sphere arrays, material names) and impact.py into workdir."""
        np.savez(workdir / "scene.npz", positions=scene.positions, velocities=scene.velocities,
                 angular_velocities=scene.angular_velocities, radii=scene.radii,
                 materials=np.array(scene.sphere_materials, dtype=str))
        (workdir / SCRIPT).write_text(render(TEMPLATE, impact_context(scene)))

    def command(self, profile, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        return profile.run_command(SCRIPT, workdir)

    def read_output(self, profile, scene, workdir: Path) -> Result:
        result = read_impact_output(scene, workdir)
        if yade_deviations(scene.case):
            result.attrs["deviation"] = yade_deviations(scene.case)
        return result


def read_series_bin(out: Path) -> tuple[list[str], np.ndarray] | None:
    """output/series.json + series.bin as (columns, rows); a cut-off last row is dropped."""
    header, body = out / "series.json", out / "series.bin"
    if not header.is_file() or not body.is_file():
        return None
    try:
        columns = json.loads(header.read_text())["columns"]
    except (ValueError, KeyError) as exc:
        raise ReadError(f"cannot read {header}: {exc}") from None
    data = body.read_bytes()
    raw = np.frombuffer(data[: len(data) - len(data) % 8], dtype="<f8")
    rows = len(raw) // len(columns)
    return columns, raw[: rows * len(columns)].reshape(rows, len(columns))


def read_impact_output(scene, workdir: Path) -> Result:
    """Parse output/ of an impact run (Yade or the reference backend), complete or partial, into a
    Result with the run.h5 names."""
    out = Path(workdir) / "output"
    result = Result()
    status_path = out / "status.json"
    if status_path.is_file():
        status = json.loads(status_path.read_text())
        result.status, result.message = status["status"], status["message"]
        result.attrs.update(n_steps=int(status["n_steps"]), dt=float(status["dt"]),
                            simulated_time=float(status["time"]), engine_wall_time_s=float(status["wall_time_s"]))
    else:
        result.status, result.message = "failed", "the engine wrote no status (it was stopped or crashed)"
    table = read_series_bin(out)
    if table is not None:
        columns, rows = table
        fill_impact_series(result, {name: rows[:, i] for i, name in enumerate(columns)}, scene.n_particles)
    elif (out / "series.npz").is_file():  # the reference backend writes named columns directly
        with np.load(out / "series.npz") as data:
            fill_impact_series(result, {name: data[name] for name in data.files}, scene.n_particles)
    if (out / "events.npz").is_file():
        with np.load(out / "events.npz") as data:
            fill_impact_events(result, {name: data[name] for name in data.files})
    if result.status == "unstable":
        result.message = f"{result.message}; {instability_advice(scene, result.message)}"
    return result


def instability_advice(scene, message: str = "") -> str:
    """The likely cause of an unstable impact run and the fix, from the scene's step, its fastest contact and
    what the engine reported (message)."""

    case = scene.case
    wall_speed, pair_speed = fastest_closing_speeds(case)
    durations = []
    for i, sphere in enumerate(case.spheres):
        if case.plane is not None and wall_speed[i] > 0:
            e_eq = effective_young(case, sphere.material, case.plane.material)
            durations.append(closed_form.hertz_contact_duration(sphere_mass(case, i), sphere.radius, e_eq,
                                                                wall_speed[i]))
        if len(case.spheres) > 1 and pair_speed > 0:
            e_eq = effective_young(case, sphere.material, sphere.material)
            durations.append(closed_form.hertz_contact_duration(sphere_mass(case, i) / 2, sphere.radius / 2, e_eq,
                                                                pair_speed))
    ratio = scene.timestep / scene.critical_timestep
    subject = (f"numerics.timestep = {scene.timestep:.3g} s ({ratio:.3g} times the critical step "
               f"{scene.critical_timestep:.3g} s)" if case.numerics.timestep is not None else
               f"the time step {scene.timestep:.3g} s ({ratio:.3g} of the critical step)")
    fix = "remove numerics.timestep" if case.numerics.timestep is not None else "lower numerics.timestep_factor"
    default = "the default 0.05 of the critical step gives at least 40 steps per contact"
    if not durations:
        return f"likely cause: {subject} is too large for these contacts; fix: {fix} ({default})"
    shortest = float(min(durations))
    steps = shortest / scene.timestep
    resolves = (f"{subject} resolves the shortest contact (Hertz duration {shortest:.3g} s at the fastest closing "
                f"speed the scene allows) in {steps:.3g} steps")
    if ratio > 1.0 or steps < 20:
        return f"likely cause: {resolves}, too coarse for contacts this stiff and fast; fix: {fix} ({default})"
    if "overlap" in message:
        return (f"{resolves}, so the step is not the likely cause: the impact itself drives the overlap beyond "
                "Hertz's small-overlap law; fix: a slower impact, or stiffer or larger spheres")
    return f"{resolves}; if that is not enough here, {fix}"


def fill_impact_series(result: Result, columns: dict[str, np.ndarray], n_spheres: int) -> None:
    """Result.time and Result.series of an impact run from named columns (shared by every backend)."""
    def block(prefix):
        return np.stack([np.column_stack([columns[f"{prefix}_{k}_{c}"] for c in "xyz"]) for k in range(n_spheres)],
                        axis=1)

    result.time = columns["time"]
    result.series = {
        "positions": Series(block("pos"), "m", "sphere centres (n, spheres, 3)"),
        "velocities": Series(block("vel"), "m/s", "sphere velocities (n, spheres, 3)"),
        "angular_velocities": Series(block("spin"), "rad/s", "sphere angular velocities (n, spheres, 3)"),
        "normal_force": Series(columns["normal_force"], "N", "sum of the contact normal forces (magnitudes)"),
        "max_overlap": Series(columns["max_overlap"], "m", "largest contact overlap"),
        "wall_force": Series(np.column_stack([columns[f"wall_f{c}"] for c in "xyz"]), "N",
                             "force of the spheres on the plane, global frame"),
        "kinetic_energy": Series(columns["kinetic_energy"], "J", "translational and rotational"),
        "potential_energy": Series(columns["potential_energy"], "J", "gravity, -m g . x"),
        "n_contacts": Series(columns["n_contacts"].astype(np.int64), "-", "contacts in force"),
    }


def fill_impact_events(result: Result, events: dict[str, np.ndarray]) -> None:
    """Result.events from the contact-event columns (EVENT_FIELDS, with their units)."""

    for name, units in EVENT_FIELDS.items():
        values = np.asarray(events.get(name, np.zeros(0)), dtype=float)
        if name in ("sphere", "other_kind", "other"):
            values = values.astype(np.int64)
        result.events[name] = Series(values, units)
