"""Reference (numpy, brute force) of the sph executable's multi-mode PTT fluid in a periodic box.

The same equations as engines/sph (README "PTT viscoelastic fluid"): Wendland C2 kernel (Canini et al. eq. 8),
Tait EOS (eq. 6) or the quadratic EOS of Nutto et al. (eq. 9), continuity (eq. 7), tensor momentum
dv_a/dt = sum_b m_b (sigma_a/rho_a^2 + sigma_b/rho_b^2) . grad_a W_ab (eq. T1), the kernel-corrected
velocity gradient L_a = G_a M_a^-1 (eq. T2), per mode the linear PTT rate
d tau/dt = L tau + tau L^T + (eta (L + L^T) - f tau) / lambda, f = 1 + (lambda eps / eta) tr tau (eq. R1),
the solvent stress 2 (eta_s + eta_C(gamma_dot)) D of the previous evaluation (eta_C the optional Cross law,
gamma_dot = sqrt(2 D:D)), the optional plateau's upper-convected elastic stress after the modes,
d tau_p/dt = L tau_p + tau_p L^T + G_p (L + L^T) (eq. R2), and Monaghan's predictor-corrector with one rate
evaluation per step (eqs. P1-P4). Every particle is fluid; every axis is periodic (box at least 4h long,
so each pair has one image within the support 2h). With subtract_mean_stress the momentum equation takes
sigma - tau_B, tau_B the volume mean of the extra stress at the start of the step (the deck's
lees_edwards.subtract_mean_stress; a uniform stress moves nothing in a periodic box). With stress_diffusion kappa
each mode stress also takes kappa sum_b V_b 2 F r_ab^2 / (r_ab^2 + 0.01 h^2) (tau_a - tau_b) (eq. SD1); with morris
the solvent viscosity eta_s is the Morris pair term instead of 2 eta_s D, dv_a/dt += sum_b 2 eta_s F r_ab^2 /
(r_ab^2 + 0.01 h^2) V_b / rho_a (v_a - v_b) (eq. 10, the deck's morris_viscosity). SI units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np


@dataclass(frozen=True)
class PttFluid:
    """One PTT material and its box: rho0 kg/m^3, c0 m/s, gamma (Tait), lambdas s, etas Pa s, epsilon,
    eta_s Pa s, h m, box lengths m (origin 0), quadratic: Nutto et al.'s EOS instead of Tait; plateau G_p Pa
    (> 0: one more stress column after the modes); cross: the Cross solvent (eta_0 Pa s, eta_inf Pa s, K s, m -)."""

    rho0: float
    c0: float
    lambdas: tuple[float, ...]
    etas: tuple[float, ...]
    epsilon: float
    eta_s: float
    h: float
    box: tuple[float, ...]
    gamma: float = 7.0
    quadratic: bool = False
    subtract_mean_stress: bool = False
    plateau: float = 0.0
    cross: tuple[float, float, float, float] | None = None
    stress_diffusion: float = 0.0
    morris: bool = False


@dataclass(frozen=True)
class PttState:
    """Positions (n, D) m, velocities (n, D) m/s, masses (n) kg, densities (n) kg/m^3, mode stresses
    (n, modes, D, D) Pa, solvent stress of the last evaluation (n, D, D) Pa, and the last rates."""

    x: np.ndarray
    v: np.ndarray
    m: np.ndarray
    rho: np.ndarray
    tau: np.ndarray
    tau_solvent: np.ndarray
    acc: np.ndarray | None = None
    drho: np.ndarray | None = None
    dtau: np.ndarray | None = None


def pressure(rho: np.ndarray, fluid: PttFluid) -> np.ndarray:
    """EOS in Pa: Tait (Canini et al. eq. 6) or p = c0^2 rho^2 / (2 rho0) (Nutto et al. eq. 9)."""
    if fluid.quadratic:
        return fluid.c0 ** 2 * rho ** 2 / (2.0 * fluid.rho0)
    return fluid.rho0 * fluid.c0 ** 2 / fluid.gamma * ((rho / fluid.rho0) ** fluid.gamma - 1.0)


def ptt_mode_rates(L: np.ndarray, tau: np.ndarray, fluid: PttFluid) -> np.ndarray:
    """d tau_i/dt in Pa/s (eq. R1, and eq. R2 for the plateau's column after the modes) for velocity gradients
    L (n, D, D) 1/s (L_jk = dv_j/dx_k) and stresses tau (n, columns, D, D) Pa."""
    modes = len(fluid.lambdas)
    lam = np.asarray(fluid.lambdas)[None, :, None, None]
    eta = np.asarray(fluid.etas)[None, :, None, None]
    t = tau[:, :modes]
    trace = np.trace(t, axis1=2, axis2=3)[:, :, None, None]
    f = 1.0 + lam * fluid.epsilon / eta * trace
    Lm = L[:, None]
    two_d = Lm + np.swapaxes(Lm, 2, 3)
    rate = Lm @ tau + tau @ np.swapaxes(Lm, 2, 3)
    rate[:, :modes] += (eta * two_d - f * t) / lam
    if fluid.plateau > 0.0:
        rate[:, modes] += fluid.plateau * two_d[:, 0]
    return rate


def cross_viscosity(shear_rate, cross) -> np.ndarray:
    """eta_C = eta_inf + (eta_0 - eta_inf) / (1 + (K gamma_dot)^m) in Pa s at shear rates gamma_dot (1/s); cross =
    (eta_0 Pa s, eta_inf Pa s, K s, m -)."""
    eta_0, eta_inf, time, exponent = cross
    return eta_inf + (eta_0 - eta_inf) / (1.0 + (time * np.asarray(shear_rate, dtype=float)) ** exponent)


def solvent_stress(L: np.ndarray, fluid: PttFluid) -> np.ndarray:
    """2 (eta_s + eta_C(gamma_dot)) D in Pa for velocity gradients L (n, D, D) 1/s, gamma_dot = sqrt(2 D:D)."""
    two_d = L + np.swapaxes(L, 1, 2)
    if fluid.cross is None:
        return fluid.eta_s * two_d
    rate = np.sqrt(0.5 * np.einsum("nij,nij->n", two_d, two_d))
    return (fluid.eta_s + cross_viscosity(rate, fluid.cross))[:, None, None] * two_d


def _pairs(x: np.ndarray, fluid: PttFluid):
    """Every unordered pair within 2h at its nearest image: indices a, b and r_ab = x_a - x_b (m)."""
    box = np.asarray(fluid.box)
    a, b = np.triu_indices(len(x), k=1)
    r = x[a] - x[b]
    r -= box * np.round(r / box)
    keep = np.einsum("ij,ij->i", r, r) < (2.0 * fluid.h) ** 2
    return a[keep], b[keep], r[keep]


def mean_extra_stress(state: PttState) -> np.ndarray:
    """Volume mean (weights m / rho) of the extra stress sum_i tau_i + tau_solvent, (D, D) Pa."""
    vol = state.m / state.rho
    extra = state.tau.sum(axis=1) + state.tau_solvent
    return np.tensordot(vol, extra, axes=(0, 0)) / vol.sum()


def rates(state: PttState, fluid: PttFluid, background: np.ndarray | None = None) -> PttState:
    """The rates of eqs. 7, T1, T2, R1 at this state; also the new solvent stress (for the next evaluation).
    background: tau_B (D, D) Pa subtracted from every particle's stress in eq. T1 (with subtract_mean_stress; by
    default this state's mean)."""
    n, dim = state.x.shape
    if background is None:
        background = mean_extra_stress(state) if fluid.subtract_mean_stress else np.zeros((dim, dim))
    h = fluid.h
    alpha = 7.0 / (4.0 * math.pi * h * h) if dim == 2 else 21.0 / (16.0 * math.pi * h ** 3)
    a, b, r = _pairs(state.x, fluid)
    t = np.maximum(1.0 - 0.5 * np.sqrt(np.einsum("ij,ij->i", r, r)) / h, 0.0)
    F = -5.0 * alpha / (h * h) * t ** 3
    vol = state.m / state.rho
    sigma = (state.tau.sum(axis=1) + state.tau_solvent - background
             - pressure(state.rho, fluid)[:, None, None] * np.eye(dim))
    S = sigma / state.rho[:, None, None] ** 2
    v_ab = state.v[a] - state.v[b]
    Fvr = F * np.einsum("ij,ij->i", v_ab, r)
    drho = np.zeros(n)
    np.add.at(drho, a, state.rho[a] * vol[b] * Fvr)
    np.add.at(drho, b, state.rho[b] * vol[a] * Fvr)
    f = np.einsum("pij,pj->pi", S[a] + S[b], F[:, None] * r)
    acc = np.zeros((n, dim))
    np.add.at(acc, a, state.m[b][:, None] * f)
    np.add.at(acc, b, -state.m[a][:, None] * f)
    vr = np.einsum("pi,pj->pij", v_ab, r)
    rr = np.einsum("pi,pj->pij", r, r)
    G = np.zeros((n, dim, dim))
    M = np.zeros((n, dim, dim))
    np.add.at(G, a, -(F * vol[b])[:, None, None] * vr)
    np.add.at(M, a, -(F * vol[b])[:, None, None] * rr)
    np.add.at(G, b, -(F * vol[a])[:, None, None] * vr)
    np.add.at(M, b, -(F * vol[a])[:, None, None] * rr)
    L = G @ np.linalg.inv(M)
    dtau = ptt_mode_rates(L, state.tau, fluid)
    r2 = np.einsum("ij,ij->i", r, r)
    w = 2.0 * F * r2 / (r2 + 0.01 * h * h)
    if fluid.morris:  # eq. 10 with mu = eta_s
        s = fluid.eta_s * w
        np.add.at(acc, a, (s * vol[b] / state.rho[a])[:, None] * v_ab)
        np.add.at(acc, b, -(s * vol[a] / state.rho[b])[:, None] * v_ab)
    if fluid.stress_diffusion > 0.0:  # eq. SD1
        diff = state.tau[a] - state.tau[b]
        lap = np.zeros_like(state.tau)
        np.add.at(lap, a, (w * vol[b])[:, None, None, None] * diff)
        np.add.at(lap, b, -(w * vol[a])[:, None, None, None] * diff)
        dtau = dtau + fluid.stress_diffusion * lap
    solvent = np.zeros_like(L) if fluid.morris else solvent_stress(L, fluid)
    return replace(state, acc=acc, drho=drho, dtau=dtau, tau_solvent=solvent)


def step(state: PttState, fluid: PttFluid, dt: float) -> PttState:
    """One predictor-corrector step of dt s (eqs. P1-P4) from a state that holds its last rates."""
    half = 0.5 * dt
    predicted = replace(state, x=state.x + half * state.v, v=state.v + half * state.acc,
                        rho=state.rho + half * state.drho, tau=state.tau + half * state.dtau)
    background = mean_extra_stress(state) if fluid.subtract_mean_stress else None
    mid = rates(predicted, fluid, background)
    return PttState(x=state.x + dt * (state.v + half * mid.acc), v=state.v + dt * mid.acc,
                    m=state.m, rho=state.rho + dt * mid.drho, tau=state.tau + dt * mid.dtau,
                    tau_solvent=mid.tau_solvent, acc=mid.acc, drho=mid.drho, dtau=mid.dtau)


def simulate(state: PttState, fluid: PttFluid, dt: float, n_steps: int) -> PttState:
    """n_steps steps of dt s from a state without rates (the initial rates are evaluated first)."""
    state = rates(state, fluid)
    for _ in range(n_steps):
        state = step(state, fluid, dt)
    return state
