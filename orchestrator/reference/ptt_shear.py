"""Steady simple shear of the linear Phan-Thien-Tanner fluid, per mode (Nutto et al., seed 002, eqs. 4-6 with
D = (grad v + grad v^T)/2, so eta is a viscosity).

In steady simple shear u = gamma_dot y e_x a mode (lambda s, eta Pa s, epsilon -) has tau_yy = 0 and, with the
Weissenberg number Wi = lambda gamma_dot and f = 1 + (lambda epsilon / eta) tr tau,

    tau_xy = eta gamma_dot / f,   tau_xx = 2 eta lambda gamma_dot^2 / f^2 = N1,   f^3 - f^2 - 2 epsilon Wi^2 = 0

(tr tau = tau_xx gives f = 1 + 2 epsilon Wi^2 / f^2). epsilon = 0 gives f = 1 (Oldroyd-B / UCM: eta, N1 = 2 eta
lambda gamma_dot^2). E.g. epsilon = 0.1, Wi = 1: f = 1.150973, eta_shear / eta = 1/f = 0.868830.
Each mode of a multi-mode material has its own f_i; the total stress is the sum of the modes'.
"""

from __future__ import annotations

import numpy as np


def steady_f(epsilon: float, weissenberg: float) -> float:
    """The real root f >= 1 of f^3 - f^2 - 2 epsilon Wi^2 = 0 (epsilon -, Wi = lambda gamma_dot -)."""
    if epsilon == 0.0 or weissenberg == 0.0:
        return 1.0
    roots = np.roots([1.0, -1.0, 0.0, -2.0 * epsilon * weissenberg**2])
    real = roots[np.abs(roots.imag) < 1e-9].real
    return float(real[real >= 1.0].max())


def steady_mode_stress(relaxation_time: float, viscosity: float, epsilon: float, shear_rate: float
                       ) -> tuple[float, float, float]:
    """(tau_xy, tau_xx, tau_yy) in Pa of one PTT mode (lambda s, eta Pa s, epsilon -) in steady shear (1/s)."""
    f = steady_f(epsilon, relaxation_time * shear_rate)
    return (viscosity * shear_rate / f, 2.0 * viscosity * relaxation_time * shear_rate**2 / f**2, 0.0)
