"""The scenes the SPH benchmarks share (ours and the peers'): the 3D dam break, the neighbour count, one result row."""

from __future__ import annotations

import math
from dataclasses import dataclass

GRAVITY = 9.81  # m/s^2


@dataclass
class BenchRow:
    """One timed run. particle_steps_per_s: all particles x steps / loop wall time (1/s);
    per_core: the same over CPU time (1/s); neighbours: mean neighbours within 2h per fluid particle."""

    scene: str
    engine: str
    threads: int
    particles: int
    fluid: int
    steps: int
    neighbours: float
    wall_s: float
    cpu_s: float
    particle_steps_per_s: float
    per_core: float
    status: str = "ok"
    note: str = ""
    wait: str = "-"  # numerics.thread_wait of a run on several threads
    repeats: int = 1  # the row is the fastest of this many runs


def dam_break_3d_case(steps: int, threads: int, dx: float = 0.02, thread_wait: str = "passive") -> dict:
    """A 3D dam break: a 0.4 x 0.4 x 0.8 m column in a 1.2 m tank, periodic across (y), three wall layers."""
    layers, depth, length, wall = 3 * dx, 0.4, 1.2, 0.9
    c0 = 10.0 * math.sqrt(2.0 * GRAVITY * 0.8)
    return {
        "case": {"kind": "sph_flow", "name": "bench_dam_break_3d", "engine": "sph",
                 "description": "3D dam break slab, dx = 0.02 m, periodic across the flow"},
        "domain": {"dimension": 3, "lo": [-layers, 0.0, -layers], "hi": [length + layers, depth, wall],
                   "periodic": [1]},
        "fluid": {"density": 1000.0, "max_speed": c0 / 10.0},
        "physics": {"terms": ["artificial_viscosity", "body_force"], "body_force": [0.0, 0.0, -GRAVITY],
                    "artificial_viscosity": {"alpha": 0.1, "beta": 0.0}},
        "blocks": [
            {"name": "column", "kind": "fluid", "lo": [0.0, 0.0, 0.0], "hi": [0.4, depth, 0.8],
             "hydrostatic_surface": 0.8},
            {"name": "floor", "kind": "boundary", "lo": [-layers, 0.0, -layers], "hi": [length + layers, depth, 0.0]},
            {"name": "left", "kind": "boundary", "lo": [-layers, 0.0, 0.0], "hi": [0.0, depth, wall]},
            {"name": "right", "kind": "boundary", "lo": [length, 0.0, 0.0], "hi": [length + layers, depth, wall]},
        ],
        "numerics": {"dx": dx, "h_over_dx": 1.3, "max_steps": steps, "threads": threads,
                     "thread_wait": thread_wait},
        "simulation": {"duration": 10.0},
        "output": {"frame_interval": 10.0},
    }


def mean_neighbours(positions, kind, support: float, periodic_box=None) -> float:
    """Mean number of particles (fluid or boundary, self excluded) within `support` (m) of a fluid particle.

    periodic_box: per-axis period in m (None or 0 for a non-periodic axis).
    """
    import numpy as np
    from scipy.spatial import cKDTree

    positions = np.asarray(positions, dtype=float)
    boxsize = None
    if periodic_box is not None and any(periodic_box):
        # cKDTree wants every coordinate inside [0, L) on a periodic axis and a huge L elsewhere
        lo = positions.min(axis=0)
        positions = positions - lo
        span = positions.max(axis=0) + 2 * support
        boxsize = np.array([p if p else 10 * s for p, s in zip(periodic_box, span)])
        positions = np.mod(positions, boxsize)
    tree = cKDTree(positions, boxsize=boxsize)
    fluid = positions[np.asarray(kind) == 0]
    counts = tree.query_ball_point(fluid, support, return_length=True)
    return float(np.mean(counts) - 1.0)


#: The material models of the shear-cell rows: name -> (model, modes ((lambda s, eta Pa s), ...)).
SHEAR_CELL_MODELS = {
    "newtonian": ("newtonian", ()),
    "ptt_1_mode": ("ptt", ((1.0, 10.0),)),
    "ptt_5_modes": ("ptt", ((0.01, 2.0), (0.1, 2.0), (1.0, 2.0), (3.0, 2.0), (10.0, 2.0))),
}


def shear_cell_case(steps: int, threads: int, model: str = "newtonian", cells: int = 100,
                    thread_wait: str = "passive") -> dict:
    """A 2D Lees-Edwards cell of cells x cells particles (1 m, dx = 0.01 m, h = 1.3 dx) in steady shear 1/s, of
    one fluid of zero-shear viscosity 10 Pa s: Newtonian (Morris, nu = 0.01 m^2/s) or PTT (SHEAR_CELL_MODELS,
    epsilon 0.1); rho0 1000 kg/m^3, c0 10 m/s, fixed dt = 1.3e-4 s (0.1 h / c0). The same particles and step for
    every model, so the rows compare the cost of the material model alone."""
    kind, modes = SHEAR_CELL_MODELS[model]
    size, dx = 1.0, 1.0 / cells
    material = {"name": "fluid", "model": kind, "density": 1000.0, "sound_speed": 10.0}
    if kind == "newtonian":
        material["viscosity"] = 0.01
    else:
        material.update(epsilon=0.1, modes=[{"relaxation_time": lam, "viscosity": eta} for lam, eta in modes])
    return {
        "case": {"kind": "sph_flow", "name": f"bench_shear_cell_{model}", "engine": "sph",
                 "description": f"2D Lees-Edwards cell, {cells} x {cells} particles, {model}"},
        "domain": {"dimension": 2, "lo": [0.0, 0.0], "hi": [size, size], "periodic": [0, 1]},
        "fluid": {"max_speed": 1.0},
        "materials": [material],
        "physics": {"terms": ["morris_viscosity"] if kind == "newtonian" else []},
        "blocks": [{"name": "cell", "kind": "fluid", "material": "fluid", "lo": [0.0, 0.0], "hi": [size, size]}],
        "lees_edwards": {"shear_rate": 1.0},
        "numerics": {"dx": dx, "h_over_dx": 1.3, "dt": 0.1 * 1.3 * dx / 10.0, "max_steps": steps,
                     "threads": threads, "thread_wait": thread_wait},
        "simulation": {"duration": 10.0},
        "output": {"frame_interval": 10.0},
    }
