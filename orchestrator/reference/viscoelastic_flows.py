"""Closed forms for verifying the sph executable's viscoelastic (multi-mode PTT) fluid. SI units.

Conventions (Nutto et al., eqs. 3-8, with the rate of strain D = (grad v + grad v^T) / 2): each mode i
obeys f_i tau_i + lambda_i tau_i^(upper convected) = 2 eta_i D, f_i = 1 + (epsilon lambda_i / eta_i) tr tau_i
(linear PTT, the trace of the mode's own stress, as engines/sph and reference/sph_ptt.py); epsilon = 0 is the
upper-convected Maxwell (UCM) fluid, and UCM plus a Newtonian solvent stress 2 eta_s D is Oldroyd-B. lambda_i is
a relaxation time (s), eta_i a mode's (polymer) viscosity (Pa s), eta_s the solvent viscosity (Pa s).

- Start-up of plane Poiseuille flow of an Oldroyd-B fluid (Waters & King 1970, Rheol. Acta 9:345-355; the series
  as in Duarte, Miranda & Oliveira 2008, J. Non-Newtonian Fluid Mech. 154:153-169, and the SPH verifications of
  Ellero & Tanner 2005, Fang et al. 2006): plates at y = 0 and y = L at rest (no slip), the fluid at rest and
  stress free until a body force per unit mass g along x is switched on at t = 0 (the coordinates of
  reference/sph_flows.py's Morris et al. flows; a pressure gradient -dp/dx is g = -(dp/dx) / rho).
- Steady simple shear of linear PTT modes (the cubic for f), and the multi-mode sum.
- Small-amplitude oscillatory shear gamma(t) = gamma_A sin(omega t) of multi-mode Maxwell/UCM from rest,
  with its start-up transient (what a rheometer simulation shows before it settles).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from orchestrator.errors import OrchestratorError

#: Odd modes summed by default. With a solvent the terms fall as n^-3 (as the Newtonian series); for UCM
#: (eta_s = 0) as n^-2 near the shear-wave fronts, so the error there is ~ 1/n_terms of the peak.
DEFAULT_TERMS = 400


def _check_fluid(rho, eta_polymer, eta_solvent, relaxation_time):
    if not rho > 0:
        raise OrchestratorError(f"rho = {rho}: the density must be above 0 kg/m^3")
    if not (eta_polymer >= 0 and eta_solvent >= 0 and eta_polymer + eta_solvent > 0):
        raise OrchestratorError(f"eta_polymer = {eta_polymer}, eta_solvent = {eta_solvent}: the viscosities must be "
                                "0 or above (Pa s), their sum above 0")
    if not relaxation_time >= 0:
        raise OrchestratorError(f"relaxation_time = {relaxation_time}: must be 0 s or above")


def oldroyd_b_poiseuille_steady_velocity(y, *, gap, body_force, rho, eta_polymer, eta_solvent):
    """Steady plane Poiseuille profile of an Oldroyd-B fluid, m/s: g y (L - y) / (2 nu_0), nu_0 = (eta_s + eta_p)
    / rho (in steady shear Oldroyd-B's shear stress is Newtonian with the total viscosity).

    y: height above the lower plate, m (0 <= y <= L); gap: L, m; body_force: g, m/s^2; rho: kg/m^3;
    eta_polymer, eta_solvent: Pa s.
    """
    y = np.asarray(y, dtype=float)
    return body_force * rho * y * (gap - y) / (2.0 * (eta_polymer + eta_solvent))


def _mode_time_factors(t, k, rho, eta_polymer, eta_solvent, relaxation_time):
    """G_n(t) (-) of each mode (last axis, wavenumbers k in 1/m) at times t (s, any shape): u_n(t) = U_n (1 - G_n)."""
    nu0, nus, lam = (eta_polymer + eta_solvent) / rho, eta_solvent / rho, relaxation_time
    t = np.asarray(t, dtype=float)[..., None]
    rate = nu0 * k**2  # the Newtonian decay rate, 1/s
    if lam == 0.0:
        return np.exp(-rate * t)
    alpha = (1.0 + lam * nus * k**2) / (2.0 * lam)  # 1/s
    w2 = alpha**2 - rate / lam  # (1/s)^2: > 0 overdamped, < 0 underdamped (oscillating)
    w = np.sqrt(np.abs(w2))
    x = w * t
    coefficient = (alpha - rate) * t
    with np.errstate(invalid="ignore", divide="ignore"):
        # overdamped: e^{-alpha t} = e^{-(alpha - w) t} e^{-w t}, alpha - w = (rate / lam) / (alpha + w) without
        # cancellation; e^{-alpha t} sinh(w t) / w = t e^{-(alpha - w) t} h(2 w t), h(z) = (1 - e^{-z}) / z
        slow = np.exp(-(rate / lam) / (alpha + w) * t)
        z = 2.0 * x
        h = np.where(z > 1e-8, -np.expm1(-z) / np.where(z > 1e-8, z, 1.0), 1.0 - 0.5 * z)
        over = slow * (0.5 * (1.0 + np.exp(-z)) + coefficient * h)
        # underdamped: e^{-alpha t} (cos(w t) + (alpha - rate) sin(w t) / w); np.sinc(x / pi) = sin(x) / x
        under = np.exp(-alpha * t) * (np.cos(x) + coefficient * np.sinc(x / math.pi))
    return np.where(w2 >= 0.0, over, under)


def waters_king_startup_velocity(y, t, *, gap, body_force, rho, eta_polymer, eta_solvent, relaxation_time,
                                 n_terms: int = DEFAULT_TERMS):
    """Start-up plane Poiseuille flow of an Oldroyd-B fluid, u(y, t) in m/s (Waters & King 1970).

    y: height above the lower plate, m (0 <= y <= L); t: time since the body force was switched on, s (>= 0);
    y and t broadcast together; gap: L, m; body_force: g, m/s^2 (along x); rho: kg/m^3; eta_polymer: eta_p, Pa s;
    eta_solvent: eta_s, Pa s (beta = eta_s / (eta_s + eta_p)); relaxation_time: lambda, s (0: Newtonian);
    n_terms: odd modes summed.

    Derivation. rho u_t = d tau/dy + eta_s u_yy + rho g with the polymer shear stress lambda tau_t + tau =
    eta_p u_y (the xy component of the UCM law in this flow; tau_yy stays 0). With u = sum_n U_n(t) sin(k_n y),
    tau = sum_n T_n(t) cos(k_n y), k_n = n pi / L and g = sum_{n odd} (4 g / (n pi)) sin(k_n y), each mode obeys
        lambda U'' + (1 + lambda nu_s k^2) U' + nu_0 k^2 U = g_n,   U(0) = 0, U'(0) = g_n,
    nu_s = eta_s / rho, nu_0 = (eta_s + eta_p) / rho. Its roots are -alpha +- w, alpha = (1 + lambda nu_s k^2) /
    (2 lambda), w^2 = alpha^2 - nu_0 k^2 / lambda, so
        u(y, t) = g y (L - y) / (2 nu_0) - sum_{n odd} 4 g L^2 / (nu_0 pi^3 n^3) sin(k_n y) G_n(t),
        G_n(t) = e^{-alpha t} [C(t) + (alpha - nu_0 k^2) S(t)],
    C = cosh(w t), S = sinh(w t) / w when w^2 > 0 (overdamped), C = cos(|w| t), S = sin(|w| t) / |w| when
    w^2 < 0 (underdamped: the velocity overshoots its steady value), C = 1, S = t when w = 0 (critical).
    lambda -> 0 or eta_p = 0 give G_n = exp(-nu k^2 t), the Newtonian series (Morris et al. 1997, eq. 21).
    """
    _check_fluid(rho, eta_polymer, eta_solvent, relaxation_time)
    y, t = np.broadcast_arrays(np.asarray(y, dtype=float), np.asarray(t, dtype=float))
    n = np.arange(1, 2 * n_terms, 2, dtype=float)
    k = n * math.pi / gap
    nu0 = (eta_polymer + eta_solvent) / rho
    amplitude = 4.0 * body_force * gap**2 / (nu0 * math.pi**3 * n**3)
    factors = _mode_time_factors(t, k, rho, eta_polymer, eta_solvent, relaxation_time)
    series = (np.sin(y[..., None] * k) * amplitude * factors).sum(axis=-1)
    steady = oldroyd_b_poiseuille_steady_velocity(y, gap=gap, body_force=body_force, rho=rho,
                                                  eta_polymer=eta_polymer, eta_solvent=eta_solvent)
    return steady - series


def waters_king_centreline_velocity(t, *, gap, body_force, rho, eta_polymer, eta_solvent, relaxation_time,
                                    n_terms: int = DEFAULT_TERMS):
    """Centre-line speed u(L/2, t), m/s, of the Waters & King start-up (see waters_king_startup_velocity; the same
    parameters and units). t: s, any shape. Its steady value is g L^2 / (8 nu_0)."""
    return waters_king_startup_velocity(0.5 * gap, t, gap=gap, body_force=body_force, rho=rho,
                                        eta_polymer=eta_polymer, eta_solvent=eta_solvent,
                                        relaxation_time=relaxation_time, n_terms=n_terms)


# ----------------------------------------------------------------------------------------- steady simple shear
@dataclass(frozen=True)
class PttShear:
    """Steady simple shear of linear PTT: f (-), shear stress tau_xy (Pa), first normal stress difference
    N1 = tau_xx - tau_yy (Pa; tau_yy = 0), shear viscosity tau_xy / gamma_dot (Pa s). Arrays over the rates
    (for one mode, or summed over modes; f is then per mode, shape (..., modes))."""

    f: np.ndarray
    shear_stress: np.ndarray
    first_normal_stress_difference: np.ndarray
    viscosity: np.ndarray


def ptt_f_in_shear(weissenberg, epsilon):
    """f (-) of a linear PTT mode in steady simple shear: the real root f >= 1 of f^3 - f^2 - 2 eps Wi^2 = 0.

    weissenberg: Wi = lambda gamma_dot (-), any shape; epsilon: eps (-, >= 0). Cardano's formula for the one real
    root (the discriminant q/27 + q^2/4, q = 2 eps Wi^2, is >= 0), polished by two Newton steps.
    """
    if not epsilon >= 0:
        raise OrchestratorError(f"epsilon = {epsilon}: the PTT parameter must be 0 or above")
    q = 2.0 * epsilon * np.asarray(weissenberg, dtype=float) ** 2
    # f = x + 1/3: x^3 - x/3 - (2/27 + q) = 0
    half = 1.0 / 27.0 + 0.5 * q
    root = np.sqrt(q / 27.0 + 0.25 * q**2)
    f = np.cbrt(half + root) + np.cbrt(half - root) + 1.0 / 3.0
    for _ in range(2):
        f = f - (f**3 - f**2 - q) / (3.0 * f**2 - 2.0 * f)
    return f


def ptt_steady_shear(shear_rate, relaxation_time, viscosity, epsilon) -> PttShear:
    """Steady simple shear v = (gamma_dot y, 0, 0) of one linear PTT mode (Phan-Thien & Tanner 1977; Nutto et al.
    eqs. 3-6 with D = (grad v + grad v^T) / 2).

    shear_rate: gamma_dot, 1/s (any shape); relaxation_time: lambda, s; viscosity: eta, Pa s; epsilon: eps (-).

    Derivation. With L = grad v (L_xy = gamma_dot) the steady law f tau - lambda (L tau + tau L^T) = eta (L + L^T)
    reads, by component, f tau_yy = 0, f tau_xy - lambda gamma_dot tau_yy = eta gamma_dot, f tau_xx -
    2 lambda gamma_dot tau_xy = 0. So tau_yy = 0, tau_xy = eta gamma_dot / f, N1 = tau_xx = 2 eta lambda
    gamma_dot^2 / f^2, and f = 1 + (eps lambda / eta) tau_xx gives f^3 - f^2 - 2 eps Wi^2 = 0, Wi = lambda
    gamma_dot. eps = 0 is UCM: f = 1, tau_xy = eta gamma_dot, N1 = 2 eta lambda gamma_dot^2.
    """
    rate = np.asarray(shear_rate, dtype=float)
    f = ptt_f_in_shear(relaxation_time * rate, epsilon)
    return PttShear(f=f, shear_stress=viscosity * rate / f,
                    first_normal_stress_difference=2.0 * viscosity * relaxation_time * rate**2 / f**2,
                    viscosity=viscosity / f)


def ptt_multimode_steady_shear(shear_rate, modes, epsilon) -> PttShear:
    """Steady simple shear of a multi-mode linear PTT fluid: each mode (its own f_i, Nutto et al. eq. 8) as in
    ptt_steady_shear, stresses summed (eq. 7). shear_rate: 1/s (any shape); modes: objects with relaxation_time
    (s) and viscosity (Pa s), e.g. reference.maxwell.Mode; epsilon: eps (-), one for all modes. The returned f
    has the modes on its last axis."""
    parts = [ptt_steady_shear(shear_rate, m.relaxation_time, m.viscosity, epsilon) for m in modes]
    return PttShear(f=np.stack([p.f for p in parts], axis=-1),
                    shear_stress=sum(p.shear_stress for p in parts),
                    first_normal_stress_difference=sum(p.first_normal_stress_difference for p in parts),
                    viscosity=sum(p.viscosity for p in parts))


# ------------------------------------------------------------------------------------- oscillatory shear
def maxwell_saos_stress(t, gamma_amplitude, omega, modes):
    """Shear stress tau_xy(t), Pa, of a multi-mode Maxwell fluid under gamma(t) = gamma_A sin(omega t) started
    from rest (stress free) at t = 0, with its start-up transient.

    t: time, s (>= 0, any shape); gamma_amplitude: gamma_A (-); omega: angular frequency, rad/s; modes: objects
    with relaxation_time lambda_i (s) and viscosity eta_i (Pa s), e.g. reference.maxwell.Mode.

    Each mode obeys lambda_i tau_i' + tau_i = eta_i gamma_dot, gamma_dot = gamma_A omega cos(omega t), tau_i(0) = 0:
        tau_i(t) = gamma_A [G'_i sin(omega t) + G''_i (cos(omega t) - e^{-t / lambda_i})],
    G'_i = G_i x^2 / (1 + x^2), G''_i = G_i x / (1 + x^2), x = omega lambda_i, G_i = eta_i / lambda_i (Nutto et al.
    eqs. 18-19). Long after the start it is gamma_A (G' sin + G'' cos). For UCM (PTT eps = 0) in homogeneous
    shear this is exact at any amplitude (tau_yy stays 0, so the shear component is linear); for eps > 0 it is
    the small-amplitude limit.
    """
    t = np.asarray(t, dtype=float)
    total = np.zeros_like(t)
    for mode in modes:
        lam, g = mode.relaxation_time, mode.viscosity / mode.relaxation_time
        x = omega * lam
        storage, loss = g * x**2 / (1.0 + x**2), g * x / (1.0 + x**2)
        total = total + gamma_amplitude * (storage * np.sin(omega * t) + loss * (np.cos(omega * t)
                                                                                 - np.exp(-t / lam)))
    return total


# ------------------------------------------------------------------------------------- start-up of steady shear
@dataclass(frozen=True)
class PttStartup:
    """Start-up of simple shear from rest: times t (s), the summed shear stress tau_xy(t) and first normal stress
    difference N1(t) (Pa) of the modes, the peak of tau_xy (Pa) and its time (s) (the overshoot; the last time
    when tau_xy only rises)."""

    time: np.ndarray
    shear_stress: np.ndarray
    first_normal_stress_difference: np.ndarray
    peak_shear_stress: float
    peak_time: float


def ptt_startup_shear(t, shear_rate, modes, epsilon, solvent_viscosity=0.0, rtol=1e-10) -> PttStartup:
    """Start-up of homogeneous simple shear v = (gamma_dot y, 0) of a multi-mode linear PTT fluid, stress free at
    t = 0, by scipy's ODE integration (the same law and conventions as ptt_steady_shear, each mode its own f_i).

    t: increasing times, s (>= 0); shear_rate: gamma_dot, 1/s (imposed from t = 0+); modes: objects with
    relaxation_time (s) and viscosity (Pa s); epsilon: eps (-, >= 0); solvent_viscosity: eta_s, Pa s (adds
    eta_s gamma_dot to tau_xy for t > 0); rtol: relative tolerance of the integration.

    With L_xy = gamma_dot the law's components are, per mode (tau_yy stays 0 from rest),
        d tau_xx/dt = 2 gamma_dot tau_xy - f tau_xx / lambda,
        d tau_xy/dt = eta gamma_dot / lambda - f tau_xy / lambda,      f = 1 + (eps lambda / eta) tau_xx,
    and their steady state is ptt_steady_shear's. UCM (eps = 0) gives tau_xy = eta gamma_dot (1 - e^{-t/lambda}),
    no overshoot; eps > 0 overshoots at Wi = lambda gamma_dot above about 1.
    """
    from scipy.integrate import solve_ivp

    if not epsilon >= 0:
        raise OrchestratorError(f"epsilon = {epsilon}: the PTT parameter must be 0 or above")
    t = np.asarray(t, dtype=float)
    lam = np.array([m.relaxation_time for m in modes], dtype=float)
    eta = np.array([m.viscosity for m in modes], dtype=float)
    if not (lam.size and np.all(lam > 0) and np.all(eta > 0)):
        raise OrchestratorError("modes: each needs relaxation_time > 0 s and viscosity > 0 Pa s")
    rate = float(shear_rate)
    k = len(lam)

    def rhs(_, y):
        xx, xy = y[:k], y[k:]
        f = 1.0 + epsilon * lam / eta * xx
        return np.concatenate([2.0 * rate * xy - f * xx / lam, (eta * rate - f * xy) / lam])

    def jacobian(_, y):
        xx, xy = y[:k], y[k:]
        f = 1.0 + epsilon * lam / eta * xx
        jac = np.zeros((2 * k, 2 * k))
        idx = np.arange(k)
        jac[idx, idx] = -(f + epsilon * lam / eta * xx) / lam
        jac[idx, k + idx] = 2.0 * rate
        jac[k + idx, idx] = -epsilon / eta * xy
        jac[k + idx, k + idx] = -f / lam
        return jac

    solution = solve_ivp(rhs, (0.0, float(t.max())), np.zeros(2 * k), method="Radau", t_eval=t, rtol=rtol,
                         atol=1e-14 * float(np.sum(eta)) * abs(rate) + 1e-300, jac=jacobian)
    if not solution.success:
        raise OrchestratorError(f"the start-up ODE failed: {solution.message}")
    shear = solution.y[k:].sum(axis=0) + solvent_viscosity * rate * (t > 0)
    normal = solution.y[:k].sum(axis=0)
    peak = int(np.argmax(shear))
    return PttStartup(time=t, shear_stress=shear, first_normal_stress_difference=normal,
                      peak_shear_stress=float(shear[peak]), peak_time=float(t[peak]))
