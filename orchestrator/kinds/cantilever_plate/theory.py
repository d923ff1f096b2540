"""Thin-plate theory of the clamped plate's first bending mode (Gray, Monaghan & Swift 2001, after Landau and
Lifshitz's theory of elasticity): the mode shape, its wave number and frequency. SI units (m, s, Pa, kg/m^3).

    f(x)    = [M (cos kx - cosh kx) - N (sin kx - sinh kx)] / Q,  f(0) = f'(0) = 0, f''(L) = f'''(L) = 0, f(L) = 1
              M = sin kL + sinh kL, N = cos kL + cosh kL, Q = 2 (cos kL sinh kL - sin kL cosh kL)
    cos kL cosh kL = -1  (the first root kL = 1.8751)
    omega^2 = E H^2 k^4 / (12 rho0 (1 - nu^2))    (plane strain: the plate modulus E / (1 - nu^2))
"""

from __future__ import annotations

import math

import numpy as np


def first_root() -> float:
    """The first root of cos(z) cosh(z) = -1, z = kL of the first cantilever mode (1.8751040687), -."""
    z = 1.875
    for _ in range(50):  # Newton on g(z) = cos z cosh z + 1
        g = math.cos(z) * math.cosh(z) + 1.0
        dg = math.cos(z) * math.sinh(z) - math.sin(z) * math.cosh(z)
        step = g / dg
        z -= step
        if abs(step) < 1e-15:
            break
    return z


def mode_shape(x, length: float) -> np.ndarray:
    """The first mode shape f(x) on 0 <= x <= length (m), scaled to f(length) = 1; x < 0 gives 0, -."""
    kl = first_root()
    k = kl / length
    x = np.clip(np.asarray(x, dtype=float), 0.0, None)
    m = math.sin(kl) + math.sinh(kl)
    n = math.cos(kl) + math.cosh(kl)
    q = 2.0 * (math.cos(kl) * math.sinh(kl) - math.sin(kl) * math.cosh(kl))
    return (m * (np.cos(k * x) - np.cosh(k * x)) - n * (np.sin(k * x) - np.sinh(k * x))) / q


def young_and_poisson(bulk: float, shear: float) -> tuple[float, float]:
    """(E Pa, nu -) from the bulk modulus K and shear modulus G (Pa)."""
    return 9.0 * bulk * shear / (3.0 * bulk + shear), (3.0 * bulk - 2.0 * shear) / (2.0 * (3.0 * bulk + shear))


def angular_frequency(length: float, thickness: float, density: float, bulk: float, shear: float) -> float:
    """omega of the first bending mode by thin-plate theory, rad/s (length, thickness m; density kg/m^3; moduli Pa)."""
    young, poisson = young_and_poisson(bulk, shear)
    k = first_root() / length
    return math.sqrt(young * thickness**2 * k**4 / (12.0 * density * (1.0 - poisson**2)))


def plate_theory(case) -> dict[str, float]:
    """A case's closed forms: omega rad/s, period s, c0 = sqrt(K / rho0) m/s, the tip's initial speed V c0 m/s and
    its amplitude V c0 / omega m (the mode swinging at theory's frequency), E Pa and nu -."""
    m, plate = case.material, case.plate
    bulk, shear = m.solid.bulk(m.density), m.solid.shear_modulus
    omega = angular_frequency(plate.length, plate.thickness, m.density, bulk, shear)
    c0 = math.sqrt(bulk / m.density)
    young, poisson = young_and_poisson(bulk, shear)
    tip_speed = plate.speed_factor * c0
    return {"omega": omega, "period": 2.0 * math.pi / omega, "c0": c0, "tip_speed": tip_speed,
            "amplitude": tip_speed / omega, "young": young, "poisson": poisson}
