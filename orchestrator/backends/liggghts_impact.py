"""LIGGGHTS backend, impact scenes: the deck's context (materials, damping,
wall copies; liggghts_physics.py says how the law maps), the files it reads,
and the reader that turns its dumps into the series and contact events Yade's
impact runs have (analysis.impact.EVENT_FIELDS, same definitions).

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

from ..case.impact import RIGID
from ..errors import OrchestratorError
from .base import Result
from .liggghts import engine_error, read_dump, read_table, write_data_file, write_stl_ascii
from .liggghts_physics import (MAX_BETA, beta_for_restitution, liggghts_beta, restitution_for_beta,
                               tangential_damping_ratio, wall_copies, wall_material)
from .yade_impact import (ENERGY_GROWTH, MAX_OVERLAP_FRACTION, domain_radius, fill_impact_events,
                          fill_impact_series, instability_advice)

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
    from ..scene.impact import poisson_ratio, young_modulus

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
    from ..analysis.impact import EVENT_LIMIT
    from ..scene.impact import energy_scale, fastest_closing_speeds

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


# ---- output ----
def _contacts_by_step(out: Path, kind: str, n_spheres: int) -> dict[int, dict[str, np.ndarray]]:
    """step -> merged contacts of one dump: keys (sphere index, other kind, other index), overlap m, approach rate
    m/s, normal force N, force on the sphere (k,3) N. Coincident wall copies are summed into one contact."""
    from ..analysis.impact import OTHER_PLANE, OTHER_SPHERE

    out_steps = {}
    for step, columns, rows in read_dump(out / f"{kind}.dump"):
        if not len(rows):
            out_steps[step] = None
            continue
        col = {name: rows[:, k] for k, name in enumerate(CONTACT_COLUMNS[: rows.shape[1]])}
        p1 = np.column_stack([col["x1"], col["y1"], col["z1"]])
        p2 = np.column_stack([col["x2"], col["y2"], col["z2"]])
        v1 = np.column_stack([col["vx1"], col["vy1"], col["vz1"]])
        v2 = np.column_stack([col["vx2"], col["vy2"], col["vz2"]])
        force = np.column_stack([col["fx"], col["fy"], col["fz"]])
        fn = np.linalg.norm(np.column_stack([col["fnx"], col["fny"], col["fnz"]]), axis=1)
        if kind == "walls":  # body 1 is the contact point on the wall, body 2 the sphere (id3)
            sphere = col["id3"].astype(np.int64) - 1
            normal = p2 - p1
            normal /= np.linalg.norm(normal, axis=1)[:, None]
            rate = -np.einsum("ij,ij->i", v2 - v1, normal)
            keys = [(int(s), OTHER_PLANE, 0) for s in sphere]
        else:  # force on atom id1 from id2
            a, b = col["id1"].astype(np.int64) - 1, col["id2"].astype(np.int64) - 1
            normal = p2 - p1
            normal /= np.linalg.norm(normal, axis=1)[:, None]
            rate = np.einsum("ij,ij->i", v1 - v2, normal)
            keys = [(int(min(i, j)), OTHER_SPHERE, int(max(i, j))) for i, j in zip(a, b)]
        merged: dict = {}
        for k, key in enumerate(keys):
            entry = merged.setdefault(key, [col["delta"][k], rate[k], 0.0, np.zeros(3)])
            entry[2] += fn[k]
            entry[3] = entry[3] + force[k]
        out_steps[step] = {
            "keys": list(merged),
            "overlap": np.array([e[0] for e in merged.values()]),
            "rate": np.array([e[1] for e in merged.values()]),
            "normal_force": np.array([e[2] for e in merged.values()]),
            "force": np.array([e[3] for e in merged.values()]).reshape(-1, 3),
        }
    return out_steps


def _merge_steps(*tables) -> dict[int, dict]:
    steps = sorted(set().union(*(t.keys() for t in tables)))
    merged = {}
    for step in steps:
        parts = [t[step] for t in tables if t.get(step) is not None]
        if not parts:
            merged[step] = {"keys": [], "overlap": np.zeros(0), "rate": np.zeros(0), "normal_force": np.zeros(0),
                            "force": np.zeros((0, 3)), "plane": np.zeros(0, bool)}
            continue
        merged[step] = {name: (sum((p[name] for p in parts), []) if name == "keys" else
                               np.concatenate([p[name] for p in parts])) for name in parts[0]}
    return merged


def contact_events(steps: dict[int, dict], dt: float) -> dict[str, np.ndarray]:
    """Contact events (analysis.impact.EVENT_FIELDS) from the contacts of consecutive dumped steps, as Yade's
    track() builds them: start/end extrapolated with overlap / rate at the first / last step in contact."""
    open_events, closed = {}, []
    for step in sorted(steps):
        t = step * dt
        contacts = steps[step]
        seen = set()
        for k, key in enumerate(contacts["keys"]):
            overlap, rate, force = contacts["overlap"][k], contacts["rate"][k], contacts["normal_force"][k]
            seen.add(key)
            event = open_events.get(key)
            if event is None:
                event = open_events[key] = {
                    "sphere": key[0], "other_kind": key[1], "other": key[2],
                    "start_time": t - overlap / rate if rate > 0 else t, "impact_speed": rate,
                    "peak_normal_force": -1.0, "peak_time": t, "max_overlap": 0.0}
            if force > event["peak_normal_force"]:
                event["peak_normal_force"], event["peak_time"] = force, t
            event["max_overlap"] = max(event["max_overlap"], overlap)
            event["last"] = (t, overlap, rate)
        for key in [k for k in open_events if k not in seen]:
            event = open_events.pop(key)
            t_last, overlap, rate = event.pop("last")
            separating = -rate
            event["end_time"] = t_last + (overlap / separating if separating > 0 else 0.0)
            event["rebound_speed"] = separating
            closed.append(event)
    rows = closed + [dict({k: v for k, v in e.items() if k != "last"}, end_time=math.nan, rebound_speed=math.nan)
                     for e in open_events.values()]
    columns = ("sphere", "other_kind", "other", "start_time", "end_time", "impact_speed", "rebound_speed",
               "peak_normal_force", "peak_time", "max_overlap")
    return {c: np.array([row[c] for row in rows], dtype=float) for c in columns}


def _atom_records(out: Path, n_spheres: int) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    steps, arrays = [], {name: [] for name in ATOM_COLUMNS}
    for step, columns, rows in read_dump(out / "atoms.dump"):
        if len(rows) != n_spheres:
            break  # an atom was lost: the deck stops with an error, the last complete record is kept
        rows = rows[np.argsort(rows[:, columns.index("id")])]
        steps.append(step)
        for name in ATOM_COLUMNS:
            arrays[name].append(rows[:, columns.index(name)])
    return np.array(steps, dtype=np.int64), {name: np.array(v) for name, v in arrays.items()}


def read_impact_output(scene, workdir: Path) -> Result:
    """Parse output/ of a LIGGGHTS impact run, complete or partial, into a Result with Yade's run.h5 names."""
    from ..runner import LOG_NAME

    workdir = Path(workdir)
    out = workdir / "output"
    case = scene.case
    n = scene.n_particles
    dt = scene.timestep
    result = Result()
    steps, atoms = _atom_records(out, n)
    contacts = _merge_steps(_contacts_by_step(out, "walls", n), _contacts_by_step(out, "pairs", n))
    finished = read_table(out / "status.txt").get("step", np.zeros(0))
    log = (workdir / LOG_NAME).read_text(errors="replace") if (workdir / LOG_NAME).is_file() else ""
    error = engine_error(log)
    last_step = int(finished[-1]) if len(finished) else int(max([steps.max() if len(steps) else 0] + list(contacts)))
    result.attrs.update(n_steps=last_step, dt=dt, simulated_time=last_step * dt)
    if len(steps):
        _fill_series(result, scene, steps, atoms, contacts)
    from ..analysis.impact import EVENT_LIMIT

    if n <= EVENT_LIMIT:
        fill_impact_events(result, contact_events(contacts, dt))
    unstable = _instability(scene, result, steps, atoms, contacts, error)
    if unstable:
        result.status = "unstable"
        result.message = f"{unstable}; {instability_advice(scene, unstable)}"
    elif error:
        result.status, result.message = "failed", f"LIGGGHTS stopped with an error: {error}"
    elif not len(finished):
        result.status, result.message = "failed", "the engine wrote no final status (it was stopped or crashed)"
    deviation = liggghts_deviations(case, scene)
    if deviation:
        result.attrs["deviation"] = deviation
    return result


