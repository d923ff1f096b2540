"""What a scratch run measured (run.h5 /measured) from the grain's series and the target's frames. Lengths in m,
energies in J, temperatures in K.

Definitions (the top face is z = 0, the top layer's centres start at z = -dx/2; dx the spacing):
- removed particles: failed ones (damage >= 1) with no unfailed target or held particle within REACH dx at the end:
  separated from the workpiece; their volume is count dx^3, their mass count rho0 dx^3; chips are the connected
  clusters of removed particles, two linked when closer than REACH dx;
- the surface at the end: at the lattice's columns (where they started, x and y), the highest remaining (not
  removed) target particle within SAMPLE dx horizontally at the end; its depth is how far it lies below -dx/2;
- the kerf: the columns deeper than KERF_DEPTH dx; its length and width are their extent along x and y (column
  edges included), its depth the deepest column;
- the pile-up: the highest rise of a remaining target particle above its start ahead of the kerf's deepest column;
- plastic work: sum m C_p (T - T0) / chi over the target (eq. 12 read backwards), and the target's internal
  energy beside it (plastic work turned to heat plus the elastic and compression energy).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.kinds.scratch.pictures import plot_scratch
from orchestrator.kinds.sph_flow.removal import REACH, REMOVAL_QUANTITIES, chips, removed
from orchestrator.kinds.scratch.scene import grain_spheres
from orchestrator.kinds.sph_flow.case_impactors import mass_properties
from orchestrator.kinds.base import print_run_measures

#: A surface column deeper than this many dx below its start belongs to the kerf.
KERF_DEPTH = 0.25
#: The surface's height at a column is the highest remaining particle within this many dx of it horizontally (any
#: point of a cubic lattice lies within 0.71 dx of one of its columns).
SAMPLE = 0.75

#: The measured quantities: name -> (SI unit, meaning).
QUANTITIES: dict[str, tuple[str, str]] = {
    "kerf_length": ("m", f"extent along x of the columns where the surface ends more than {KERF_DEPTH} dx below its start"),
    "kerf_width": ("m", "extent along y of the same columns"),
    "kerf_depth": ("m", "the deepest surface column below its start"),
    "pile_up": ("m", "the highest rise of a remaining target particle ahead of the kerf's deepest column"),
    "max_penetration": ("m", "the grain's lowest point below the top face during the run"),
    "max_temperature": ("K", "highest temperature in the target over the frames"),
    "max_plastic_strain": ("-", "largest equivalent plastic strain in the target at the end"),
    "plastic_work": ("J", "sum m C_p (T - T0) / chi over the target at the end"),
    "internal_energy": ("J", "the target's internal energy at the end"),
    "plastic_work_fraction": ("-", "plastic_work over the grain's initial kinetic energy"),
    "grain_speed_end": ("m/s", "the grain's speed at the end"),
    **REMOVAL_QUANTITIES,
    "removed_mass": ("kg", "removed_count rho0 dx^3"),
    "chips": ("-", f"connected clusters of removed particles (linked within {REACH} dx)"),
    "largest_chip": ("-", "particles in the largest chip"),
    "energy_balance": ("-", ("(grain kinetic, contact, target kinetic and internal energy) at the end over the "
                             "grain's initial kinetic energy, minus 1")),
}


def kerf(x0: np.ndarray, x: np.ndarray, keep: np.ndarray, dx: float) -> dict[str, float]:
    """Kerf length, width, depth (m) and the pile-up (m) ahead of it, from the target's start x0 and end x (n, 3) m
    and the mask of its remaining particles. The surface is sampled where the lattice's columns started (x, y): its
    height there is the highest remaining particle within SAMPLE dx (horizontally) at the end, its depth how far
    that lies below -dx/2. Material the grain pushes along stays where it ends (an Eulerian surface)."""
    from scipy.spatial import cKDTree

    columns = np.unique(np.round(x0[:, :2] / dx - 0.5).astype(np.int64), axis=0)
    points = (columns + 0.5) * dx
    near = cKDTree(x[keep, :2]).query_ball_point(points, SAMPLE * dx)
    z = x[keep, 2]
    top = np.array([z[i].max() if len(i) else np.nan for i in near])
    depth = -0.5 * dx - top
    known = np.isfinite(depth)
    if not known.any():
        return {}
    groove = known & (depth > KERF_DEPTH * dx)
    if not groove.any():
        return {"kerf_depth": float(max(np.nanmax(depth), 0.0))}
    g = columns[groove]
    deepest = points[np.nanargmax(depth)]
    ahead = x[keep, 0] > deepest[0] + 0.5 * dx
    out = {"kerf_length": float((g[:, 0].max() - g[:, 0].min() + 1) * dx),
           "kerf_width": float((g[:, 1].max() - g[:, 1].min() + 1) * dx), "kerf_depth": float(np.nanmax(depth))}
    if ahead.any():
        out["pile_up"] = float(np.max(x[keep][ahead, 2] - x0[keep][ahead, 2]))
    return out


def grain_energy(result) -> tuple[np.ndarray, np.ndarray]:
    """The grain's kinetic and contact energy series, J."""
    s = result.series
    return (np.asarray(s["impactor_grain_kinetic_energy"].values, dtype=float),
            np.asarray(s["impactor_grain_contact_energy"].values, dtype=float))


