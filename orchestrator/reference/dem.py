"""A small numpy DEM with the contact law of Uhlmann et al. 2015: spheres
against spheres, infinite planes and triangle meshes, under gravity, with
rotation. It is the reference the engines are checked against on small
scenes (up to MAX_SPHERES spheres). SI units: m, kg, s, N, Pa.

Integration is velocity Verlet: half a kick with the old forces, a drift,
forces at the new positions from the half-step velocities (which give the
tangential increment v_t dt of eq. 7 and the dash-pot velocity), half a
kick. The dash-pot thus lags by half a step: its error is first order in dt
(0.14 % on the rebound at e_n = 0.2 with 400 steps per contact; see the
tests). Spheres are solid (I = 2/5 m R^2); their orientation is not tracked.

Sphere-wall contacts: a plane or a triangle face has R = inf, so R_eq = R of
the sphere (Hertz's sphere on a flat), m_eq = m of the sphere, and E_eq and
k_t come from the sphere's and the wall's materials (eqs. 3 and 5; a rigid
wall has E = inf, see contact.mindlin_stiffness_coefficient). A mesh edge or
vertex is taken as a flat too (Hertz has no answer for a sharp edge), and a
sphere touches a mesh once per feature (dem_geometry). Walls are immovable
or translate at a constant velocity. Yade's Ig2_Facet_Sphere_ScGeom and
Ig2_Wall_Sphere_ScGeom take the wall as a sphere of radius 2R unless
hertzian=True, i.e. R_eq = 2R/3 and k_n 0.816 times ours (checked on Yade
2023.02a): compare with hertzian=True.

Example::

    out = simulate(positions=[[0, 0, 0.02]], velocities=[[0, 0, 0]], radii=[3.27e-3],
                   sphere_material=[0], materials=[ceramic, steel],
                   pair_table={(0, 1): (0.68, 0.28), (0, 0): (0.86, 0.34)},
                   planes=[Plane(point=(0, 0, 0), normal=(0, 0, 1), material=1)],
                   dt=1e-7, t_end=0.1, record_every=1e-3, free_flight_dt_max=1e-4)
"""

from __future__ import annotations

import time as wallclock
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np

from orchestrator.reference import closed_form, contact
from orchestrator.reference.dem_forces import KIND_PLANE, KIND_SPHERE, KIND_TRIANGLE, ContactLaw, PairLaw, StepContacts
from orchestrator.reference.dem_geometry import (
    TriangleSearch,
    nearest_gaps,
    sphere_plane_contacts,
    sphere_sphere_contacts,
)

#: Largest scene the reference DEM accepts (brute numpy; engines are for larger ones).
MAX_SPHERES = 2000
#: A step whose deepest overlap exceeds this fraction of a radius is taken as a blow-up.
_MAX_OVERLAP_FRACTION = 0.2


class DemBlewUp(RuntimeError):
    """The run went unstable; .partial holds what simulate() had recorded until then."""

    def __init__(self, message: str, partial: dict):
        super().__init__(message)
        self.partial = partial


@dataclass(frozen=True)
class Material:
    """An elastic material: Young's modulus E, Pa (inf for a rigid wall), Poisson ratio, -, density, kg/m^3."""

    young_modulus: float
    poisson_ratio: float
    density: float


@dataclass(frozen=True)
class Plane:
    """An infinite plane wall through point (m) with unit normal pointing to the spheres' side."""

    point: Sequence[float]
    normal: Sequence[float]
    material: int
    velocity: Sequence[float] = (0.0, 0.0, 0.0)  # m/s, constant
    name: str = ""


@dataclass(frozen=True)
class TriangleMesh:
    """A triangle mesh wall: vertices (V,3), m; faces (F,3) vertex indices."""

    vertices: np.ndarray
    faces: np.ndarray
    material: int
    velocity: Sequence[float] = (0.0, 0.0, 0.0)  # m/s, constant
    name: str = ""


@dataclass
class _Scene:
    radii: np.ndarray
    masses: np.ndarray
    inertia: np.ndarray
    sphere_material: np.ndarray
    planes: list[Plane]
    meshes: list[TriangleMesh]
    searches: list[TriangleSearch] = field(default_factory=list)

    @property
    def n_walls(self) -> int:
        return len(self.planes) + len(self.meshes)


