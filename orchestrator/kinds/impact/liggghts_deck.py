"""LIGGGHTS backend, impact scenes: the deck's context (materials, damping,
wall copies; orchestrator.dem.liggghts_law says how the law maps), the files
it reads, and the reader that turns its dumps into the series and contact
events Yade's impact runs have (orchestrator.reference.dem_forces.EVENT_FIELDS,
same definitions).

The deck dumps the spheres at every record and, while a contact is on or may
start before the next record (a sphere within reach of the plane or of
another sphere), every contact every step (compute pair/gran/local,
wall/gran/local); the events are built from those steps here, as Yade's
track() builds them in the engine. LIGGGHTS cannot stop itself on a blow-up:
the reader finds it afterwards (overlap beyond MAX_OVERLAP_FRACTION of the
radius, energy growth, a sphere leaving the domain or the box) with the same
messages and advice as Yade's runs.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.dem.liggghts_law import (
    MAX_BETA,
    beta_for_restitution,
    liggghts_beta,
    restitution_for_beta,
    tangential_damping_ratio,
    wall_copies,
    wall_material,
)
from orchestrator.engines.liggghts_files import write_data_file, write_stl_ascii
from orchestrator.errors import OrchestratorError
from orchestrator.kinds.impact.analysis import EVENT_LIMIT
from orchestrator.kinds.impact.case import RIGID
from orchestrator.kinds.impact.physics import energy_scale, fastest_closing_speeds, poisson_ratio, young_modulus
from orchestrator.kinds.impact.yade import (
    domain_radius,
)

TEMPLATE = Path(__file__).resolve().parent / "templates" / "liggghts.in.j2"
PLANE_STL = "plane.stl"
DATA_FILE = "spheres.data"
#: Columns the deck asks of compute pair/gran/local and wall/gran/local, in LIGGGHTS's order.
CONTACT_COLUMNS = ("x1", "y1", "z1", "x2", "y2", "z2", "vx1", "vy1", "vz1", "vx2", "vy2", "vz2", "id1", "id2", "id3",
                   "fx", "fy", "fz", "fnx", "fny", "fnz", "delta")
ATOM_COLUMNS = ("id", "radius", "mass", "x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz")


def _damping_beta(scene, pair) -> float:
    """LIGGGHTS's beta for a pair under model.damping ('engine': LIGGGHTS's own reading of e_n)."""
    if pair.alpha is None:
        return beta_for_restitution(pair.restitution)
    return liggghts_beta(pair.alpha)


def _elastic(case, name) -> tuple[float, float]:

    return young_modulus(case, name), poisson_ratio(case, name)


def check_impact_scene(scene) -> None:
    """Refuse what LIGGGHTS 3.8 cannot run: sphere-sphere damping beyond its restitution floor, wall copies
    shared by spheres of several materials."""
    case = scene.case
    for a, b in sorted(_sphere_pairs(scene)):
        pair = scene.pair(a, b)
        beta = _damping_beta(scene, pair)
        if beta > MAX_BETA:
            raise OrchestratorError(
                f"contacts ({a}, {b}): restitution = {pair.restitution} with model.damping = "
                f"{case.model.damping!r} needs a damping ratio beta = {beta:.3g}; LIGGGHTS 3.8 accepts at most "
                f"{MAX_BETA:.3g} between spheres (coefficientRestitution > 0.05); run it on yade or reference, or "
                "raise the restitution")
    copies = _plane_copies(scene)
    if copies > 1 and len(set(scene.sphere_materials)) > 1:
        raise OrchestratorError(
            f"the plane needs {copies} copies on LIGGGHTS for its damping (beta beyond 3.8's limit), which only "
            "works for spheres of one material; this scene has "
            f"{', '.join(sorted(set(scene.sphere_materials)))}; run it on yade or reference")


def _sphere_pairs(scene) -> set:
    kinds = sorted(set(scene.sphere_materials))
    counts = {k: scene.sphere_materials.count(k) for k in kinds}
    return {tuple(sorted((a, b))) for a in kinds for b in kinds if a != b or counts[a] > 1}


def _plane_copies(scene) -> int:
    if scene.plane_material is None:
        return 1
    betas = [_damping_beta(scene, scene.pair(m, scene.plane_material)) for m in set(scene.sphere_materials)]
    return max(wall_copies(b) for b in betas)


def liggghts_deviations(case, scene=None) -> str:
    """What LIGGGHTS runs differently from what the case asks ('' if nothing)."""
    notes = []
    sliding = any(c.friction > 0 for c in case.contacts)
    if sliding and case.model.coulomb_limit == "total":
        notes.append("model.coulomb_limit = 'total' asked; LIGGGHTS bounds only the elastic tangential force and "
                     "adds the dash-pot while a contact sticks (its tangential history model has no other rule)")
    if sliding:
        ratios = ""
        if scene is not None:
            ratios = ", ".join(f"{tangential_damping_ratio(*_elastic(case, a), *_elastic(case, b)):.3g} for {a}-{b}"
                               for (a, b), p in sorted(scene.pairs.items()) if p.friction > 0)
        notes.append("LIGGGHTS keeps the total tangential displacement (F_t = -k_t(delta) s) where the paper "
                     "increments the force, and damps tangentially with c_t = c_n sqrt(k_t / (3/2 k_n))"
                     + (f" ({ratios})" if ratios else ""))
    if scene is not None:
        # a rigid partner takes Mindlin's limit in the reference too
        unlike = [p for (a, b), p in scene.pairs.items() if a != b and p.friction > 0 and RIGID not in (a, b)]
        if unlike:
            notes.append("unlike materials in contact get Mindlin's k_t = 8 G* sqrt(R delta), not eq. 5's "
                         "4 G_m / (2 - nu_m)")
    if case.model.damping == "engine" and any(c.e_t != c.restitution for c in case.contacts):
        notes.append("LIGGGHTS damps both directions with e_n (no separate e_t)")
    return "; ".join(notes)


def _types(scene) -> tuple[list[str], dict[str, int]]:
    kinds = sorted(set(scene.sphere_materials))
    return kinds, {name: k + 1 for k, name in enumerate(kinds)}


def impact_context(scene) -> dict:
    """Plain values the impact deck needs (SI units)."""

    case = scene.case
    kinds, type_of = _types(scene)
    n_types = len(kinds) + (1 if scene.plane_material is not None else 0)
    young = [_elastic(case, k)[0] for k in kinds]
    poisson = [_elastic(case, k)[1] for k in kinds]
    restitution = np.ones((n_types, n_types))
    friction = np.zeros((n_types, n_types))
    for a in kinds:
        for b in kinds:
            key = tuple(sorted((a, b)))
            if key in scene.pairs:
                pair = scene.pairs[key]
                i, j = type_of[a] - 1, type_of[b] - 1
                restitution[i, j] = restitution_for_beta(min(_damping_beta(scene, pair), MAX_BETA))
                friction[i, j] = pair.friction
    copies = _plane_copies(scene)
    plane = None
    reach = domain_radius(scene)
    if scene.plane_material is not None:
        wall_type = n_types
        e_wall, nu_wall = _elastic(case, scene.plane_material)
        if copies == 1:  # the plate's own material, or a rigid wall 1e6 times stiffer than the stiffest sphere
            material = wall_material(max(young), 0.3, e_wall, nu_wall, 1)
        else:  # one sphere material (check_impact_scene)
            material = wall_material(*_elastic(case, kinds[0]), e_wall, nu_wall, copies)
        young.append(material.young)
        poisson.append(material.poisson)
        for kind in kinds:
            pair = scene.pair(kind, scene.plane_material)
            beta = _damping_beta(scene, pair) / math.sqrt(copies)
            restitution[type_of[kind] - 1, wall_type - 1] = restitution[wall_type - 1, type_of[kind] - 1] = \
                restitution_for_beta(beta)
            friction[type_of[kind] - 1, wall_type - 1] = friction[wall_type - 1, type_of[kind] - 1] = pair.friction
        plane = {"type": wall_type, "copies": copies, "normal": [repr(float(v)) for v in scene.plane_normal],
                 "offset": repr(float(scene.plane_point @ scene.plane_normal))}
    dt = scene.timestep
    n_steps = max(1, math.ceil(scene.duration / dt - 1e-9))
    record_every = max(1, round(scene.record_interval / dt))
    horizon = record_every * dt
    wall_speed, pair_speed = fastest_closing_speeds(case)
    g = float(np.linalg.norm(scene.gravity))
    track = scene.n_particles <= EVENT_LIMIT
    reach_plane = 2.0 * (float(wall_speed.max()) * horizon + 0.5 * g * horizon**2) + 1e-12
    reach_pair = 2.0 * (pair_speed * horizon) + 1e-12
    r_min = float(scene.radii.min())
    return {
        "n_types": n_types,
        "young": [repr(float(v)) for v in young],
        "poisson": [repr(float(v)) for v in poisson],
        "restitution": [repr(float(v)) for v in restitution.ravel()],
        "friction": [repr(float(v)) for v in friction.ravel()],
        "stiffness_scale": repr(case.numerics.stiffness_scale),
        "plane": plane,
        "pairs": scene.n_particles > 1,
        "track_events": track,
        "reach_plane": repr(reach_plane),
        "reach_pair": repr(reach_pair),
        "skin": repr(max(0.1 * r_min, 1.01 * reach_pair if track and scene.n_particles > 1 else 0.0)),
        "gravity": repr(g),
        "dt": repr(dt),
        "n_steps": n_steps,
        "planned_steps": n_steps,
        "record_every": record_every,
        "progress_every": max(1, n_steps // 200),
        "domain_radius": repr(reach),
        "energy_scale": repr(energy_scale(case)),
        "deviation": liggghts_deviations(case, scene),
    }


def write_impact_files(scene, workdir: Path) -> None:
    """spheres.data (read_data) and, with a plane, plane.stl into workdir."""
    case = scene.case
    kinds, type_of = _types(scene)
    reach = domain_radius(scene)
    lo = scene.positions.min(axis=0) - reach
    hi = scene.positions.max(axis=0) + reach
    densities = np.array([case.materials[m].density for m in scene.sphere_materials])
    n_types = len(kinds) + (1 if scene.plane_material is not None else 0)
    write_data_file(Path(workdir) / DATA_FILE, np.column_stack([lo, hi]), n_types,
                    np.array([type_of[m] for m in scene.sphere_materials]), scene.radii, densities, scene.positions,
                    scene.velocities, scene.angular_velocities)
    if scene.plane_material is not None:
        triangle = scene.plane_triangle(reach)
        # LIGGGHTS meshes are two-sided; the corner order only fixes the STL normal, which it ignores
        write_stl_ascii(Path(workdir) / PLANE_STL, triangle, np.array([[0, 1, 2]]), "plane")
