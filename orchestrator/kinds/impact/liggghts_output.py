"""What a LIGGGHTS impact run wrote into output/, read back into the run.h5 names (liggghts_deck.py writes the deck)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.engines.base import Result
from orchestrator.engines.liggghts_files import engine_error, read_dump, read_table
from orchestrator.kinds.impact.analysis import EVENT_LIMIT, OTHER_PLANE, OTHER_SPHERE
from orchestrator.kinds.impact.liggghts_deck import ATOM_COLUMNS, CONTACT_COLUMNS, liggghts_deviations
from orchestrator.kinds.impact.physics import energy_scale
from orchestrator.kinds.impact.yade import (
    ENERGY_GROWTH,
    MAX_OVERLAP_FRACTION,
    domain_radius,
    fill_impact_events,
    fill_impact_series,
    instability_advice,
)
from orchestrator.reference.dem_forces import EVENT_FIELDS
from orchestrator.runner import LOG_NAME


# ---- output ----
def _contacts_by_step(out: Path, kind: str, n_spheres: int) -> dict[int, dict[str, np.ndarray]]:
    """step -> merged contacts of one dump: keys (sphere index, other kind, other index), overlap m, approach rate
    m/s, normal force N, force on the sphere (k,3) N. Coincident wall copies are summed into one contact."""

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
    """Contact events (the columns of EVENT_FIELDS) from the contacts of consecutive dumped steps, as Yade's
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
    return {c: np.array([row[c] for row in rows], dtype=float) for c in EVENT_FIELDS}


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
