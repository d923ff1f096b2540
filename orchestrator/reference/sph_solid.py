"""Reference (numpy, brute force) of the sph executable's Johnson-Cook solid in a periodic box.

The same equations as engines/sph (src/materials/johnson_cook_material.h; README "Johnson-Cook solid"), written
independently of it: Wendland C2 kernel (Canini et al. eq. 8), continuity (eq. 7), the solid's pressure (linear
or Mie-Grueneisen with the specific internal energy e, clipped at 0 once failed), the tensor momentum equation
dv_a/dt = sum_b m_b (sigma_a/rho_a^2 + sigma_b/rho_b^2 + f_ab^n (R_a + R_b)) . grad_a W_ab (or, with
corrected_momentum, eq. KC1: sigma_a/rho_a^2 M_a^-T + sigma_b/rho_b^2 M_b^-T with the M of the last evaluation) with Monaghan's
artificial stress R = -epsilon sum_i max(sigma_i, 0)/rho^2 e_i e_i^T and f_ab = W(r_ab)/W(dx), Monaghan's
artificial viscosity (eqs. 11-12) with the solid's wave speed, the kernel-corrected velocity gradient L = G M^-1
(eq. T2), the hypoelastic Jaumann rate ds/dt = 2 G dev(D) + W s - s W (2D: plane strain, ds_zz/dt = -2 G tr D / 3),
de_a/dt = -1/2 sum_b m_b v_ab . f_ab (the work of the pair forces f_ab of the momentum equation, with the artificial
stress and viscosity: kinetic plus internal energy is conserved; sigma : D / rho in the continuum), Monaghan's predictor-corrector (eqs. P1-P4), and after the corrector the radial return,
heating and damage of reference.johnson_cook. Every particle is a solid particle; every axis is periodic (box at
least 4h long). With bodies (SolidState.body), two particles of two bodies take none of the pair terms above but the
contact of eq. SC1 (engines/sph/src/solid_contact.h): a spring k (dx - r) along r_ab for r < dx, k = rho0 c_L^2
dx^(D-2), in compression only. SI units throughout.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from orchestrator.reference import johnson_cook as jc

#: Columns of the solid state (the executable's frames/<k>/solid_state): e J/kg, eps_p -, its rate 1/s, T K,
#: damage -, s_zz Pa (2D plane strain).
ENERGY, PLASTIC_STRAIN, PLASTIC_RATE, TEMPERATURE, DAMAGE, SZZ = range(6)


@dataclass(frozen=True)
class SolidScene:
    """The material and numerics: a jc.Solid (its strength used only when `plastic`, its heat only when its
    heat_fraction > 0), artificial stress epsilon and exponent n, artificial viscosity alpha and beta, h and dx
    (m), box lengths (m, origin 0)."""

    solid: jc.Solid
    plastic: bool
    h: float
    dx: float
    box: tuple[float, ...]
    artificial_stress: float = 0.0
    exponent: int = 4
    alpha: float = 0.0
    beta: float = 0.0
    corrected_momentum: bool = False

    @property
    def wave_speed(self) -> float:
        """sqrt((K + 4G/3) / rho0), m/s."""
        return math.sqrt((self.solid.eos.reference_bulk_modulus + 4.0 / 3.0 * self.solid.shear_modulus)
                         / self.solid.rho0)


@dataclass(frozen=True)
class SolidState:
    """Positions (n, D) m, velocities (n, D) m/s, masses (n) kg, densities (n) kg/m^3, deviatoric stresses
    (n, D, D) Pa, the solid scalars (n, 6) (the columns above), the last rates, the last evaluation's kernel
    correction M^-T (n, D, D) of eq. KC1 (None: the identity), and each particle's body (n) ints (None: one body)."""

    x: np.ndarray
    v: np.ndarray
    m: np.ndarray
    rho: np.ndarray
    s: np.ndarray
    scalars: np.ndarray
    acc: np.ndarray | None = None
    drho: np.ndarray | None = None
    ds: np.ndarray | None = None
    dscalars: np.ndarray | None = None
    correction: np.ndarray | None = None
    body: np.ndarray | None = None


def start_scalars(scene: SolidScene, count: int) -> np.ndarray:
    """The scalars of unstrained particles at the room temperature (K)."""
    scalars = np.zeros((count, 6))
    scalars[:, TEMPERATURE] = scene.solid.strength.room_temperature
    return scalars


def pressure(scene: SolidScene, rho: float, energy: float, failed: bool) -> float:
    """The solid's pressure (Pa) at density rho (kg/m^3) and specific energy e (J/kg); >= 0 once failed."""
    p = scene.solid.eos.pressure(rho, energy)
    return max(p, 0.0) if failed else p


def artificial_stress(sigma_rho2: np.ndarray, epsilon: float) -> np.ndarray:
    """R / rho^2 (n, D, D) from sigma / rho^2 (n, D, D): -epsilon times the tensile principal values."""
    values, vectors = np.linalg.eigh(sigma_rho2)
    return np.einsum("nij,nj,nkj->nik", vectors, -epsilon * np.maximum(values, 0.0), vectors)


