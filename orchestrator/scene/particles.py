"""The particle cloud: radii from the case's size distribution and
non-overlapping random positions, both drawn from one seeded generator so
that the same case gives the same cloud on every engine."""

from __future__ import annotations

import math

import numpy as np


def draw_radii(rng: np.random.Generator, count: int, mean: float, spread: float, distribution: str) -> np.ndarray:
    """Ball radii, m: normal (std = spread, truncated at +-2 spread) or uniform (mean +- spread)."""
    if spread == 0.0:
        return np.full(count, mean)
    if distribution == "uniform":
        return rng.uniform(mean - spread, mean + spread, count)
    radii = rng.normal(mean, spread, count)
    outside = np.abs(radii - mean) > 2.0 * spread
    while outside.any():
        radii[outside] = rng.normal(mean, spread, outside.sum())
        outside = np.abs(radii - mean) > 2.0 * spread
    return radii


def random_cloud_in_cylinder(
    rng: np.random.Generator,
    radii: np.ndarray,
    cylinder_radius: float,
    z_bottom: float,
    volume_fraction: float = 0.3,
    candidates: int = 8,
    max_rounds: int = 200,
) -> np.ndarray:
    """Centres (n,3), m, of non-touching balls placed by random sequential addition
    in a vertical cylinder (axis z through the origin) starting at z_bottom.

    The region is made tall enough for the given loose volume fraction, so the
    balls fall a short way and settle into a random (not lattice) bed. Larger
    balls are placed first; each ball takes the first of a batch of random
    candidates that touches no placed ball, and the region grows 10 % taller
    whenever a batch finds no room.
    """
    count = len(radii)
    r_max = float(radii.max())
    inner = cylinder_radius - r_max
    if inner <= 0:
        raise ValueError("the container is narrower than one ball")
    solid = float(np.sum(4.0 / 3.0 * np.pi * radii**3))
    height = max(solid / (volume_fraction * math.pi * cylinder_radius**2), 2.0 * r_max)
    centres = np.empty((count, 3))
    placed_r = np.empty(count)
    order = np.argsort(-radii, kind="stable")
    for n_placed, index in enumerate(order):
        r = radii[index]
        for _ in range(max_rounds):
            rho = inner * np.sqrt(rng.random(candidates))
            phi = 2.0 * np.pi * rng.random(candidates)
            z = z_bottom + r_max + (height - 2.0 * r_max) * rng.random(candidates)
            cand = np.column_stack([rho * np.cos(phi), rho * np.sin(phi), z])
            if n_placed:
                gap = np.linalg.norm(cand[:, None, :] - centres[None, :n_placed], axis=2) - placed_r[None, :n_placed] - r
                free = np.flatnonzero(gap.min(axis=1) > 0.0)
            else:
                free = np.array([0])
            if free.size:
                centres[n_placed] = cand[free[0]]
                placed_r[n_placed] = r
                break
            height *= 1.1
        else:
            raise ValueError(f"could not place ball {n_placed + 1} of {count}; the container is too small")
    out = np.empty((count, 3))
    out[order] = centres
    return out
