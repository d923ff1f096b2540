"""Closed-form and series solutions of the SPH verification flows. SI units.

- Start-up Poiseuille flow between plates y = 0 and y = L at rest, driven
  from rest at t = 0 by a body force F along x (Morris, Fox & Zhu 1997,
  J. Comput. Phys. 136:214-226, eq. 21, written here with a positive flow):
      u(y, t) = F y (L - y) / (2 nu)
                - sum_{n odd} 4 F L^2 / (nu pi^3 n^3) sin(n pi y / L) exp(-n^2 pi^2 nu t / L^2).
  The series at t = 0 is the sine series of the parabola, so u(y, 0) = 0.
- Start-up Couette flow: plates at rest, the top one (y = L) set moving at
  v0 at t = 0 (same paper, eq. 22):
      u(y, t) = v0 y / L + sum_{n >= 1} 2 v0 (-1)^n / (n pi) sin(n pi y / L) exp(-n^2 pi^2 nu t / L^2).
- Hydrostatic pressure in a column of depth H under gravity g: rho g (H - y).

MORRIS1997 holds the paper's parameters (L = 1e-3 m, nu = 1e-6 m^2/s,
F = 2e-4 m/s^2, v0 = 2.5e-5 m/s); both flows then peak at 2.5e-5 m/s and
relax on the diffusion time L^2 / nu = 1 s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Terms of the series by default; the Poiseuille terms fall as n^-3 (error < 1e-7 of the peak at t = 0),
#: the Couette ones as 1/n, which matters only for t << L^2/(nu pi^2 n^2).
DEFAULT_TERMS = 400


@dataclass(frozen=True)
class MorrisChannel:
    """The plates of Morris, Fox & Zhu (1997), section 5.1.

    gap: L, m; viscosity: kinematic nu, m^2/s; body_force: F, m/s^2
    (Poiseuille); plate_speed: v0 of the moving top plate, m/s (Couette).
    """

    gap: float = 1e-3
    viscosity: float = 1e-6
    body_force: float = 2e-4
    plate_speed: float = 2.5e-5

    @property
    def diffusion_time(self) -> float:
        """L^2 / nu, s: the slowest mode decays as exp(-pi^2 t / (L^2/nu))."""
        return self.gap**2 / self.viscosity

    @property
    def poiseuille_peak(self) -> float:
        """Steady centre-line speed F L^2 / (8 nu), m/s."""
        return poiseuille_steady_velocity(0.5 * self.gap, self.gap, self.viscosity, self.body_force)


MORRIS1997 = MorrisChannel()


def _modes(n_terms: int, odd_only: bool) -> np.ndarray:
    return np.arange(1, 2 * n_terms, 2, dtype=float) if odd_only else np.arange(1, n_terms + 1, dtype=float)


def poiseuille_steady_velocity(y, gap, viscosity, body_force):
    """Steady plane Poiseuille profile F y (L - y) / (2 nu), m/s.

    y: height above the lower plate, m (0 <= y <= L); gap: L, m;
    viscosity: nu, m^2/s; body_force: F, m/s^2.
    """
    y = np.asarray(y, dtype=float)
    return body_force * y * (gap - y) / (2.0 * viscosity)


def poiseuille_velocity(y, t, gap, viscosity, body_force, n_terms: int = DEFAULT_TERMS):
    """Start-up Poiseuille flow u(y, t), m/s (Morris et al. 1997, eq. 21).

    y: height above the lower plate, m (array); t: time since the force was
    switched on, s (>= 0, scalar); gap: L, m; viscosity: nu, m^2/s;
    body_force: F, m/s^2; n_terms: odd modes summed.
    """
    y = np.asarray(y, dtype=float)
    n = _modes(n_terms, odd_only=True)
    amplitude = 4.0 * body_force * gap**2 / (viscosity * math.pi**3 * n**3)
    decay = np.exp(-(n**2) * math.pi**2 * viscosity * t / gap**2)
    modes = np.sin(np.multiply.outer(y, n) * math.pi / gap)
    return poiseuille_steady_velocity(y, gap, viscosity, body_force) - modes @ (amplitude * decay)


def couette_steady_velocity(y, gap, plate_speed):
    """Steady Couette profile v0 y / L, m/s (lower plate at rest, upper at v0)."""
    return plate_speed * np.asarray(y, dtype=float) / gap


def couette_velocity(y, t, gap, viscosity, plate_speed, n_terms: int = DEFAULT_TERMS):
    """Start-up Couette flow u(y, t), m/s (Morris et al. 1997, eq. 22).

    y: height above the lower plate, m (array); t: time since the upper plate
    was set moving at plate_speed v0 (m/s), s (>= 0, scalar); gap: L, m;
    viscosity: nu, m^2/s; n_terms: modes summed.
    """
    y = np.asarray(y, dtype=float)
    n = _modes(n_terms, odd_only=False)
    amplitude = 2.0 * plate_speed * (-1.0) ** n / (n * math.pi)
    decay = np.exp(-(n**2) * math.pi**2 * viscosity * t / gap**2)
    modes = np.sin(np.multiply.outer(y, n) * math.pi / gap)
    return couette_steady_velocity(y, gap, plate_speed) + modes @ (amplitude * decay)


def hydrostatic_pressure(y, depth, density, gravity: float = 9.81):
    """rho g (H - y), Pa, at height y (m) in a column of free-surface height H (m).

    density: rho, kg/m^3; gravity: g, m/s^2 (positive). Zero above the surface.
    """
    y = np.asarray(y, dtype=float)
    return density * gravity * np.clip(depth - y, 0.0, None)



def layer_under_water_stress(y, layer_top, water_depth, layer_density, water_density, gravity: float = 9.81):
    """Vertical stress sigma_yy (Pa, compression negative) at height y (m) in a layer resting on a floor at y = 0, of
    top layer_top (m) under water water_depth (m) deep, at rest: minus the weight above per unit area,
    -(rho_w g H_w + rho_s g (H_s - y)).

    layer_density: rho_s, water_density: rho_w, kg/m^3; gravity: g, m/s^2 (positive).
    """
    y = np.asarray(y, dtype=float)
    return -(water_density * gravity * water_depth + layer_density * gravity * np.clip(layer_top - y, 0.0, None))

def tait_density(pressure, rest_density, sound_speed, gamma: float = 7.0, background_pressure: float = 0.0):
    """Density from the Tait equation of state (Canini et al. eq. 6) inverted, kg/m^3.

    pressure: Pa; rest_density: rho0, kg/m^3; sound_speed: c0, m/s;
    background_pressure: p_B, Pa. rho = rho0 (1 + gamma (p - p_B) / (rho0 c0^2))^(1/gamma).
    """
    stiffness = rest_density * sound_speed**2 / gamma
    return rest_density * (1.0 + (np.asarray(pressure, dtype=float) - background_pressure) / stiffness) ** (1.0 / gamma)


# ------------------------------------------------------------------------------------------ two-layer flows
def two_layer_poiseuille_velocity(y, lower_height, gap, lower_density, upper_density, lower_viscosity,
                                  upper_viscosity, body_force):
    """Steady two-layer Poiseuille profile u(y), m/s: two immiscible Newtonian layers between plates at rest,
    the lower (density rho1, dynamic viscosity mu1) on 0 < y < h1, the upper (rho2, mu2) on h1 < y < L,
    driven along x by the body force per unit mass F (the force density rho_i F differs between the layers).

    y: height above the lower plate, m; lower_height: h1, m; gap: L, m; densities: kg/m^3; viscosities:
    dynamic mu, Pa s; body_force: F, m/s^2.

    Derivation. Steady, fully developed: d tau/dy = -rho_i F with the shear stress tau = mu_i du/dy, so
        u1(y) = -rho1 F y^2 / (2 mu1) + A1 y                      (u1(0) = 0),
        u2(y) = -rho2 F s^2 / (2 mu2) + A2 s,  s = L - y           (u2(L) = 0).
    The stress is continuous at y = h1 (h2 = L - h1): tau1 = -rho1 F h1 + mu1 A1, tau2 = rho2 F h2 - mu2 A2, so
        mu1 A1 + mu2 A2 = F (rho1 h1 + rho2 h2) = S;
    and so is the velocity: -rho1 F h1^2/(2 mu1) + A1 h1 = -rho2 F h2^2/(2 mu2) + A2 h2, so
        h1 A1 - h2 A2 = F (rho1 h1^2 / (2 mu1) - rho2 h2^2 / (2 mu2)) = D.
    Hence A1 = (S h2 + mu2 D) / (mu1 h2 + mu2 h1), A2 = (S h1 - mu1 D) / (mu1 h2 + mu2 h1). With rho1 = rho2,
    mu1 = mu2 it is the one-layer F y (L - y) / (2 nu).
    """
    y = np.asarray(y, dtype=float)
    h1, h2, f = lower_height, gap - lower_height, body_force
    r1, r2, m1, m2 = lower_density, upper_density, lower_viscosity, upper_viscosity
    s_total = f * (r1 * h1 + r2 * h2)
    d_jump = f * (r1 * h1**2 / (2.0 * m1) - r2 * h2**2 / (2.0 * m2))
    a1 = (s_total * h2 + m2 * d_jump) / (m1 * h2 + m2 * h1)
    a2 = (s_total * h1 - m1 * d_jump) / (m1 * h2 + m2 * h1)
    s = gap - y
    return np.where(y <= h1, -r1 * f * y**2 / (2.0 * m1) + a1 * y, -r2 * f * s**2 / (2.0 * m2) + a2 * s)


def two_layer_couette_velocity(y, lower_height, gap, lower_viscosity, upper_viscosity, plate_speed):
    """Steady two-layer Couette profile u(y), m/s: the lower layer (dynamic viscosity mu1) on 0 < y < h1 over a
    plate at rest, the upper (mu2) on h1 < y < L under a plate moving at v0.

    y: height above the lower plate, m; lower_height: h1, m; gap: L, m; viscosities: Pa s; plate_speed: v0, m/s.

    Derivation. Without a body force the shear stress tau is one constant across the gap, so each layer is
    linear with du/dy = tau / mu_i; u(0) = 0, u(L) = v0 and continuity at h1 (h2 = L - h1) give
    tau (h1/mu1 + h2/mu2) = v0 and the interface speed u_i = v0 (h1/mu1) / (h1/mu1 + h2/mu2):
        u(y) = u_i y / h1 (y < h1),  u(y) = u_i + (v0 - u_i) (y - h1) / h2 (y > h1).
    With mu1 = mu2 it is the one-layer v0 y / L.
    """
    y = np.asarray(y, dtype=float)
    h1, h2 = lower_height, gap - lower_height
    u_i = plate_speed * (h1 / lower_viscosity) / (h1 / lower_viscosity + h2 / upper_viscosity)
    return np.where(y <= h1, u_i * y / h1, u_i + (plate_speed - u_i) * (y - h1) / h2)