def _fill_series(result: Result, scene, steps, atoms, contacts) -> None:
    n = scene.n_particles
    g = scene.gravity
    positions = np.stack([atoms["x"], atoms["y"], atoms["z"]], axis=-1)
    velocities = np.stack([atoms["vx"], atoms["vy"], atoms["vz"]], axis=-1)
    spins = np.stack([atoms["omegax"], atoms["omegay"], atoms["omegaz"]], axis=-1)
    mass, radius = atoms["mass"], atoms["radius"]
    kinetic = 0.5 * np.sum(mass * np.sum(velocities**2, axis=-1), axis=1) + \
        0.5 * np.sum(0.4 * mass * radius**2 * np.sum(spins**2, axis=-1), axis=1)
    potential = -np.sum(mass * (positions @ g), axis=1)
    empty = {"keys": [], "overlap": np.zeros(0), "normal_force": np.zeros(0), "force": np.zeros((0, 3))}
    at = [contacts.get(int(s), empty) for s in steps]
    wall_force = np.array([-c["force"][[k[1] == 1 for k in c["keys"]]].sum(axis=0) if len(c["keys"]) else np.zeros(3)
                           for c in at])
    columns = {
        "time": steps * scene.timestep,
        "kinetic_energy": kinetic,
        "potential_energy": potential,
        "normal_force": np.array([c["normal_force"].sum() for c in at]),
        "max_overlap": np.array([c["overlap"].max() if len(c["overlap"]) else 0.0 for c in at]),
        "n_contacts": np.array([len(c["keys"]) for c in at], dtype=float),
        "wall_fx": wall_force[:, 0], "wall_fy": wall_force[:, 1], "wall_fz": wall_force[:, 2],
    }
    for name, block in (("pos", positions), ("vel", velocities), ("spin", spins)):
        for k in range(n):
            for c, axis in enumerate("xyz"):
                columns[f"{name}_{k}_{axis}"] = block[:, k, c]
    fill_impact_series(result, columns, n)