def _pairs(x: np.ndarray, scene: SolidScene):
    """Every unordered pair within 2h at its nearest image: indices a, b and r_ab = x_a - x_b (m)."""
    box = np.asarray(scene.box)
    a, b = np.triu_indices(len(x), k=1)
    r = x[a] - x[b]
    r -= box * np.round(r / box)
    keep = np.einsum("ij,ij->i", r, r) < (2.0 * scene.h) ** 2
    return a[keep], b[keep], r[keep]


def contact_stiffness(scene: SolidScene, dim: int) -> float:
    """k of eq. SC1, rho0 c_L^2 dx^(D-2): N/m in 3D, N/m per unit depth in 2D."""
    return scene.solid.rho0 * scene.wave_speed ** 2 * (scene.dx if dim == 3 else 1.0)


def _contacts(state: SolidState, scene: SolidScene, a, b, r):
    """The pairs of two bodies (a, b, r_ab, their overlaps dx - r > 0, m) and a mask of the pairs within one body."""
    within = np.ones(len(a), dtype=bool) if state.body is None else state.body[a] == state.body[b]
    overlap = scene.dx - np.sqrt(np.einsum("ij,ij->i", r[~within], r[~within]))
    touching = overlap > 0.0
    return a[~within][touching], b[~within][touching], r[~within][touching], overlap[touching], within


def contact_energy(state: SolidState, scene: SolidScene) -> float:
    """The springs' energy of eq. SC1, sum 1/2 k (dx - r)^2, J (J/m in 2D)."""
    *_, overlap, _ = _contacts(state, scene, *_pairs(state.x, scene))
    return 0.5 * contact_stiffness(scene, state.x.shape[1]) * float(np.sum(overlap ** 2))


def rates(state: SolidState, scene: SolidScene) -> SolidState:
    """The rates of continuity, momentum, the deviatoric stress and the scalars at this state."""
    n, dim = state.x.shape
    h, eye = scene.h, np.eye(dim)
    alpha_d = 7.0 / (4.0 * math.pi * h * h) if dim == 2 else 21.0 / (16.0 * math.pi * h ** 3)
    failed = state.scalars[:, DAMAGE] >= 1.0
    p = np.array([pressure(scene, rho, e, f) for rho, e, f in zip(state.rho, state.scalars[:, ENERGY], failed)])
    S = (state.s - p[:, None, None] * eye) / state.rho[:, None, None] ** 2
    R = artificial_stress(S, scene.artificial_stress)
    if scene.corrected_momentum and state.correction is not None:  # eq. KC1: sigma_a / rho_a^2 M_a^-T grad W
        S = S @ state.correction
    a, b, r = _pairs(state.x, scene)
    ca, cb, cr, overlap, within = _contacts(state, scene, a, b, r)
    a, b, r = a[within], b[within], r[within]
    q = np.sqrt(np.einsum("ij,ij->i", r, r)) / h
    t = np.maximum(1.0 - 0.5 * q, 0.0)
    F = -5.0 * alpha_d / (h * h) * t ** 3
    q_dx = scene.dx / h
    fn = (t ** 4 * (2.0 * q + 1.0) / ((1.0 - 0.5 * q_dx) ** 4 * (2.0 * q_dx + 1.0))) ** scene.exponent
    vol = state.m / state.rho
    v_ab = state.v[a] - state.v[b]
    vr = np.einsum("ij,ij->i", v_ab, r)
    drho = np.zeros(n)
    np.add.at(drho, a, state.rho[a] * vol[b] * F * vr)
    np.add.at(drho, b, state.rho[b] * vol[a] * F * vr)
    pair = S[a] + S[b] + fn[:, None, None] * (R[a] + R[b])
    f = np.einsum("pij,pj->pi", pair, F[:, None] * r)
    eta2 = 0.01 * h * h
    rho_ab, c = 0.5 * (state.rho[a] + state.rho[b]), scene.wave_speed
    mu_ab = h * np.minimum(vr, 0.0) / (np.einsum("ij,ij->i", r, r) + eta2)
    pi = (-scene.alpha * c * mu_ab + scene.beta * mu_ab ** 2) / rho_ab
    f -= (pi * F)[:, None] * r
    acc = np.zeros((n, dim))
    np.add.at(acc, a, state.m[b][:, None] * f)
    np.add.at(acc, b, -state.m[a][:, None] * f)
    spring = (contact_stiffness(scene, dim) * overlap / (scene.dx - overlap))[:, None] * cr  # eq. SC1, N
    np.add.at(acc, ca, spring / state.m[ca][:, None])
    np.add.at(acc, cb, -spring / state.m[cb][:, None])
    G, M = np.zeros((n, dim, dim)), np.zeros((n, dim, dim))
    for owner, other in ((a, b), (b, a)):
        weight = -(F * vol[other])[:, None, None]
        np.add.at(G, owner, weight * np.einsum("pi,pj->pij", v_ab, r))
        np.add.at(M, owner, weight * np.einsum("pi,pj->pij", r, r))
    L = G @ np.linalg.inv(M)
    correction = np.where(failed[:, None, None], eye, np.swapaxes(np.linalg.inv(M), 1, 2))
    stretching, spin = 0.5 * (L + np.swapaxes(L, 1, 2)), 0.5 * (L - np.swapaxes(L, 1, 2))
    third = np.trace(stretching, axis1=1, axis2=2) / 3.0
    shear = scene.solid.shear_modulus
    ds = 2.0 * shear * (stretching - third[:, None, None] * eye) + spin @ state.s - state.s @ spin
    ds[failed] = 0.0
    dscalars = np.zeros((n, 6))
    if dim == 2:
        dscalars[:, SZZ] = np.where(failed, 0.0, -2.0 * shear * third)
    # de/dt: each pair's force takes m_a m_b v_ab . f from the kinetic energy and gives half to each particle
    power = np.einsum("pi,pi->p", v_ab, f)
    np.add.at(dscalars[:, ENERGY], a, -0.5 * state.m[b] * power)
    np.add.at(dscalars[:, ENERGY], b, -0.5 * state.m[a] * power)
    return replace(state, acc=acc, drho=drho, ds=ds, dscalars=dscalars,
                   correction=correction if scene.corrected_momentum else None)