def simulate(positions, velocities, radii, sphere_material, materials: Sequence[Material],
             pair_table: Mapping[tuple[int, int], tuple[float, float]], *, dt: float, t_end: float,
             record_every: float, angular_velocities=None, planes: Sequence[Plane] = (),
             meshes: Sequence[TriangleMesh] = (), gravity=(0.0, 0.0, -9.81), damping: str = "eq10",
             no_tension: bool = True, coulomb_limit: str = "total",
             free_flight_dt_max: float | None = None) -> dict:
    """Run the scene from t = 0 to t_end and return its time series and contact record.

    positions, velocities, angular_velocities: (N,3), m, m/s, rad/s;
    radii: (N,), m; sphere_material: (N,) index into materials;
    pair_table: {(material a, material b): (e_n, mu)} for every pair that
    can touch (order free); dt: step while anything is in contact (or
    always), s; t_end, record_every: s; gravity: m/s^2.
    damping: "eq10" takes alpha from e_n by eq. 10 (the paper, Yade);
    "exact" takes the alpha that gives e_n exactly for this law
    (closed_form.alpha_from_restitution). no_tension: the normal force
    never pulls (Yade; see contact.normal_force). coulomb_limit: "total"
    or "elastic" (Yade), see contact.tangential_force_update.
    free_flight_dt_max: if set, steps grow up to this (s) while no contact
    is active, never closing more than half of any gap in one step
    (ballistic flight is exact under velocity Verlet).

    Returns a dict: time (n,), s; positions, velocities, angular_velocities
    (n,N,3); wall_force (n,W,3), N, the contact force on each wall (planes
    first, then meshes; wall_names); kinetic_energy (n,), J; contact_count
    (n,); contacts: per contact from first touch to separation, the arrays
    of dem_forces.EVENT_FIELDS: sphere, other_kind (0 sphere, 1 plane, 2
    triangle), other (index within its kind), start_time, end_time (s),
    impact_speed, rebound_speed (normal, m/s), peak_normal_force (N),
    peak_time (s), max_overlap (m); steps, wall_time_s.
    Raises ValueError for bad input (naming it) and DemBlewUp (with the
    series recorded so far) when an overlap passes 20 % of a radius.
    """
    x, v, w, scene = _validated_scene(positions, velocities, angular_velocities, radii, sphere_material,
                                      materials, planes, meshes)
    _check_options(dt, t_end, record_every, damping, coulomb_limit)
    law = ContactLaw(_pair_law(materials, pair_table, scene, damping, no_tension), scene.radii, scene.masses,
                     scene.sphere_material, scene.n_walls, no_tension, coulomb_limit)
    gravity = np.asarray(gravity, float)
    walls = [*scene.planes, *scene.meshes]
    wall_velocity = np.array([np.asarray(wall.velocity, float) for wall in walls]).reshape(-1, 3)
    started = wallclock.perf_counter()

    t, steps = 0.0, 0
    batch = _detect(x, scene, 0.0)
    _refuse_deep_start(batch, scene)
    force, torque, wall_force = law.forces(batch, v, w, wall_velocity, 0.0, 0.0)
    accel, spin_accel = force / scene.masses[:, None] + gravity, torque / scene.inertia[:, None]
    series = _Recorder()
    series.add(t, x, v, w, wall_force, scene, law.active_count)
    next_record = record_every
    while t < t_end * (1 - 1e-12):
        step = _step_size(x, v, wall_velocity, gravity, scene, law, t, dt, t_end, next_record, free_flight_dt_max)
        v_half, w_half = v + 0.5 * step * accel, w + 0.5 * step * spin_accel
        x = x + step * v_half
        t += step
        steps += 1
        batch = _detect(x, scene, t)
        if len(batch.overlap) and np.max(batch.overlap / scene.radii[batch.sphere]) > _MAX_OVERLAP_FRACTION:
            raise DemBlewUp(f"reference DEM blew up at t = {t:.6g} s (overlap above "
                            f"{_MAX_OVERLAP_FRACTION:.0%} of a radius): reduce dt ({dt:g} s)",
                            dict(series.arrays(), contacts=law.events(), steps=steps))
        force, torque, wall_force = law.forces(batch, v_half, w_half, wall_velocity, t, step)
        accel, spin_accel = force / scene.masses[:, None] + gravity, torque / scene.inertia[:, None]
        v, w = v_half + 0.5 * step * accel, w_half + 0.5 * step * spin_accel
        if t >= next_record * (1 - 1e-12) or t >= t_end * (1 - 1e-12):
            series.add(t, x, v, w, wall_force, scene, law.active_count)
            while next_record <= t * (1 + 1e-12):
                next_record += record_every
    out = series.arrays()
    out.update(contacts=law.events(), steps=steps, wall_time_s=wallclock.perf_counter() - started,
               wall_names=[wall.name or f"plane{k}" for k, wall in enumerate(scene.planes)]
               + [mesh.name or f"mesh{k}" for k, mesh in enumerate(scene.meshes)])
    return out