def _instability(scene, result, steps, atoms, contacts, error: str) -> str:
    """The first sign of a blow-up in what the run wrote ('' if none), with Yade's wording."""
    from ..scene.impact import energy_scale

    radii = scene.radii
    dt = scene.timestep
    for step in sorted(contacts):
        c = contacts[step]
        for k, key in enumerate(c["keys"]):
            radius = min(radii[key[0]], radii[key[2]]) if key[1] == 0 else radii[key[0]]
            overlap = c["overlap"][k]
            if not np.isfinite(overlap) or overlap > MAX_OVERLAP_FRACTION * radius:
                return ("a contact overlap reached %.3g of the sphere radius at t = %.6g s (allowed %.2g)"
                        % (overlap / radius, step * dt, MAX_OVERLAP_FRACTION))
    if len(steps):
        series = result.series
        total = series["kinetic_energy"].values + series["potential_energy"].values
        if not np.all(np.isfinite(total)):
            k = int(np.flatnonzero(~np.isfinite(total))[0])
            return "a sphere position or velocity became NaN at t = %.6g s" % (steps[k] * dt)
        scale = energy_scale(scene.case)
        grown = np.flatnonzero(total - total[0] > ENERGY_GROWTH * scale)
        if len(grown):
            k = int(grown[0])
            return ("the kinetic plus potential energy grew by %.3g J, %.3g %% of what the scene can release, by "
                    "t = %.6g s" % (total[k] - total[0], 100.0 * (total[k] - total[0]) / scale, steps[k] * dt))
        far = np.linalg.norm(series["positions"].values - scene.positions[None], axis=2).max(axis=1)
        out = np.flatnonzero(far > domain_radius(scene))
        if len(out):
            k = int(out[0])
            return ("a sphere left the domain (%.3g m from its start, farther than the scene's energy allows, "
                    "%.3g m) at t = %.6g s" % (far[k], domain_radius(scene), steps[k] * dt))
    if "Lost atoms" in error:
        return "a sphere left the domain (LIGGGHTS lost it: %s)" % error
    return ""
