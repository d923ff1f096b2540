"""The case dicts of `orchestrator bench sph` (workflows.bench_sph, which finds them through Kind.benches): PySPH's
2D dam break, a 3D dam break slab, a periodic 3D block and the Lees-Edwards shear cells of the material models, as
sph_flow cases. The 3D dam break and the block are the scenes our executable and LAMMPS SPH both run
(PEER_SCENES): each engine renders the same case through its adapter (kinds/sph_flow/sph.py, lammps.py), so both
get the same particles, h, fixed dt, c0 and viscosity."""

from __future__ import annotations

import math

GRAVITY = 9.81  # m/s^2

#: PySPH's dam_break_2d defaults (pysph 1.0b2): spacing, h/dx, column, tank, wall layers.
PYSPH_DX, PYSPH_HDX = 0.03, 1.3
COLUMN_CELLS_2D = (34, 67)  # PySPH's get_2d_block(dx, 1.0, 2.0) holds 34 x 67 particles
TANK_2D, WALL_LAYERS_2D = (4.02, 4.02), 4  # m (134 dx), layers


def dam_break_2d_case(steps: int, threads: int, dx: float = PYSPH_DX, thread_wait: str = "passive") -> dict:
    """PySPH's 2D dam break as an sph_flow case dict (SI units), stopped after `steps` steps."""
    cx, cy = COLUMN_CELLS_2D
    layers = WALL_LAYERS_2D * dx
    width, height = TANK_2D
    c0 = 10.0 * math.sqrt(2.0 * GRAVITY * 2.0)
    return {
        "case": {"kind": "sph_flow", "name": "bench_dam_break_2d", "engine": "sph",
                 "description": "PySPH's dam_break_2d: 34 x 67 fluid particles, dx = 0.03 m, h = 1.3 dx"},
        "domain": {"dimension": 2, "lo": [-layers, -layers], "hi": [width + layers, height]},
        "fluid": {"density": 1000.0, "max_speed": c0 / 10.0},
        "physics": {"terms": ["artificial_viscosity", "body_force"], "body_force": [0.0, -GRAVITY],
                    "artificial_viscosity": {"alpha": 0.1, "beta": 0.0}},
        "blocks": [
            {"name": "column", "kind": "fluid", "lo": [0.0, 0.0], "hi": [cx * dx, cy * dx],
             "hydrostatic_surface": cy * dx},
            {"name": "floor", "kind": "boundary", "lo": [-layers, -layers], "hi": [width + layers, 0.0]},
            {"name": "left", "kind": "boundary", "lo": [-layers, 0.0], "hi": [0.0, height]},
            {"name": "right", "kind": "boundary", "lo": [width, 0.0], "hi": [width + layers, height]},
        ],
        "numerics": {"dx": dx, "h_over_dx": PYSPH_HDX, "max_steps": steps, "threads": threads,
                     "thread_wait": thread_wait},
        "simulation": {"duration": 10.0},
        "output": {"frame_interval": 10.0},
    }


def dam_break_3d_case(steps: int, threads: int, dx: float = 0.02, thread_wait: str = "passive") -> dict:
    """A 3D dam break: a 0.4 x 0.4 x 0.8 m column in a 1.2 m tank, periodic across (y), three wall layers; h = 1.3 dx,
    artificial viscosity alpha = 0.1, a fixed step of 0.25 h / c0 (the adaptive rule's step at rest, which LAMMPS
    takes too)."""
    layers, depth, length, wall = 3 * dx, 0.4, 1.2, 0.9
    c0 = 10.0 * math.sqrt(2.0 * GRAVITY * 0.8)
    hdx = 1.3
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
        "numerics": {"dx": dx, "h_over_dx": hdx, "dt": 0.25 * hdx * dx / c0, "max_steps": steps,
                     "threads": threads, "thread_wait": thread_wait},
        "simulation": {"duration": 10.0},
        "output": {"frame_interval": 10.0},
    }


#: The periodic 3D block: cells, spacing m, h/dx, fixed step s, largest speed m/s, layers of the shear flow.
BLOCK_CELLS, BLOCK_DX, BLOCK_HDX, BLOCK_DT, BLOCK_SPEED, BLOCK_LAYERS = (40, 40, 16), 1e-3, 1.5, 2e-6, 1.0, 8
#: Steps of the block per step of the 3D dam break (500 to its 200 by default).
BLOCK_STEPS_PER_3D_STEP = 2.5


def block_steps(steps_3d: int) -> int:
    """Steps of the block for `steps_3d` steps of the 3D dam break."""
    return max(1, round(BLOCK_STEPS_PER_3D_STEP * steps_3d))


def block_3d_case(steps: int, threads: int, thread_wait: str = "passive") -> dict:
    """A periodic 3D block of 40 x 40 x 16 particles at dx = 1 mm (25 600), no walls: water (rho0 1000 kg/m^3,
    c0 = 10 m/s), h = 1.5 dx, artificial viscosity alpha = 0.1, fixed dt = 2 us. It starts as a stepped sine shear
    flow, u_x = 1 m/s sin(2 pi y / L_y) on 8 layers across y, so particles pass each other and both engines rebuild
    their neighbour lists as they would in a flow."""
    size = [n * BLOCK_DX for n in BLOCK_CELLS]
    rows = BLOCK_CELLS[1] // BLOCK_LAYERS
    layers = []
    for k in range(BLOCK_LAYERS):
        lo, hi = k * rows * BLOCK_DX, (k + 1) * rows * BLOCK_DX
        u = BLOCK_SPEED * math.sin(2.0 * math.pi * (k + 0.5) / BLOCK_LAYERS)
        layers.append({"name": f"layer_{k}", "kind": "fluid", "lo": [0.0, lo, 0.0], "hi": [size[0], hi, size[2]],
                       "velocity": [u, 0.0, 0.0]})
    return {
        "case": {"kind": "sph_flow", "name": "bench_block_3d", "engine": "sph",
                 "description": "periodic 3D block, 40 x 40 x 16 particles, dx = 1 mm, a stepped sine shear flow"},
        "domain": {"dimension": 3, "lo": [0.0, 0.0, 0.0], "hi": size, "periodic": [0, 1, 2]},
        "fluid": {"density": 1000.0, "max_speed": BLOCK_SPEED},
        "physics": {"terms": ["artificial_viscosity"], "artificial_viscosity": {"alpha": 0.1, "beta": 0.0}},
        "blocks": layers,
        "numerics": {"dx": BLOCK_DX, "h_over_dx": BLOCK_HDX, "dt": BLOCK_DT, "max_steps": steps, "threads": threads,
                     "thread_wait": thread_wait},
        "simulation": {"duration": 10.0},
        "output": {"frame_interval": 10.0},
    }


#: The scenes both our executable and LAMMPS run: name -> (case builder, its steps for --steps-3d steps).
PEER_SCENES = {
    "block_3d": (block_3d_case, block_steps),
    "dam_break_3d": (dam_break_3d_case, lambda steps_3d: steps_3d),
}


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
