"""The reference SPH solver's kernel, equation of state and neighbour search (numpy, SI units): the Wendland C2
kernel and its gradient factor, Tait's equation, the sound speed, periodic wrapping and the pairs within 2h.
`model` is a reference.sph SphModel (or, for the equation of state, a SphMaterial): anything with the fields used."""

from __future__ import annotations

import itertools
import math

import numpy as np


def kernel_value(r, h: float, dimension: int):
    """Wendland C2 W(r) = alpha_D (1 - q/2)^4 (2q + 1), q = r/h < 2, 1/m^D (eq. 8)."""
    alpha_d = 7.0 / (4.0 * math.pi * h * h) if dimension == 2 else 21.0 / (16.0 * math.pi * h**3)
    q = np.asarray(r, dtype=float) / h
    t = 1.0 - 0.5 * q
    return np.where(q >= 2.0, 0.0, alpha_d * t**4 * (2.0 * q + 1.0))


def kernel_gradient_factor(r, h: float, dimension: int):
    """F(r) with grad_a W_ab = F(r) r_ab: -5 alpha_D (1 - q/2)^3 / h^2, 1/m^(D+2)."""
    alpha_d = 7.0 / (4.0 * math.pi * h * h) if dimension == 2 else 21.0 / (16.0 * math.pi * h**3)
    q = np.asarray(r, dtype=float) / h
    t = 1.0 - 0.5 * q
    return np.where(q >= 2.0, 0.0, -5.0 * alpha_d / (h * h) * t**3)


def tait_pressure(rho, model):
    """Eq. 6: rho0 c0^2/gamma ((rho/rho0)^gamma - 1) + p_B, Pa (the model's or material's parameters; each may
    be an array, one value per particle)."""
    ratio = np.asarray(rho, dtype=float) / model.rho0
    return model.rho0 * model.c0**2 / model.gamma * (ratio**model.gamma - 1.0) + model.background_pressure


def sound_speed(rho, model):
    """c = c0 (rho/rho0)^((gamma-1)/2), m/s."""
    return model.c0 * (np.asarray(rho, dtype=float) / model.rho0) ** (0.5 * (model.gamma - 1.0))


def wrap(x: np.ndarray, model) -> np.ndarray:
    """Positions mapped into [lo, hi) along the periodic axes (a copy), m."""
    x = np.array(x, dtype=float)
    for axis, lo, hi in zip(model.periodic_axes, model.periodic_lo, model.periodic_hi):
        length = hi - lo
        column = x[:, axis]
        outside = (column >= hi) | (column < lo)
        column[outside] -= length * np.floor((column[outside] - lo) / length)
        column[column >= hi] = lo
    return x


def neighbour_pairs(x: np.ndarray, model, targets: np.ndarray | None = None):
    """Pairs (a, b, r_ab) with 0 < |r_ab| < 2h over every periodic image of b: r_ab = x_a - (x_b + shift), m.

    targets: the points a (default x itself).
    """
    from scipy.spatial import cKDTree

    xa = x if targets is None else targets
    support = 2.0 * model.h
    shifts = [np.zeros(model.dimension)]
    if model.periodic_axes:
        shifts = []
        lengths = [hi - lo for lo, hi in zip(model.periodic_lo, model.periodic_hi)]
        for combo in itertools.product((-1, 0, 1), repeat=len(model.periodic_axes)):
            shift = np.zeros(model.dimension)
            for axis, k, length in zip(model.periodic_axes, combo, lengths):
                shift[axis] = k * length
            shifts.append(shift)
    tree_a = cKDTree(xa)
    a_parts, b_parts, r_parts = [], [], []
    for shift in shifts:
        image = x + shift
        matrix = tree_a.sparse_distance_matrix(cKDTree(image), support * (1 + 1e-12), output_type="ndarray")
        a, b = matrix["i"].astype(np.int64), matrix["j"].astype(np.int64)
        r_ab = xa[a] - image[b]
        r2 = np.einsum("ij,ij->i", r_ab, r_ab)
        keep = (r2 < support * support) & (r2 != 0.0)
        a_parts.append(a[keep]), b_parts.append(b[keep]), r_parts.append(r_ab[keep])
    order_a, order_b = np.concatenate(a_parts), np.concatenate(b_parts)
    r_ab = np.concatenate(r_parts)
    order = np.lexsort((order_b, order_a))
    return order_a[order], order_b[order], r_ab[order]