def target_energy(case, last: dict) -> dict[str, float]:
    """Kinetic and internal energy (J) and plastic work (J) of the target's moving particles in a frame (kinetic
    and internal of the run's particle masses, f rho0 dx^3 with a mass scaling f; the plastic work from the
    temperature, rho0 dx^3 C_p dT / chi, is the same with or without it)."""
    moving = np.asarray(last["kind"]) == 0
    mass = case.material.inertial_density() * case.numerics.dx**3
    v = np.asarray(last["velocities"], dtype=float)[moving]
    out = {"kinetic": 0.5 * mass * float(np.sum(v * v)),
           "internal": mass * float(np.sum(np.asarray(last["internal_energy"], dtype=float)[moving]))}
    s = case.material.solid
    if s.heat_fraction > 0.0 and "temperature" in last:
        t0 = s.room_temperature or 293.0
        heat = np.asarray(last["temperature"], dtype=float)[moving] - t0
        physical = case.material.density * case.numerics.dx**3
        out["plastic_work"] = physical * s.heat_capacity * float(np.sum(heat)) / s.heat_fraction
    return out


def surface(case, first: dict, last: dict) -> dict[str, float]:
    """The kerf, the pile-up, the removed particles and chips, the plastic strain, from the first and last frame."""
    dx = case.numerics.dx
    moving = np.asarray(first["kind"]) == 0
    x0 = np.asarray(first["positions"], dtype=float)
    x = np.asarray(last["positions"], dtype=float)
    damage = np.asarray(last.get("damage", np.zeros(len(x))), dtype=float)
    gone = removed(x, np.where(moving, damage, 0.0), np.ones(len(x), dtype=bool), dx) & moving
    out = kerf(x0[moving], x[moving], ~gone[moving], dx)
    labels = chips(x[gone], dx)
    out.update({"failed_count": float(np.sum((damage >= 1.0) & moving)), "removed_count": float(gone.sum()),
                "removed_volume": float(gone.sum()) * dx**3,
                "removed_mass": float(gone.sum()) * case.material.density * dx**3,
                "chips": float(labels.max() + 1) if labels.size else 0.0,
                "largest_chip": float(np.bincount(labels).max()) if labels.size else 0.0})
    if "plastic_strain" in last:
        out["max_plastic_strain"] = float(np.max(np.asarray(last["plastic_strain"])[moving]))
    return out


def measure_scratch(case, result) -> dict[str, float]:
    """Measured quantities of a scratch run (QUANTITIES); empty without its series."""
    if "impactor_grain_position" not in result.series or len(result.time) < 2:
        return {}
    kinetic, contact = grain_energy(result)
    velocity = np.asarray(result.series["impactor_grain_velocity"].values, dtype=float)
    position = np.asarray(result.series["impactor_grain_position"].values, dtype=float)
    measured = {"grain_speed_end": float(np.linalg.norm(velocity[-1]))}
    if len(result.frames) >= 2:
        first, last = result.frames[0][1], result.frames[-1][1]
        measured.update(surface(case, first, last))
        orientation = np.asarray(result.series["impactor_grain_orientation"].values, dtype=float)
        measured["max_penetration"] = float(max(-lowest_point(case, position, orientation).min(), 0.0))
        if "temperature" in last:
            moving = np.asarray(first["kind"]) == 0
            measured["max_temperature"] = max(float(np.max(np.asarray(f["temperature"])[moving]))
                                              for _, f in result.frames if "temperature" in f)
        if "internal_energy" in last and kinetic[0] > 0.0:
            e = target_energy(case, last)
            measured["internal_energy"] = e["internal"]
            final = e["kinetic"] + e["internal"] + float(kinetic[-1] + contact[-1])
            measured["energy_balance"] = final / float(kinetic[0]) - 1.0
            if "plastic_work" in e:
                measured["plastic_work"] = e["plastic_work"]
                measured["plastic_work_fraction"] = e["plastic_work"] / float(kinetic[0])
    return {k: v for k, v in measured.items() if math.isfinite(v)}


def rotation(q: np.ndarray) -> np.ndarray:
    """The rotation matrices (m, 3, 3) of unit quaternions (m, 4) w, x, y, z."""
    w, x, y, z = (q / np.linalg.norm(q, axis=1, keepdims=True)).T
    return np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
                     np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
                     np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], 1)


def lowest_point(case, position: np.ndarray, orientation: np.ndarray) -> np.ndarray:
    """The height (m) of the grain's lowest point at each record, from its centre of mass (m, 3) m and orientation
    (m, 4): its spheres turned by the rotation since the start."""
    spheres = grain_spheres(case)
    centre = mass_properties(spheres, case.grain.density)[1]
    turn = rotation(orientation) @ rotation(orientation[:1])[0].T
    relative = spheres[:, :3] - centre
    z = np.einsum("mj,kj->mk", turn[:, 2, :], relative) + position[:, 2:3] - spheres[:, 3]
    return z.min(axis=1)


def analyze_scratch_run(run_dir: Path, run: dict, case, render: bool = True) -> dict:
    """Print the measured quantities (QUANTITIES) and write scratch.png. Returns {name: path}."""
    print_run_measures(run_dir, run, QUANTITIES)
    if not render:
        return {}
    path = plot_scratch(run, case, Path(run_dir) / "scratch.png")
    print(f"{'picture':<24} {path}")
    return {"picture": path}
