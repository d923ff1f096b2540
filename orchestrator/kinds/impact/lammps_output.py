"""What a LAMMPS impact run wrote (output/spheres.dump, output/status.txt, the screen log), read back into the run.h5
names every impact backend writes: the series, the contact events (orchestrator.reference.dem_forces.EVENT_FIELDS,
built as Yade's track() builds them) and the status.

The dump holds each sphere's state, the total force on it and the force of each wall fix on it (fix wall/gran/region
``contacts``: a flag, then the force). A wall contact's force is the wall fix's; a sphere pair's force is what is
left of the spheres' forces after the walls and gravity, split among the pairs in contact (LAMMPS reports no
per-contact total force: ``compute pair/local`` gives the elastic normal part only). The split is exact wherever
the contacts of a step form no closed loop (every impact, a chain); around a loop (a dense pile, whose series alone
use it) it is the least-squares one. LAMMPS cannot stop itself on a blow-up: the reader finds it afterwards, with the
messages and advice of Yade's runs.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from orchestrator.engines.base import Result
from orchestrator.engines.liggghts_files import engine_error, read_dump, read_table
from orchestrator.kinds.impact.analysis import EVENT_LIMIT, OTHER_PLANE, OTHER_SPHERE
from orchestrator.kinds.impact.liggghts_output import contact_events
from orchestrator.kinds.impact.physics import energy_scale
from orchestrator.kinds.impact.yade import (
    ENERGY_GROWTH,
    MAX_OVERLAP_FRACTION,
    domain_radius,
    fill_impact_events,
    fill_impact_series,
    instability_advice,
)
from orchestrator.runner import LOG_NAME, tail

DUMP = "output/spheres.dump"
STATUS = "output/status.txt"
#: Per-sphere columns of the dump, in the deck's order; each wall fix adds f_<fix>[1..4] (contact flag, force).
ATOM_COLUMNS = ("id", "type", "radius", "mass", "x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz",
                "fx", "fy", "fz")
#: A connected group of sphere pairs in contact larger than this is split with sparse least squares.
DENSE_SPLIT_LIMIT = 400
_LOOP = re.compile(r"Loop time of (\S+) on (\d+) procs for (\d+) steps")


def dump_columns(wall_types: list[int]) -> list[str]:
    """The dump's columns: ATOM_COLUMNS, then flag and force of the wall fix of each sphere type in wall_types."""
    return list(ATOM_COLUMNS) + [f"f_wall_{t}[{k}]" for t in wall_types for k in (1, 2, 3, 4)]


def _record(columns: list[str], rows: np.ndarray) -> dict[str, np.ndarray]:
    """One snapshot, sorted by id: radius, mass (n,), x, v, spin, force, wall_force (n, 3), on_wall (n,) bool."""
    rows = rows[np.argsort(rows[:, columns.index("id")])]
    col = {name: rows[:, k] for k, name in enumerate(columns)}
    vector = lambda *names: np.column_stack([col[n] for n in names])
    walls = sorted({name.split("[")[0] for name in columns if name.startswith("f_wall_")})
    wall_force = sum((vector(*(f"{w}[{k}]" for k in (2, 3, 4))) for w in walls), np.zeros((len(rows), 3)))
    on_wall = np.zeros(len(rows), bool)
    for w in walls:
        on_wall |= col[f"{w}[1]"] > 0
    return {"radius": col["radius"], "mass": col["mass"], "x": vector("x", "y", "z"), "v": vector("vx", "vy", "vz"),
            "spin": vector("omegax", "omegay", "omegaz"), "force": vector("fx", "fy", "fz"),
            "wall_force": wall_force, "on_wall": on_wall}