def _check_options(dt, t_end, record_every, damping, coulomb_limit) -> None:
    """ValueError naming the first of simulate's options that is out of range."""
    if not (dt > 0 and t_end > 0 and record_every > 0):
        raise ValueError(f"dt, t_end and record_every must be > 0 (got {dt}, {t_end}, {record_every})")
    if damping not in ("eq10", "exact"):
        raise ValueError(f"damping must be 'eq10' or 'exact', got {damping!r}")
    if coulomb_limit not in ("total", "elastic"):
        raise ValueError(f"coulomb_limit must be 'total' or 'elastic', got {coulomb_limit!r}")


def _refuse_deep_start(batch: StepContacts, scene) -> None:
    """ValueError when a sphere starts overlapping something by more than _MAX_OVERLAP_FRACTION of its radius."""
    if len(batch.overlap) and np.max(batch.overlap / scene.radii[batch.sphere]) > _MAX_OVERLAP_FRACTION:
        deepest = int(np.argmax(batch.overlap / scene.radii[batch.sphere]))
        raise ValueError(f"sphere {batch.sphere[deepest]} starts overlapping a sphere or wall by "
                         f"{batch.overlap[deepest]:.3g} m (more than {_MAX_OVERLAP_FRACTION:.0%} of its radius): "
                         "move it apart")


def _validated_scene(positions, velocities, angular_velocities, radii, sphere_material, materials, planes, meshes):
    radii = np.asarray(radii, float).reshape(-1)
    count = len(radii)
    if count > MAX_SPHERES:
        raise ValueError(f"the reference DEM handles at most {MAX_SPHERES} spheres (MAX_SPHERES); this scene has "
                         f"{count}: run it on an engine, or check a smaller part of it")
    if count == 0:
        raise ValueError("the scene has no spheres")
    if np.any(~np.isfinite(radii) | (radii <= 0)):
        raise ValueError("every sphere radius must be a finite number > 0 (m)")
    if angular_velocities is None:
        angular_velocities = np.zeros((count, 3))
    arrays = []
    named = (("positions", positions), ("velocities", velocities), ("angular_velocities", angular_velocities))
    for name, value in named:
        array = np.array(value, float)
        if array.shape != (count, 3) or not np.all(np.isfinite(array)):
            raise ValueError(f"{name} must be a finite ({count}, 3) array (one row per sphere), "
                             f"got shape {array.shape}")
        arrays.append(array)
    sphere_material = np.asarray(sphere_material, int).reshape(-1)
    if sphere_material.shape != (count,):
        raise ValueError(f"sphere_material must give one material index per sphere ({count})")
    for index, material in enumerate(materials):
        if not (material.young_modulus > 0 and 0 <= material.poisson_ratio < 0.5):
            raise ValueError(f"material {index}: need E > 0 (Pa) and 0 <= nu < 0.5, got {material}")
    wall_materials = [p.material for p in planes] + [m.material for m in meshes]
    if any(not 0 <= k < len(materials) for k in [*sphere_material.tolist(), *wall_materials]):
        raise ValueError(f"a material index is outside 0..{len(materials) - 1}")
    for k in np.unique(sphere_material):
        if not (np.isfinite(materials[k].young_modulus) and materials[k].density > 0):
            raise ValueError(f"material {k} is used by spheres: it needs a finite E and a density > 0")
    densities = np.array([materials[k].density for k in sphere_material])
    masses = densities * 4.0 / 3.0 * np.pi * radii**3
    for k, plane in enumerate(planes):
        if np.shape(plane.point) != (3,) or np.shape(plane.normal) != (3,) or not np.linalg.norm(plane.normal) > 0:
            raise ValueError(f"plane {k}: point and normal must be 3-vectors, the normal not zero")
    planes = [Plane(np.asarray(p.point, float), np.asarray(p.normal, float) / np.linalg.norm(p.normal), p.material,
                    tuple(p.velocity), p.name) for p in planes]
    meshes = list(meshes)
    for k, mesh in enumerate(meshes):
        vertices, faces = np.asarray(mesh.vertices), np.asarray(mesh.faces)
        if vertices.ndim != 2 or vertices.shape[1] != 3 or faces.ndim != 2 or faces.shape[1] != 3 or not len(faces):
            raise ValueError(f"mesh {mesh.name or k}: vertices must be (V, 3) and faces (F, 3) with F > 0")
        if faces.min() < 0 or faces.max() >= len(vertices):
            raise ValueError(f"mesh {mesh.name or k}: a face names a vertex outside 0..{len(vertices) - 1}")
    scene = _Scene(radii, masses, contact.SOLID_SPHERE_GYRATION * masses * radii**2, sphere_material, planes, meshes,
                   [TriangleSearch(m.vertices, m.faces) for m in meshes])
    return arrays[0], arrays[1], arrays[2], scene


