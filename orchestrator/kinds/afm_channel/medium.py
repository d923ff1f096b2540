"""The channel medium's steady flow (kind "afm_channel"): the developed flow of a Newtonian or multi-mode linear PTT
medium between two plane walls under a pressure gradient, and the periodic cell's flow through its wide part and
the narrower passage over the workpiece at one flow rate. SI units (m, s, Pa).

A developed plane channel flow u(z) of gap H under the driving gradient G (Pa/m: rho f of the body force less the
pressure's own gradient) has the shear stress tau(z) = G (H/2 - z), and at each height the steady simple shear of
the medium at the rate gamma_dot(z) = du/dz that carries it: tau = eta_s gamma_dot + sum_i eta_i gamma_dot / f_i
(reference.viscoelastic_flows.ptt_multimode_steady_shear; f_i from its cubic), which rises with gamma_dot for
epsilon >= 0 and is inverted by interpolation on a log-spaced table. Each mode then holds tau_i,xz = eta_i gamma_dot / f_i and tau_i,xx =
2 eta_i lambda_i gamma_dot^2 / f_i^2 (the first normal stress difference along the flow), the other components 0.

In the periodic cell the workpiece narrows the passage to H - height over its length and its support; the medium
runs through both parts at one flow rate Q (per unit width), and the two parts' driving gradients G_w, G_n make
up the body force's over the cell: L_w G_w + L_n G_n = rho f L (the pressure returns to itself around the cell).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from orchestrator.reference.maxwell import Mode
from orchestrator.reference.viscoelastic_flows import ptt_multimode_steady_shear, ptt_steady_shear

#: Heights across the gap of the profile's quadrature (trapezoid rule), -.
_POINTS = 1001
#: Rates of the table that inverts the shear law (log-spaced over 12 decades and more), -.
_TABLE = 20001


@dataclass(frozen=True)
class MediumLaw:
    """The medium's steady shear law: solvent (or Newtonian) viscosity eta_s Pa s, PTT modes and epsilon -."""

    solvent: float
    modes: tuple[Mode, ...] = ()
    epsilon: float = 0.0

    def shear_stress(self, rate) -> np.ndarray:
        """tau (Pa) of steady simple shear at gamma_dot (1/s, any shape, odd in gamma_dot)."""
        rate = np.asarray(rate, dtype=float)
        tau = self.solvent * rate
        if self.modes:
            tau = tau + np.sign(rate) * ptt_multimode_steady_shear(np.abs(rate), self.modes, self.epsilon).shear_stress
        return tau

    def rate(self, stress) -> np.ndarray:
        """gamma_dot (1/s) of steady simple shear carrying the shear stress tau (Pa, any shape): the inverse of
        shear_stress, interpolated in log-log on _TABLE rates from 1e-12 of the zero-shear viscosity's rate to the
        solvent's rate for the largest |tau| (a relative error below 1e-6; tau rises with gamma_dot)."""
        stress = np.asarray(stress, dtype=float)
        size = np.abs(stress)
        if not self.modes:
            return stress / self.solvent
        top = max(float(size.max(initial=0.0)), 1e-300)
        zero_shear = self.solvent + sum(m.viscosity for m in self.modes)
        high = top / self.solvent if self.solvent > 0 else top / zero_shear * 1e12
        rates = np.geomspace(top / zero_shear * 1e-12, high, _TABLE)
        table = self.shear_stress(rates)
        found = np.exp(np.interp(np.log(np.maximum(size, 1e-300)), np.log(table), np.log(rates)))
        return np.where(size > 0.0, np.sign(stress) * found, 0.0)

    def mode_stresses(self, rate) -> np.ndarray:
        """Each mode's steady (tau_xz, tau_xx) at gamma_dot (1/s, shape (n,)), Pa: shape (n, modes, 2)."""
        rate = np.asarray(rate, dtype=float)
        out = np.zeros((len(rate), len(self.modes), 2))
        for k, mode in enumerate(self.modes):
            shear = ptt_steady_shear(np.abs(rate), mode.relaxation_time, mode.viscosity, self.epsilon)
            out[:, k, 0] = np.sign(rate) * shear.shear_stress
            out[:, k, 1] = shear.first_normal_stress_difference
        return out


