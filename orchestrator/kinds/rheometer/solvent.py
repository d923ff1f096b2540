"""The loss modulus of a generalized-Newtonian solvent (a Cross law) in oscillatory shear. SI units.

Under the strain gamma(t) = gamma_A sin(omega t) the solvent's stress is tau(t) = eta(|gamma_dot|) gamma_dot with
gamma_dot = gamma_A omega cos(omega t). It has no sin(omega t) part (G' = 0), and eq. 17's fit over whole cycles
takes its first cos(omega t) Fourier coefficient, so with s = omega t

    G'' = (1 / (pi gamma_A)) int_0^{2 pi} tau cos s ds = (omega / pi) int_0^{2 pi} eta(gamma_A omega |cos s|) cos^2 s ds
        = (4 omega / pi) int_0^{pi/2} eta(gamma_A omega cos s) cos^2 s ds

(a constant eta gives eta omega). The Cox-Merz reading G'' = omega eta(omega) of `calibrate maxwell --cross` takes
the shear rate equal to omega instead of the run's gamma_A omega |cos s|; the two agree only where eta is constant
over the rates involved.
"""

from __future__ import annotations

import math

import numpy as np


def first_harmonic_loss_modulus(viscosity, omega, amplitude: float):
    """G'' in Pa of a solvent of viscosity(gamma_dot) (Pa s, gamma_dot 1/s) at angular frequencies omega (rad/s,
    scalar or array) and strain amplitude gamma_A (-), by adaptive quadrature of the first harmonic."""
    from scipy.integrate import quad

    def one(w: float) -> float:
        integral, _ = quad(lambda s: float(viscosity(amplitude * w * math.cos(s))) * math.cos(s) ** 2, 0.0,
                           0.5 * math.pi, epsabs=0.0, epsrel=1e-12, limit=200)
        return 4.0 * w / math.pi * integral

    omega = np.asarray(omega, dtype=float)
    return np.vectorize(one, otypes=[float])(omega) if omega.ndim else one(float(omega))


def cox_merz_loss_modulus(viscosity, omega):
    """omega eta(omega) in Pa (the Cox-Merz reading of a fitted Cross law) at angular frequencies omega (rad/s)."""
    omega = np.asarray(omega, dtype=float)
    return omega * viscosity(omega)