def _pair_law(materials, pair_table, scene, damping, no_tension) -> PairLaw:
    count = len(materials)
    young = np.array([m.young_modulus for m in materials], float)
    poisson = np.array([m.poisson_ratio for m in materials], float)
    table = {}
    for (a, b), (restitution, friction) in pair_table.items():
        if not (0 <= a < count and 0 <= b < count):
            raise ValueError(f"pair_table names material pair ({a}, {b}); materials are 0..{count - 1}")
        if not (0 < restitution <= 1 and friction >= 0):
            raise ValueError(f"pair ({a}, {b}): need 0 < e_n <= 1 and mu >= 0, got e_n={restitution}, mu={friction}")
        table[(a, b)] = table[(b, a)] = (restitution, friction)
    kinds, counts = np.unique(scene.sphere_material, return_counts=True)
    needed = {(int(a), int(w.material)) for a in kinds for w in [*scene.planes, *scene.meshes]}
    needed |= {(int(a), int(b)) for a, n_a in zip(kinds, counts) for b in kinds if a != b or n_a > 1}
    missing = sorted(pair for pair in needed if pair not in table)
    if missing:
        raise ValueError(f"pair_table has no (e_n, mu) for material pairs {missing}")
    alpha_of = contact.damping_alpha if damping == "eq10" else \
        (lambda e: closed_form.alpha_from_restitution(float(e), no_tension))
    effective_young, factor = np.full((count, count), np.nan), np.full((count, count), np.nan)
    alpha, friction = np.zeros((count, count)), np.zeros((count, count))
    for (a, b), (restitution, mu) in table.items():
        if np.isinf(young[a]) and np.isinf(young[b]):
            continue
        effective_young[a, b] = contact.effective_modulus(young[a], poisson[a], young[b], poisson[b])
        factor[a, b] = contact.mindlin_stiffness_coefficient(1.0, young[a], poisson[a], young[b], poisson[b])
        alpha[a, b], friction[a, b] = alpha_of(restitution), mu
    return PairLaw(effective_young, factor, alpha, friction)