def _return_mapping(scene: SolidScene, s: np.ndarray, scalars: np.ndarray, rho: float, dt: float):
    """post_correct of one particle: (deviatoric stress (D, D) Pa, scalars (6)) after failure, the radial return,
    heating and damage."""
    dim, scalars = s.shape[0], scalars.copy()
    scalars[PLASTIC_RATE] = 0.0
    if scalars[DAMAGE] >= 1.0:
        scalars[SZZ] = 0.0
        return np.zeros_like(s), scalars
    if not scene.plastic:
        return s, scalars
    full = np.zeros((3, 3))
    full[:dim, :dim] = s
    if dim == 2:
        full[2, 2] = scalars[SZZ]
    step = jc.radial_return(scene.solid, full, np.zeros((3, 3)), scalars[PLASTIC_STRAIN], scalars[TEMPERATURE], dt)
    increment = step.plastic_strain_increment
    if increment <= 0.0:
        return s, scalars
    s = step.deviatoric_stress[:dim, :dim].copy()
    if dim == 2:
        scalars[SZZ] = step.deviatoric_stress[2, 2]
    scalars[PLASTIC_STRAIN] += increment
    scalars[PLASTIC_RATE] = increment / dt
    if scene.solid.heat_fraction > 0.0:
        scalars[TEMPERATURE] += step.temperature_rise
    failure = scene.solid.failure
    if failure is None:
        return s, scalars
    strength = scene.solid.strength
    p = pressure(scene, rho, scalars[ENERGY], False)
    t_star = jc.homologous_temperature(scalars[TEMPERATURE], strength.room_temperature, strength.melting_temperature)
    triaxiality = jc.triaxiality(-p, jc.von_mises(step.deviatoric_stress))
    strain = jc.failure_strain(failure, triaxiality, increment / dt, t_star)
    scalars[DAMAGE] = min(1.0, scalars[DAMAGE] + jc.damage_increment(increment, strain))
    if scalars[DAMAGE] >= 1.0:
        s, scalars[SZZ] = np.zeros_like(s), 0.0
    return s, scalars


def step(state: SolidState, scene: SolidScene, dt: float) -> SolidState:
    """One predictor-corrector step of dt s (eqs. P1-P4) and the return mapping, from a state with its rates."""
    half = 0.5 * dt
    predicted = replace(state, x=state.x + half * state.v, v=state.v + half * state.acc,
                        rho=state.rho + half * state.drho, s=state.s + half * state.ds,
                        scalars=state.scalars + half * state.dscalars)
    mid = rates(predicted, scene)
    rho = state.rho + dt * mid.drho
    s, scalars = state.s + dt * mid.ds, state.scalars + dt * mid.dscalars
    for i in range(len(rho)):
        s[i], scalars[i] = _return_mapping(scene, s[i], scalars[i], rho[i], dt)
    return SolidState(x=state.x + dt * (state.v + half * mid.acc), v=state.v + dt * mid.acc, m=state.m, rho=rho,
                      s=s, scalars=scalars, acc=mid.acc, drho=mid.drho, ds=mid.ds, dscalars=mid.dscalars,
                      correction=mid.correction, body=state.body)


def simulate(state: SolidState, scene: SolidScene, dt: float, n_steps: int) -> SolidState:
    """n_steps steps of dt s from a state without rates (the initial rates are evaluated first; twice with eq.
    KC1, whose M^-T the first gives)."""
    state = rates(state, scene)
    if scene.corrected_momentum:
        state = rates(state, scene)
    for _ in range(n_steps):
        state = step(state, scene, dt)
    return state