def developed_rate(law: MediumLaw, z, gap: float, gradient: float) -> np.ndarray:
    """gamma_dot = du/dz (1/s) at heights z (m above the lower wall) of the developed flow of gap H (m) under the
    driving gradient G (Pa/m)."""
    return law.rate(gradient * (0.5 * gap - np.asarray(z, dtype=float)))


def developed_velocity(law: MediumLaw, z, gap: float, gradient: float) -> np.ndarray:
    """u(z) (m/s) of the developed flow (developed_rate integrated from the lower wall, u = 0 there, by the
    trapezoid rule on _POINTS heights); z clipped to the gap."""
    grid = np.linspace(0.0, gap, _POINTS)
    rate = developed_rate(law, grid, gap, gradient)
    u = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(grid))])
    return np.interp(np.clip(np.asarray(z, dtype=float), 0.0, gap), grid, u)


def developed_state(law: MediumLaw, z, gap: float, gradient: float, dimension: int) -> tuple[np.ndarray, np.ndarray]:
    """The developed flow at heights z (m above the lower wall, shape (n,)) with the flow along the first axis and
    the gradient along the last: the speed u (m/s, (n,)) and each mode's stress tensor (Pa, (n, modes, D, D): tau_xz
    = tau_zx the shear, tau_xx the first normal stress difference, the rest 0)."""
    z = np.asarray(z, dtype=float)
    rate = developed_rate(law, np.clip(z, 0.0, gap), gap, gradient)
    stresses = np.zeros((len(z), len(law.modes), dimension, dimension))
    if law.modes:
        modes = law.mode_stresses(rate)
        stresses[:, :, 0, -1] = stresses[:, :, -1, 0] = modes[:, :, 0]
        stresses[:, :, 0, 0] = modes[:, :, 1]
    return developed_velocity(law, z, gap, gradient), stresses


def flow_rate(law: MediumLaw, gap: float, gradient: float) -> float:
    """Q = integral of u over the gap (m^2/s, per unit width) of the developed flow."""
    grid = np.linspace(0.0, gap, _POINTS)
    u = developed_velocity(law, grid, gap, gradient)
    return float(np.sum(0.5 * (u[1:] + u[:-1]) * np.diff(grid)))


@dataclass(frozen=True)
class CellFlow:
    """The cell's steady flow: the wide part's gap (m) and driving gradient (Pa/m), the passage's over the
    workpiece, and their flow rate (m^2/s)."""

    wide_gap: float
    wide_gradient: float
    narrow_gap: float
    narrow_gradient: float
    flow_rate: float


@lru_cache(maxsize=64)
def cell_flow(law: MediumLaw, drive: float, gaps: tuple[float, float], lengths: tuple[float, float]) -> CellFlow:
    """The flow through the wide part and the passage (gaps m, lengths m along x) at one flow rate, their gradients
    making up the drive rho f (Pa/m) over the cell: bisection on the wide part's gradient (cached: a case asks for
    it several times)."""
    (wide, narrow), (l_wide, l_narrow) = gaps, lengths
    total = l_wide + l_narrow

    def narrow_of(g_wide: float) -> float:
        return (drive * total - l_wide * g_wide) / l_narrow

    lo, hi = 0.0, drive * total / l_wide  # all of the drive on one part or the other
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        if flow_rate(law, wide, mid) < flow_rate(law, narrow, narrow_of(mid)):
            lo = mid
        else:
            hi = mid
    g = 0.5 * (lo + hi)
    return CellFlow(wide, g, narrow, narrow_of(g), flow_rate(law, wide, g))
