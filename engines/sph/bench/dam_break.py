"""Write a dam-break scene (particles.h5 + deck.json) for timing the sph executable.

usage: python dam_break.py OUTDIR [--dim 2] [--dx 0.005] [--t-end 0.1] [--threads 2]
Needs numpy and h5py. A water column 0.6 m long and 0.3 m high at the left of
a 1.6 m tank (in 3D a slab `--depth` wide, periodic across the flow), three
layers of fixed boundary particles, gravity, artificial viscosity.
"""
import argparse
import itertools
import json
from pathlib import Path

import h5py
import numpy as np


def lattice(counts, start, dx):
    axes = [(np.arange(s, s + n) + 0.5) * dx for s, n in zip(start, counts)]
    return np.array(list(itertools.product(*axes)))


def scene(dim: int, dx: float, depth: float):
    """Positions, densities (hydrostatic), kinds, particle mass and c0 of the scene."""
    rho0, g = 1000.0, 9.81
    length, height, tank, tank_height = 0.6, 0.3, 1.6, 0.5
    c0 = 10.0 * np.sqrt(2.0 * g * height) * 1.05
    B = rho0 * c0**2 / 7.0
    up = dim - 1  # vertical axis; in 3D axis 1 is periodic (no side walls)
    fluid_extent = [length, height] if dim == 2 else [length, depth, height]
    fluid = lattice([round(e / dx) for e in fluid_extent], [0] * dim, dx)
    nx, nz = round(tank / dx), round(tank_height / dx)
    counts = [nx + 6, nz + 3] if dim == 2 else [nx + 6, round(depth / dx), nz + 3]
    start = [-3, -3] if dim == 2 else [-3, 0, -3]
    outer = lattice(counts, start, dx)
    wall = outer[(outer[:, 0] < 0) | (outer[:, 0] > tank) | (outer[:, up] < 0)]
    pos = np.vstack([fluid, wall])
    rho = rho0 * (1.0 + rho0 * g * np.clip(height - pos[:, up], 0.0, None) / B) ** (1.0 / 7.0)
    kind = np.concatenate([np.zeros(len(fluid), np.int8), np.ones(len(wall), np.int8)])
    return pos, rho, kind, rho0 * dx**dim, c0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("outdir", type=Path)
    ap.add_argument("--dim", type=int, default=2, choices=(2, 3))
    ap.add_argument("--dx", type=float, default=0.005)
    ap.add_argument("--depth", type=float, default=0.1, help="tank width across the flow in 3D, m")
    ap.add_argument("--t-end", type=float, default=0.1)
    ap.add_argument("--threads", type=int, default=2)
    a = ap.parse_args()
    a.outdir.mkdir(parents=True, exist_ok=True)
    pos, rho, kind, mass, c0 = scene(a.dim, a.dx, a.depth)
    with h5py.File(a.outdir / "particles.h5", "w") as f:
        f["positions"] = pos
        f["velocities"] = np.zeros_like(pos)
        f["masses"] = np.full(len(pos), mass)
        f["densities"] = rho
        f["kind"] = kind
    gravity = [0.0] * a.dim
    gravity[-1] = -9.81
    probe = [1.6 - 2 * a.dx] + ([a.depth / 2] if a.dim == 3 else []) + [2 * a.dx]
    deck = {
        "dimension": a.dim, "particles_file": "particles.h5",
        "physics": ["artificial_viscosity", "body_force"],
        "rho0": 1000.0, "c0": c0, "v_max": c0 / 10.0, "alpha": 0.05,
        "h": 1.3 * a.dx, "dx": a.dx, "body_force": gravity,
        "t_end": a.t_end, "threads": a.threads,
        **({"periodic": {"axes": [1], "lo": [0.0], "hi": [a.depth]}} if a.dim == 3 else {}),
        "output": {"file": "out.h5", "frame_interval": a.t_end / 2, "series_interval": a.t_end / 20,
                   "probes": [{"name": "toe", "point": probe}]},
    }
    (a.outdir / "deck.json").write_text(json.dumps(deck, indent=2))
    print(f"{len(pos)} particles ({int((kind == 0).sum())} fluid) in {a.outdir}")


if __name__ == "__main__":
    main()
