"""A sphere settling through a viscous fluid at low Reynolds number: Stokes' drag and its correction for a simple
cubic array of spheres (a sphere in a periodic box), Hasimoto (1959). SI units.

- Stokes' drag on a sphere of radius a moving at U through a fluid of viscosity mu: F = 6 pi mu a U.
- In a periodic cubic box of side L (a simple cubic array), with the solid volume fraction
  c = (4/3) pi a^3 / L^3 and the array's weight carried by the mean pressure gradient, Hasimoto's (1959) drag is
      F = 6 pi mu a U K,   K = 1 / (1 - 1.7601 c^(1/3) + c - 1.5593 c^2 + O(c^(8/3)))
  with U the superficial slip velocity, the volume flux through the array per unit area in the spheres' frame:
  (1 - c) times the sphere's velocity relative to the fluid's mean velocity (the velocity of Darcy's law, which
  Zick & Homsy 1982 use for the permeability). Against the exact values of Zick & Homsy
  (1982) for the simple cubic array the truncated series is within 0.1 % at c = 0.027 (K = 2.008) and 0.7 % at
  c = 0.064 (2.810), and 5.6 % high at c = 0.125: use it for c <= 0.07.
- Terminal speed of a sphere of density rho_s in a fluid of density rho_f under g: Hasimoto's F is the force the
  fluid exerts on the sphere when the fluid carries no body force (its weight moved into the pressure), so in
  sedimentation it is the weight less Archimedes' buoyancy at the fluid's density, F = (rho_s - rho_f) V g, not
  the net force (rho_s - rho_m) V g = (1 - c) (rho_s - rho_f) V g left over after the buoyancy of the mixture's mean
  pressure gradient (that gradient's own buoyancy is part of Hasimoto's F: n F = -grad P). Hence
  U = (rho_s - rho_f) g (4/3 pi a^3) / (6 pi mu a K), the hindered settling U / U_Stokes = 1 / K of a simple cubic
  array in the frame of zero volume flux, where the sphere's speed is the superficial slip velocity.
"""

from __future__ import annotations

import math

#: Coefficients of Hasimoto's (1959) series for the simple cubic array: 1 - 1.7601 c^(1/3) + c - 1.5593 c^2.
HASIMOTO_SIMPLE_CUBIC = (1.7601, 1.0, 1.5593)


def stokes_drag(mu: float, radius: float, speed: float) -> float:
    """Stokes' drag 6 pi mu a U, N (mu Pa s, radius m, speed m/s)."""
    return 6.0 * math.pi * mu * radius * speed


def solid_fraction(radius: float, box: float) -> float:
    """c = (4/3) pi a^3 / L^3 of a sphere of radius a (m) in a cubic box of side L (m)."""
    return 4.0 / 3.0 * math.pi * radius**3 / box**3


def hasimoto_factor(c: float) -> float:
    """Hasimoto's (1959) drag factor K(c) of the simple cubic array, 1 / (1 - 1.7601 c^(1/3) + c - 1.5593 c^2).
    ValueError outside 0 <= c <= 0.2 (the truncated series' range)."""
    if not 0.0 <= c <= 0.2:
        raise ValueError(f"solid fraction c = {c} is outside the series' range 0..0.2")
    a1, a3, a6 = HASIMOTO_SIMPLE_CUBIC
    return 1.0 / (1.0 - a1 * c ** (1.0 / 3.0) + a3 * c - a6 * c * c)


def periodic_terminal_speed(rho_s: float, rho_f: float, mu: float, g: float, radius: float, box: float) -> float:
    """Terminal superficial slip velocity (m/s: (1 - c) times the speed relative to the fluid's mean) of a sphere
    (density rho_s kg/m^3, radius m) in a cubic periodic box (side m) of a fluid (rho_f kg/m^3, mu Pa s) under
    gravity g (m/s^2), the mixture's weight balanced by the mean pressure gradient: Stokes with Hasimoto's factor,
    the drag (rho_s - rho_f) V g (the module's docstring says why not (1 - c) of it)."""
    c = solid_fraction(radius, box)
    weight = (rho_s - rho_f) * g * 4.0 / 3.0 * math.pi * radius**3
    return weight / (6.0 * math.pi * mu * radius * hasimoto_factor(c))
