"""The SPH verification checks of the penalty walls (eq. 14): a column at rest on a plane wall and a block sliding
down an inclined one (see checks.py for the row format)."""

from __future__ import annotations

import math

import numpy as np

from orchestrator.errors import OrchestratorError
from orchestrator.kinds.sph_flow.checks_base import (
    body_force_of,
    check_row,
    fluid_mask,
    frames_of,
    one_material,
    relative,
    tolerance_of,
)
from orchestrator.reference.sph_walls import penalty_force


# ------------------------------------------------------------------------------------------- penalty walls
def _plane_wall(case):

    if len(case.walls) != 1 or case.walls[0].shape != "plane":
        raise OrchestratorError(f"{case.case.name}: a penalty scene needs exactly one plane wall")
    wall = case.walls[0]
    normal = np.asarray(wall.normal, dtype=float)
    normal /= np.linalg.norm(normal)
    params = case.physics.wall_penalty

    def force(d):
        return penalty_force(d, params.range, params.s, params.psi)

    return wall, np.asarray(wall.center, dtype=float), normal, force


def _formula_rows(case, run, centre, normal, force):
    """The engine's wall force at each frame against eq. 14 summed over the frame's particle distances;
    the smallest distance to the plane over all frames."""
    name = case.case.name
    wall = case.walls[0].name
    series = run.get("series", {})
    time = np.asarray(series.get("time", []))
    recorded = np.asarray(series.get(f"wall_force_{wall}", np.zeros((0, case.dimension))))
    worst, last, d_min = 0.0, (math.nan, math.nan), math.inf
    for t, frame in frames_of(run):
        fluid = fluid_mask(frame)
        d = (np.asarray(frame["positions"])[fluid] - centre) @ normal
        d_min = min(d_min, float(d.min()))
        on_plane = float(np.sum(force(d)))  # N, on the particles, along the normal
        if not len(time):
            continue
        i = int(np.argmin(np.abs(time - t)))
        if abs(time[i] - t) > 1e-9 * max(t, 1.0):
            continue
        engine = -float(recorded[i] @ normal)  # the series is the reaction on the mesh
        worst = max(worst, abs(engine - on_plane) / max(abs(on_plane), 1e-300))
        last = (engine, on_plane)
    rows = [
        check_row(name, "eq14_wall_force", last[0], last[1], worst, tolerance_of(case, "eq14_wall_force"),
             source="eq. 14 (orchestrator.reference.sph_walls.penalty_force) at each frame's distances",
             note="eq14_wall_force: value = the engine's recorded wall force along the normal, expected = eq. 14 "
                  "summed over the particles at the last frame; rel_error = worst over all frames"),
        check_row(name, "min_distance_to_wall", d_min, 0.0, None, None, passed=d_min > 0.0, source="no crossing",
             note="min_distance_to_wall: smallest particle-plane distance over every frame; passes when > 0"),
    ]
    return rows


def check_penalty_column(case, run) -> tuple[list[dict], dict]:
    """A column resting on a penalty floor: the floor carries the weight; eq. 14; no crossing."""
    name = case.case.name
    _, centre, normal, force = _plane_wall(case)
    g = body_force_of(case)
    frames = frames_of(run)
    first = frames[0][1] if frames else None
    mass = float(one_material(case, "penalty_column").rho0 * case.numerics.dx ** case.dimension)
    n_fluid = int(np.count_nonzero(fluid_mask(first))) if first is not None else 0
    weight = mass * n_fluid * float(-(g @ normal))
    series = run.get("series", {})
    time = np.asarray(series.get("time", []))
    recorded = np.asarray(series.get(f"wall_force_{case.walls[0].name}", np.zeros((0, case.dimension))))
    push = -(recorded @ normal) if len(recorded) else np.zeros(0)  # the fluid pushes the floor against n
    late = time >= 0.5 * case.simulation.duration
    mean = float(np.mean(push[late])) if late.any() else math.nan
    rows = [check_row(name, "floor_force", mean, weight, relative(mean, weight), tolerance_of(case, "floor_force"),
                 source="weight of the column, rho0 N dx^3 g",
                 note="floor_force: the fluid's push on the floor along -n, averaged over the second half of the run")]
    rows += _formula_rows(case, run, centre, normal, force)
    plot = {"title": f"{name}: floor force", "xlabel": "t [s]", "ylabel": "force on the floor [N]",
            "lines": [(time, push, "-", "C0", "engine (eq. 14)"), (time, np.full(len(time), weight), "--", "k",
                                                                   "weight")]}
    return rows, plot


def check_penalty_incline(case, run) -> tuple[list[dict], dict]:
    """One particle on an inclined penalty plane: keeps eq. 14's balance distance, slides g sin(theta) t^2 / 2."""
    from scipy.optimize import brentq

    name = case.case.name
    wall, centre, normal, force = _plane_wall(case)
    g = body_force_of(case)
    frames = frames_of(run)
    mass = float(one_material(case, "penalty_incline").rho0 * case.numerics.dx ** case.dimension)
    load = mass * float(-(g @ normal))  # weight across the plane, N
    params = case.physics.wall_penalty
    d_star = brentq(lambda d: float(force(d)) - load, 0.0, params.s, xtol=1e-16 * params.s)
    along = g - (g @ normal) * normal  # m/s^2, down the slope
    t = np.array([time for time, _ in frames])
    x = np.array([np.asarray(f["positions"])[fluid_mask(f)][0] for _, f in frames])
    slide = (x - x[0]) @ along / np.linalg.norm(along)
    slide_exact = 0.5 * np.linalg.norm(along) * t**2
    d = (x - centre) @ normal
    series = run.get("series", {})
    recorded = np.asarray(series.get(f"wall_force_{wall.name}", np.zeros((0, case.dimension))))
    pressed = -(recorded @ normal) if len(recorded) else np.zeros(1) * math.nan
    rows = [
        check_row(name, "slide_distance", slide[-1], slide_exact[-1], relative(slide[-1], slide_exact[-1]),
             tolerance_of(case, "slide_distance"), source="frictionless slide g sin(theta) t^2 / 2",
             note=f"slide_distance: along the slope after {t[-1]:.3g} s"),
        check_row(name, "distance_to_plane", d[-1], d_star, float(np.max(np.abs(d - d_star))) / d_star,
             tolerance_of(case, "distance_to_plane"),
             source="eq. 14 balance F(d*) = m g cos(theta)",
             note="distance_to_plane: rel_error = largest deviation from d* over every frame / d*"),
        check_row(name, "plane_force", float(np.mean(pressed)), load, float(np.max(np.abs(pressed - load))) / load,
             tolerance_of(case, "plane_force"), source="m g cos(theta)",
             note="plane_force: the particle's push on the plane along -n; rel_error = worst record"),
    ]
    rows += _formula_rows(case, run, centre, normal, force)
    plot = {"title": f"{name}: slide", "xlabel": "t [s]", "ylabel": "distance down the slope [mm]",
            "lines": [(t, slide * 1e3, "o", "C0", "engine"), (t, slide_exact * 1e3, "-", "k", "g sin(theta) t^2 / 2")]}
    return rows, plot