def _touching_pairs(x: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """(k, 2) index pairs i < j of spheres that overlap (LAMMPS's test: distance < R_i + R_j)."""
    from scipy.spatial import cKDTree

    if len(x) < 2:
        return np.zeros((0, 2), dtype=np.int64)
    candidates = cKDTree(x).query_pairs(2.0 * float(radius.max()), output_type="ndarray")
    if not len(candidates):
        return np.zeros((0, 2), dtype=np.int64)
    gap = np.linalg.norm(x[candidates[:, 0]] - x[candidates[:, 1]], axis=1) - radius[candidates].sum(axis=1)
    return np.sort(candidates[gap < 0.0], axis=1)


def split_pair_forces(pairs: np.ndarray, residual: np.ndarray) -> np.ndarray:
    """Force (k, 3), N, on sphere pairs[:, 0] from pairs[:, 1] such that each sphere's pair forces add up to its
    residual (n, 3), N (its force less walls and gravity): per connected group of pairs, least squares (exact
    without closed loops)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.sparse.linalg import lsqr

    n = len(residual)
    forces = np.zeros((len(pairs), 3))
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    for group in np.unique(label[pairs[:, 0]]):
        members = np.flatnonzero(label[pairs[:, 0]] == group)
        spheres = np.unique(pairs[members])
        row = {s: k for k, s in enumerate(spheres)}
        a = np.zeros((len(spheres), len(members)))
        for c, (i, j) in enumerate(pairs[members]):
            a[row[i], c], a[row[j], c] = 1.0, -1.0
        b = residual[spheres]
        if len(members) <= DENSE_SPLIT_LIMIT:
            forces[members] = np.linalg.lstsq(a, b, rcond=None)[0]
        else:
            forces[members] = np.column_stack([lsqr(a, b[:, k], atol=1e-14, btol=1e-14)[0] for k in range(3)])
    return forces


def step_contacts(record: dict, plane, gravity: np.ndarray, dt: float) -> dict:
    """The contacts of one snapshot as the event builder takes them: keys (sphere, other kind, other), overlap m,
    approach rate m/s, normal force N, force on the sphere (k, 3) N. plane: (point, unit normal) or None; dt: s.

    The approach rate is that of the velocities the step's forces were computed with, half a step before the
    dumped ones (velocity Verlet: v - dt/2 f/m), as LIGGGHTS's contact computes report it: the first step in
    contact sees the impact speed before the contact acted."""
    x, radius = record["x"], record["radius"]
    v = record["v"] - 0.5 * dt * record["force"] / record["mass"][:, None]
    keys, overlap, rate, normal_force, force = [], [], [], [], []
    if plane is not None:
        point, normal = plane
        for s in np.flatnonzero(record["on_wall"]):
            keys.append((int(s), OTHER_PLANE, 0))
            overlap.append(radius[s] - float((x[s] - point) @ normal))
            rate.append(-float(v[s] @ normal))
            force.append(record["wall_force"][s])
            normal_force.append(float(record["wall_force"][s] @ normal))
    pairs = _touching_pairs(x, radius)
    if len(pairs):
        residual = record["force"] - record["wall_force"] - record["mass"][:, None] * gravity
        on_first = split_pair_forces(pairs, residual)
        d = x[pairs[:, 0]] - x[pairs[:, 1]]
        distance = np.linalg.norm(d, axis=1)
        n = d / distance[:, None]
        for c, (i, j) in enumerate(pairs):
            keys.append((int(i), OTHER_SPHERE, int(j)))
            overlap.append(radius[i] + radius[j] - distance[c])
            rate.append(-float((v[i] - v[j]) @ n[c]))
            force.append(on_first[c])
            normal_force.append(float(on_first[c] @ n[c]))
    return {"keys": keys, "overlap": np.array(overlap, float), "rate": np.array(rate, float),
            "normal_force": np.array(normal_force, float), "force": np.array(force, float).reshape(-1, 3)}


def read_impact_output(scene, workdir: Path, deviation: str = "") -> Result:
    """Parse a LAMMPS impact run in workdir, complete or partial, into a Result with Yade's run.h5 names."""
    workdir = Path(workdir)
    dt, n = scene.timestep, scene.n_particles
    plane = None if scene.plane_normal is None else (scene.plane_point, scene.plane_normal)
    steps, records, lost = [], [], False
    for step, columns, rows in read_dump(workdir / DUMP):
        if len(rows) != n:
            lost = True  # LAMMPS dropped a sphere that left the box; the last complete record is kept
            break
        if steps and steps[-1] == step:
            continue
        steps.append(step)
        records.append(_record(columns, rows))
    contacts = {step: step_contacts(r, plane, scene.gravity, dt) for step, r in zip(steps, records)}
    log = tail(workdir / LOG_NAME, 400) if (workdir / LOG_NAME).is_file() else ""
    finished = read_table(workdir / STATUS).get("step", np.zeros(0))
    result = Result()
    last = int(finished[-1]) if len(finished) else (steps[-1] if steps else 0)
    result.attrs.update(n_steps=last, dt=dt, simulated_time=last * dt)
    loops = _LOOP.findall(log)
    if loops:
        result.attrs["engine_wall_time_s"] = float(loops[-1][0])
    record_every = max(1, round(scene.record_interval / dt))
    kept = [k for k, s in enumerate(steps) if s % record_every == 0 or k == len(steps) - 1]
    if kept:
        _fill_series(result, scene, [steps[k] for k in kept], [records[k] for k in kept], contacts)
    if n <= EVENT_LIMIT:
        fill_impact_events(result, contact_events(contacts, dt))
    error = engine_error(log)
    unstable = _instability(scene, result, contacts, lost or "Lost atoms" in error)
    if unstable:
        result.status, result.message = "unstable", f"{unstable}; {instability_advice(scene, unstable)}"
    elif error:
        result.status, result.message = "failed", f"LAMMPS stopped with an error: {error}"
    elif not len(finished):
        result.status, result.message = "failed", "LAMMPS wrote no final status (it was stopped or crashed)"
    if deviation:
        result.attrs["deviation"] = deviation
    return result


def _fill_series(result: Result, scene, steps: list[int], records: list[dict], contacts: dict) -> None:
    n = scene.n_particles
    stack = lambda name: np.stack([r[name] for r in records])
    mass, radius = stack("mass"), stack("radius")
    positions, velocities, spins = stack("x"), stack("v"), stack("spin")
    kinetic = 0.5 * np.sum(mass * np.sum(velocities**2, axis=-1), axis=1) + \
        0.5 * np.sum(0.4 * mass * radius**2 * np.sum(spins**2, axis=-1), axis=1)
    at = [contacts[s] for s in steps]
    on_plane = [np.array([k[1] == OTHER_PLANE for k in c["keys"]], bool) for c in at]
    columns = {
        "time": np.array(steps, float) * scene.timestep,
        "kinetic_energy": kinetic,
        "potential_energy": -np.sum(mass * (positions @ scene.gravity), axis=1),
        "normal_force": np.array([c["normal_force"].sum() for c in at]),
        "max_overlap": np.array([c["overlap"].max() if len(c["overlap"]) else 0.0 for c in at]),
        "n_contacts": np.array([len(c["keys"]) for c in at], dtype=float),
    }
    wall = np.array([-c["force"][mask].sum(axis=0) for c, mask in zip(at, on_plane)]).reshape(-1, 3)
    columns.update(wall_fx=wall[:, 0], wall_fy=wall[:, 1], wall_fz=wall[:, 2])
    for name, block in (("pos", positions), ("vel", velocities), ("spin", spins)):
        for k in range(n):
            for c, axis in enumerate("xyz"):
                columns[f"{name}_{k}_{axis}"] = block[:, k, c]
    fill_impact_series(result, columns, n)


def _instability(scene, result: Result, contacts: dict, lost: bool) -> str:
    """The first sign of a blow-up in what the run wrote ('' if none), with Yade's wording."""
    dt, radii = scene.timestep, scene.radii
    for step in sorted(contacts):
        c = contacts[step]
        for k, key in enumerate(c["keys"]):
            radius = radii[key[0]] if key[1] == OTHER_PLANE else min(radii[key[0]], radii[key[2]])
            overlap = c["overlap"][k]
            if not np.isfinite(overlap) or overlap > MAX_OVERLAP_FRACTION * radius:
                return (f"a contact overlap reached {overlap / radius:.3g} of the sphere radius at t = "
                        f"{step * dt:.6g} s (allowed {MAX_OVERLAP_FRACTION:.2g})")
    if result.time is not None and len(result.time):
        time = result.time
        total = result.series["kinetic_energy"].values + result.series["potential_energy"].values
        if not np.all(np.isfinite(total)):
            first = int(np.flatnonzero(~np.isfinite(total))[0])
            return f"a sphere position or velocity became NaN at t = {time[first]:.6g} s"
        scale = energy_scale(scene.case)
        grown = np.flatnonzero(total - total[0] > ENERGY_GROWTH * scale)
        if len(grown):
            k = int(grown[0])
            grew = total[k] - total[0]
            return (f"the kinetic plus potential energy grew by {grew:.3g} J, {100.0 * grew / scale:.3g} % of what "
                    f"the scene can release, by t = {time[k]:.6g} s")
        far = np.linalg.norm(result.series["positions"].values - scene.positions[None], axis=2).max(axis=1)
        out = np.flatnonzero(far > domain_radius(scene))
        if len(out):
            k = int(out[0])
            return (f"a sphere left the domain ({far[k]:.3g} m from its start, farther than the scene's energy "
                    f"allows, {domain_radius(scene):.3g} m) at t = {time[k]:.6g} s")
    if lost:
        return "a sphere left the domain (LAMMPS lost it from its box)"
    return ""