def _detect(x, scene: _Scene, t) -> StepContacts:
    """Every contact at positions x and time t, sorted by key = sphere * n_targets + target,
    where targets are numbered spheres, then planes, then the triangles of each mesh."""
    n_spheres, n_planes = len(scene.radii), len(scene.planes)
    parts = []  # per kind of target: (found, kind, target id, partner sphere, wall, other material)

    found = sphere_sphere_contacts(x, scene.radii)
    none = -np.ones_like(found.other)
    parts.append((found, KIND_SPHERE, found.other, found.other, none, scene.sphere_material[found.other]))
    if scene.planes:
        points = np.array([p.point + np.asarray(p.velocity) * t for p in scene.planes])
        found = sphere_plane_contacts(x, scene.radii, points, np.array([p.normal for p in scene.planes]))
        materials = np.array([p.material for p in scene.planes])
        parts.append((found, KIND_PLANE, n_spheres + found.other, -np.ones_like(found.other), found.other,
                      materials[found.other]))
    first_triangle = n_spheres + n_planes
    for k, (mesh, search) in enumerate(zip(scene.meshes, scene.searches)):
        found, _ = search.contacts(x, scene.radii, np.asarray(mesh.velocity, float) * t)
        parts.append((found, KIND_TRIANGLE, first_triangle + found.other, -np.ones_like(found.other),
                      np.full_like(found.other, n_planes + k), np.full_like(found.other, mesh.material)))
        first_triangle += len(search.corners)

    n_targets = first_triangle
    key = np.concatenate([found.sphere.astype(np.int64) * n_targets + target for found, _, target, *_ in parts])
    order = np.argsort(key, kind="stable")

    def joined(column):
        return np.concatenate(column)[order]

    return StepContacts(
        key=key[order],
        sphere=joined([found.sphere for found, *_ in parts]),
        partner=joined([partner for _, _, _, partner, _, _ in parts]),
        wall=joined([wall for *_, wall, _ in parts]),
        kind=joined([np.full(len(found.sphere), kind) for found, kind, *_ in parts]),
        other=joined([found.other for found, *_ in parts]),
        other_material=joined([material for *_, material in parts]),
        normal=joined([found.normal for found, *_ in parts]),
        overlap=joined([found.overlap for found, *_ in parts]),
    )


def _step_size(x, v, wall_velocity, gravity, scene, law, t, dt, t_end, next_record, dt_max):
    """dt while in contact; in free flight the largest step (<= dt_max) that cannot
    close more than half of any gap, landing on record times."""
    remaining = t_end - t
    if dt_max is None or dt_max <= dt or law.active_count:
        return min(dt, remaining)
    plane_points = np.array([p.point + np.asarray(p.velocity) * t for p in scene.planes]).reshape(-1, 3)
    plane_normals = np.array([p.normal for p in scene.planes]).reshape(-1, 3)
    gaps = nearest_gaps(x, scene.radii, plane_points, plane_normals, scene.searches,
                        [np.asarray(m.velocity, float) * t for m in scene.meshes])
    speeds = np.linalg.norm(v, axis=1)
    fastest_other = max(speeds.max(), np.linalg.norm(wall_velocity, axis=1).max(initial=0.0))
    closing = speeds + fastest_other
    g = np.linalg.norm(gravity)
    half_gap = 0.5 * np.maximum(gaps, 0.0)
    # largest h with closing h + g h^2 <= gap / 2
    if g > 0:
        limit = (-closing + np.sqrt(closing**2 + 4.0 * g * half_gap)) / (2.0 * g)
    else:
        limit = half_gap / np.maximum(closing, 1e-300)
    step = float(np.clip(limit.min(), dt, dt_max))
    to_record = next_record - t
    if to_record > dt:
        step = min(step, to_record)
    return min(step, remaining)


class _Recorder:
    """Collects the recorded states and turns them into arrays."""

    def __init__(self):
        self.rows: dict[str, list] = {name: [] for name in ("time", "positions", "velocities", "angular_velocities",
                                                             "wall_force", "kinetic_energy", "contact_count")}

    def add(self, t, x, v, w, wall_force, scene, contact_count):
        energy = 0.5 * (np.sum(scene.masses * np.sum(v * v, axis=1)) + np.sum(scene.inertia * np.sum(w * w, axis=1)))
        for name, value in (("time", t), ("positions", x.copy()), ("velocities", v.copy()),
                            ("angular_velocities", w.copy()), ("wall_force", wall_force.copy()),
                            ("kinetic_energy", energy), ("contact_count", contact_count)):
            self.rows[name].append(value)

    def arrays(self) -> dict:
        return {name: np.asarray(values) for name, values in self.rows.items()}
