"""Reference weakly compressible SPH in numpy: the equations of the sph
executable (engines/sph; Canini et al.), written plainly over
explicit neighbour pairs, for small scenes (up to a few thousand particles).

Same model and algorithm as the executable, departures from the paper
included (engines/sph/README.md):
- Wendland C2 kernel with support 2h (eq. 8), alpha_D = 7/(4 pi h^2) in 2D,
  21/(16 pi h^3) in 3D;
- Tait EOS with background pressure (eq. 6); a fixed boundary particle's
  pressure and sound speed are those of max(rho, rho0) (a grain's particle's of its own density);
- continuity (eq. 7) with the sign of drho/dt = -rho div v; fixed boundary
  particles evolve by the rate of the summation density, sum m_b v_ab . grad W;
- pressure gradient (eq. 9 / rho_a), Morris viscosity (eq. 10, mu = rho0 nu,
  boundary particles entering with the mirrored velocity 2 v_b - <v>_fluid),
  Monaghan artificial viscosity (eqs. 11-12), body force, penalty walls
  (eq. 14, orchestrator.reference.sph_walls);
- the renormalised Morris sum (optional, viscosity_correction; engine eq. VC1):
  each fluid particle's viscous sum times k_a = D / sum_b V_b (-F_ab) r_ab^4 /
  (r_ab^2 + 0.01 h^2), over all its neighbours (morris_correction_factors);
- Smagorinsky's eddy viscosity (optional, eddy_viscosity = cs; engine eqs.
  SM1-SM2): nu_t,a = (cs dx)^2 sqrt(2 S:S) of S = sym(L_a), L_a = -sum_b V_b
  F_ab (v_a - v_b) (x) r_ab with a boundary b at its no-slip velocity; the
  Morris mu_ab gains rho0 (nu_t,a + nu_t,b) / 2 between fluid particles and
  rho0 nu_t of the fluid one against a boundary particle (none with
  eddy_walls = False); a step uses the nu_t
  of the previous evaluation (SphState.nu_t; of the initial state first);
- several materials (optional): each particle's rho0, c0, gamma, p_B and nu
  are its material's (EOS, boundary pressure of max(rho, rho0)); the Morris
  term of two different materials takes the harmonic mean
  mu_ab = 2 mu_a mu_b / (mu_a + mu_b) for (mu_a + mu_b)/2, one material its mu
  (engines/sph/src/material.h);
- periodic axes: every image within 2h (the executable's cell lists find the
  same ones when the periodic length is at least 4h);
- Monaghan's predictor-corrector leapfrog with one rate evaluation per step,
  at the half step; a, Drho are the rates of the previous step's evaluation
  (of the initial state before the first step):
  x* = x + dt/2 v, v* = v + dt/2 a, rho* = rho + dt/2 Drho; a*, Drho* at
  (x*, v*, rho*); then v' = v + dt a*, rho' = rho + dt Drho*,
  x' = x + dt (v + dt/2 a*); a*, Drho* are the next step's a, Drho.
Inlets and outlets are not modelled here.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, replace

import numpy as np

from orchestrator.reference.sph_kernel import (  # noqa: F401  (part of this module's API)
    kernel_gradient_factor, kernel_value, neighbour_pairs, sound_speed, tait_pressure, wrap)
from orchestrator.reference.sph_walls import PenaltyWalls

FLUID, BOUNDARY, GRAIN = 0, 1, 4  # GRAIN: a rigid grain's particle (sph_grains.py)


@dataclass(frozen=True)
class SphMaterial:
    """One material: rho0 kg/m^3, c0 m/s, gamma -, background pressure Pa, kinematic viscosity m^2/s (or None)."""

    rho0: float
    c0: float
    gamma: float = 7.0
    background_pressure: float = 0.0
    viscosity: float | None = None


@dataclass(frozen=True)
class SphModel:
    """The physics of a run (SI units). Optional terms are None when off."""

    dimension: int
    rho0: float  # kg/m^3
    c0: float  # m/s
    h: float  # smoothing length, m
    gamma: float = 7.0
    background_pressure: float = 0.0  # Pa
    viscosity: float | None = None  # kinematic nu, m^2/s (Morris, eq. 10)
    alpha: float | None = None  # artificial viscosity (eqs. 11-12), -
    beta: float = 0.0
    av_walls: bool = True  # eqs. 11-12 also on fluid-boundary pairs; False: fluid-fluid pairs only
    body_force: tuple | None = None  # m/s^2
    walls: PenaltyWalls | None = None
    periodic_axes: tuple[int, ...] = ()
    periodic_lo: tuple[float, ...] = ()  # m, one per periodic axis
    periodic_hi: tuple[float, ...] = ()
    materials: tuple[SphMaterial, ...] = ()  # several materials (SphState.material indexes them); else the above
    viscosity_correction: bool = False  # the Morris sum renormalised per particle (engine eq. VC1)
    eddy_viscosity: float | None = None  # Smagorinsky's cs (engine eqs. SM1-SM2), -
    dx: float = 0.0  # lattice spacing, m: the eddy viscosity's length cs dx
    eddy_walls: bool = True  # nu_t also on fluid-boundary pairs; False: fluid-fluid pairs only
    density_diffusion: float | None = None  # delta of engine eq. DD1 (fluid-fluid pairs), -

    def material_list(self) -> tuple[SphMaterial, ...]:
        """The materials, or the one material of rho0, c0, gamma, background_pressure and viscosity."""
        if self.materials:
            return self.materials
        return (SphMaterial(self.rho0, self.c0, self.gamma, self.background_pressure, self.viscosity),)

    @property
    def viscous(self) -> bool:
        """True if the Morris term is on (a material has a viscosity)."""
        return any(m.viscosity is not None for m in self.material_list())

    @property
    def eta2(self) -> float:
        """0.01 h^2, m^2 (the regularisation of eqs. 10-11)."""
        return 0.01 * self.h * self.h


@dataclass(frozen=True)
class SphState:
    """Particle state: x (n, D) m, v (n, D) m/s, rho (n) kg/m^3, mass (n) kg, kind (n) 0 fluid / 1 boundary;
    acc (n, D) m/s^2 and drho (n) kg/m^3/s: the rates of the last evaluation (None before the first step);
    material (n) index into SphModel.material_list() (None: all 0); nu_t (n) m^2/s: the eddy viscosity of the last
    evaluation (None: 0); spin (n, 3) rad/s: a grain particle's grain's angular velocity (None: no grains)."""

    x: np.ndarray
    v: np.ndarray
    rho: np.ndarray
    mass: np.ndarray
    kind: np.ndarray
    acc: np.ndarray | None = None
    drho: np.ndarray | None = None
    material: np.ndarray | None = None
    nu_t: np.ndarray | None = None
    spin: np.ndarray | None = None


def particle_materials(state: SphState, model: SphModel) -> SphMaterial:
    """Every particle's material parameters as arrays (n,) in one SphMaterial (viscosity 0 where None)."""
    materials = model.material_list()
    index = np.zeros(len(state.mass), dtype=np.int64) if state.material is None else np.asarray(state.material)
    rho0, c0, gamma, p_b = (np.array([getattr(m, key) for m in materials], dtype=float)[index]
                            for key in ("rho0", "c0", "gamma", "background_pressure"))
    nu = np.array([m.viscosity or 0.0 for m in materials])[index]
    return SphMaterial(rho0, c0, gamma, p_b, nu)


def pair_viscosity(model: SphModel) -> np.ndarray:
    """mu_ab of eq. 10 for every two materials (k, l), Pa s: mu_k when k = l, else the harmonic mean
    2 mu_k mu_l / (mu_k + mu_l) (0 when both are 0); mu = rho0 nu."""
    mu = np.array([m.rho0 * (m.viscosity or 0.0) for m in model.material_list()])
    total = mu[:, None] + mu[None, :]
    harmonic = np.divide(2.0 * mu[:, None] * mu[None, :], total, out=np.zeros_like(total), where=total > 0.0)
    return np.where(np.eye(len(mu), dtype=bool), mu[:, None] * np.ones_like(total), harmonic)


def _sum_to(index: np.ndarray, values: np.ndarray, n: int) -> np.ndarray:
    out = np.zeros((n,) + values.shape[1:])
    np.add.at(out, index, values)
    return out


def rates(state: SphState, model: SphModel) -> tuple[np.ndarray, np.ndarray]:
    """(dv/dt (n, D) m/s^2, drho/dt (n) kg/m^3/s) of every particle at the state (zero acceleration for
    boundary particles; a grain's particle: the reaction of its fluid pairs, eq. G1)."""
    n, d = state.x.shape
    fluid = state.kind == FLUID
    own = particle_materials(state, model)
    rho_eos = np.where(fluid | (state.kind == GRAIN), state.rho, np.maximum(state.rho, own.rho0))
    p = tait_pressure(rho_eos, own)
    c = sound_speed(rho_eos, own)
    vol = state.mass / state.rho
    p_rho2 = p / (state.rho * state.rho)
    a, b, r_ab = neighbour_pairs(state.x, model)
    r2 = np.einsum("ij,ij->i", r_ab, r_ab)
    F = kernel_gradient_factor(np.sqrt(r2), model.h, d)
    grad_w = F[:, None] * r_ab
    v_ab = state.v[a] - state.v[b]
    v_dot_grad = np.einsum("ij,ij->i", v_ab, grad_w)
    moving = fluid[a]

    drho = np.where(moving, state.rho[a] * vol[b] * v_dot_grad, state.mass[b] * v_dot_grad)
    acc_pairs = -(state.mass[b] * (p_rho2[a] + p_rho2[b]))[:, None] * grad_w
    if model.viscous:
        v_noslip = _no_slip_velocities(state, model)
        s = _morris_factors(state, model, a, b, r_ab, r2, grad_w)
        acc_pairs += s[:, None] * (state.v[a] - v_noslip[b])
    if model.alpha is not None:
        vr = np.einsum("ij,ij->i", v_ab, r_ab)
        approaching = vr < 0.0
        mu_ab = model.h * vr / (r2 + model.eta2)
        rho_ab = 0.5 * (state.rho[a] + state.rho[b])
        c_ab = 0.5 * (c[a] + c[b])
        pi_ab = np.where(approaching, (-model.alpha * c_ab * mu_ab + model.beta * mu_ab * mu_ab) / rho_ab, 0.0)
        if not model.av_walls:
            pi_ab = np.where(fluid[b], pi_ab, 0.0)
        acc_pairs -= (state.mass[b] * pi_ab)[:, None] * grad_w
    acc = _sum_to(a[moving], acc_pairs[moving], n)
    grain = state.kind == GRAIN
    if grain.any():  # eq. G1: each fluid-grain pair's reaction on the grain's particle (sph_grains.py)
        react = moving & grain[b]
        acc += _sum_to(b[react], -(state.mass[a] / state.mass[b])[react][:, None] * acc_pairs[react], n)
    if model.density_diffusion is not None:
        drho = drho + _density_diffusion(state, model, a, b, r_ab, r2, F, fluid)
    drho_sum = _sum_to(a, drho, n)
    if model.body_force is not None:
        acc[fluid] += np.asarray(model.body_force, dtype=float)
    if model.walls is not None and fluid.any():
        acc[fluid] += model.walls.forces(state.x[fluid]) / state.mass[fluid][:, None]
    acc[~(fluid | grain)] = 0.0
    return acc, drho_sum


def _density_diffusion(state: SphState, model: SphModel, a, b, r_ab, r2, F, fluid) -> np.ndarray:
    """Engine eq. DD1 per pair (a, b), kg/m^3/s: between two fluid particles 2 delta h c0 V_b (rho_a - rho_b -
    rho0/c0^2 g . r_ab) F r^2 / (r^2 + 0.01 h^2) (Molteni & Colagrossi 2009; Fourtakas et al. 2019), else 0;
    F: the pairs' kernel gradient factors (grad_a W_ab = F r_ab)."""
    g = np.zeros(state.x.shape[1]) if model.body_force is None else np.asarray(model.body_force, dtype=float)
    hydrostatic = model.rho0 / model.c0 ** 2 * (r_ab @ g)
    w = 2.0 * model.density_diffusion * model.h * model.c0 * F * r2 / (r2 + model.eta2)
    vol_b = state.mass[b] / state.rho[b]
    return np.where(fluid[a] & fluid[b], w * vol_b * (state.rho[a] - state.rho[b] - hydrostatic), 0.0)


def _morris_factors(state: SphState, model: SphModel, a, b, r_ab, r2, grad_w) -> np.ndarray:
    """Eq. 10's factor of each pair (a, b), 1/s: 2 mu_ab V_b / rho_a (r_ab . grad W) / (r_ab^2 + eta^2), with the eddy
    viscosity (eq. SM2) and the renormalisation k_a (eq. VC1) where the model has them."""
    n = len(state.mass)
    fluid = state.kind == FLUID
    vol = state.mass / state.rho
    index = np.zeros(n, dtype=np.int64) if state.material is None else np.asarray(state.material)
    mu = pair_viscosity(model)[index[a], index[b]]
    if model.eddy_viscosity is not None and state.nu_t is not None:  # eq. SM2
        wall = 1.0 if model.eddy_walls else 0.0
        nu_ab = np.where(fluid[a] & fluid[b], 0.5 * (state.nu_t[a] + state.nu_t[b]),
                         wall * (state.nu_t[a] + state.nu_t[b]))
        mu = mu + model.rho0 * nu_ab
    s = 2.0 * mu * vol[b] / state.rho[a] * np.einsum("ij,ij->i", r_ab, grad_w) / (r2 + model.eta2)
    if model.viscosity_correction:
        s = s * morris_correction_factors(a, r2, vol[b], n, model)[a]
    return s


def grain_levers(state: SphState, model: SphModel) -> np.ndarray:
    """Eq. G5 (engines/sph/src/grain_pairs.h) of every particle, m/s: a grain particle g's sum over its fluid pairs of
    its side's viscous factor times x_g - x_f (zero elsewhere); m_g omega x q_g is the part of its viscous reaction
    that answers the grain's own rotation, which the grain's torque leaves out (sph_grains.wrenches)."""
    n, d = state.x.shape
    levers = np.zeros((n, d))
    if not model.viscous:
        return levers
    a, b, r_ab = neighbour_pairs(state.x, model)
    r2 = np.einsum("ij,ij->i", r_ab, r_ab)
    grad_w = kernel_gradient_factor(np.sqrt(r2), model.h, d)[:, None] * r_ab
    s = _morris_factors(state, model, a, b, r_ab, r2, grad_w)  # the fluid side's factor; the grain's: m_a/m_b s
    react = (state.kind[a] == FLUID) & (state.kind[b] == GRAIN)
    a, b, r_ab, s = a[react], b[react], r_ab[react], s[react]
    return _sum_to(b, -(state.mass[a] / state.mass[b] * s)[:, None] * r_ab, n)  # m_a/m_b s (x_b - x_a)


def eddy_viscosities(state: SphState, model: SphModel) -> np.ndarray:
    """nu_t of eq. SM1 (engines/sph/src/eddy_viscosity.h) of every particle at the state, m^2/s: (cs dx)^2
    sqrt(2 S:S) of the symmetric part S of L_a = -sum_b V_b F_ab (v_a - v_b^no-slip) (x) r_ab; 0 for boundary
    particles (and for every particle when the model has no eddy viscosity)."""
    n, d = state.x.shape
    fluid = state.kind == FLUID
    if model.eddy_viscosity is None:
        return np.zeros(n)
    a, b, r_ab = neighbour_pairs(state.x, model)
    keep = fluid[a]
    a, b, r_ab = a[keep], b[keep], r_ab[keep]
    factor = kernel_gradient_factor(np.linalg.norm(r_ab, axis=1), model.h, d) * (state.mass[b] / state.rho[b])
    v_g = state.v[a] - _no_slip_velocities(state, model)[b]
    grad = _sum_to(a, -factor[:, None, None] * v_g[:, :, None] * r_ab[:, None, :], n)
    strain = 0.5 * (grad + np.transpose(grad, (0, 2, 1)))
    nu_t = (model.eddy_viscosity * model.dx) ** 2 * np.sqrt(2.0 * np.einsum("nij,nij->n", strain, strain))
    return np.where(fluid, nu_t, 0.0)


def morris_correction_factors(a: np.ndarray, r2: np.ndarray, vol_b: np.ndarray, n: int, model: SphModel) -> np.ndarray:
    """k of eq. VC1 (engines/sph/src/viscosity_correction.h) for each of the n particles, -: D over
    sum_b V_b (-F_ab) r_ab^4 / (r_ab^2 + 0.01 h^2) over the pairs (a, b) with |r_ab|^2 = r2 (m^2) and V_b = vol_b
    (m^D); 1 for a particle without neighbours. With k the Morris sum of a quadratic velocity field is its exact
    Laplacian where the weighted second moment of the neighbours is isotropic (a regular lattice)."""
    d = model.dimension
    g = -kernel_gradient_factor(np.sqrt(r2), model.h, d) * r2 * r2 / (r2 + model.eta2)
    total = _sum_to(a, vol_b * g, n)
    return np.divide(float(d), total, out=np.ones(n), where=total > 0.0)


def _no_slip_velocities(state: SphState, model: SphModel) -> np.ndarray:
    """v for fluid; 2 v_b - (Shepard average of the fluid velocity within 2h) for boundary particles; for a grain's
    particle the fluid's velocity relative to the grain's rotation, v_f - omega x (x_f - x_b), is averaged (engine eq.
    G4), m/s."""
    v_noslip = state.v.copy()
    boundary = np.nonzero((state.kind == BOUNDARY) | (state.kind == GRAIN))[0]
    fluid = np.nonzero(state.kind == FLUID)[0]
    if not len(boundary) or not len(fluid):
        return v_noslip
    b, f, r_bf = _pairs_including_coincident(state.x[boundary], state.x[fluid], model)
    w = kernel_value(np.linalg.norm(r_bf, axis=1), model.h, model.dimension)
    weight = _sum_to(b, w, len(boundary))
    seen = state.v[fluid][f]
    if state.spin is not None:  # r_bf = x_b - x_f: omega x (x_f - x_b) = -omega x r_bf
        seen = seen + np.cross(state.spin[boundary][b], r_bf)
    velocity = _sum_to(b, w[:, None] * seen, len(boundary))
    wet = weight > 0.0
    rows = boundary[wet]
    v_noslip[rows] = 2.0 * state.v[rows] - velocity[wet] / weight[wet][:, None]
    return v_noslip


def _pairs_including_coincident(targets: np.ndarray, sources: np.ndarray, model: SphModel):
    """Pairs (target i, source j, r = target - source image) with |r| < 2h, coincident points included."""
    from scipy.spatial import cKDTree

    support = 2.0 * model.h
    lengths = [hi - lo for lo, hi in zip(model.periodic_lo, model.periodic_hi)]
    parts = []
    tree = cKDTree(targets)
    for combo in itertools.product((-1, 0, 1), repeat=len(model.periodic_axes)):
        shift = np.zeros(model.dimension)
        for axis, k, length in zip(model.periodic_axes, combo, lengths):
            shift[axis] = k * length
        image = sources + shift
        matrix = tree.sparse_distance_matrix(cKDTree(image), support * (1 + 1e-12), output_type="ndarray")
        i, j = matrix["i"].astype(np.int64), matrix["j"].astype(np.int64)
        r = targets[i] - image[j]
        keep = np.einsum("ij,ij->i", r, r) < support * support
        parts.append((i[keep], j[keep], r[keep]))
    return tuple(np.concatenate(items) for items in zip(*parts))


def last_rates(state: SphState, model: SphModel) -> tuple[np.ndarray, np.ndarray]:
    """The rates of the state's last evaluation, or of the state itself before the first step
    ((n, D) m/s^2, (n) kg/m^3/s)."""
    if state.acc is None or state.drho is None:
        return rates(state, model)
    return state.acc, state.drho


def step(state: SphState, model: SphModel, dt: float) -> SphState:
    """One predictor-corrector step of dt seconds with one rate evaluation, at the half step; the
    predictor uses the rates of the last evaluation. Boundary particles keep x and v."""
    moves = state.kind == FLUID
    if state.acc is None and model.eddy_viscosity is not None:  # the engine's first evaluation sets nu_t
        acc0, drho0 = rates(state, model)
        state = replace(state, acc=acc0, drho=drho0, nu_t=eddy_viscosities(state, model))
    acc0, drho0 = last_rates(state, model)
    half = 0.5 * dt
    x_half = state.x.copy()
    x_half[moves] = wrap(state.x[moves] + half * state.v[moves], model)
    v_half = state.v + half * acc0
    mid = replace(state, x=x_half, v=v_half, rho=state.rho + half * drho0)
    acc1, drho1 = rates(mid, model)
    x_new = state.x.copy()
    x_new[moves] = wrap(state.x[moves] + dt * (state.v[moves] + half * acc1[moves]), model)
    nu_t = eddy_viscosities(mid, model) if model.eddy_viscosity is not None else state.nu_t
    return replace(state, x=x_new, v=state.v + dt * acc1, rho=state.rho + dt * drho1, acc=acc1, drho=drho1,
                   nu_t=nu_t)


def simulate(state: SphState, model: SphModel, dt: float, n_steps: int, every: int = 0):
    """Advance n_steps fixed steps of dt s; returns (final state, [(step, state) every `every` steps])."""
    states = []
    state = replace(state, x=wrap(state.x, model))
    for k in range(1, n_steps + 1):
        state = step(state, model, dt)
        if every and k % every == 0:
            states.append((k, state))
    return state, states


def from_scene(scene) -> tuple[SphState, SphModel]:
    """The state and model of an SphScene (orchestrator.kinds.sph_flow.scene); ValueError for inlets or outlets."""
    case = scene.case
    if case.inlets or case.outlets:
        raise ValueError("the reference SPH does not model inlets and outlets")
    if scene.wall_point is not None:
        raise ValueError("the reference SPH does not model wall points (a block's cylinder.wall): its walls mirror "
                         "the velocity on the lattice")
    physics = case.physics
    walls = None
    if physics.wall_penalty is not None:
        wp = physics.wall_penalty
        walls = PenaltyWalls({name: (m.vertices, m.faces) for name, m in scene.meshes.items()}, wp.range, wp.s, wp.psi)
    axes = tuple(case.domain.periodic)
    av = physics.artificial_viscosity
    first = scene.materials[0]
    several = tuple(SphMaterial(m.rho0, m.c0, m.gamma, m.background_pressure, m.viscosity)
                    for m in scene.materials) if case.materials else ()
    model = SphModel(
        dimension=case.dimension, rho0=first.rho0, c0=first.c0, h=scene.h, gamma=first.gamma,
        background_pressure=first.background_pressure, viscosity=first.viscosity, materials=several,
        alpha=None if av is None else av.alpha, beta=0.0 if av is None else av.beta,
        av_walls=True if av is None else av.walls,
        body_force=physics.body_force if scene.body_force is None else scene.body_force, walls=walls, periodic_axes=axes,
        periodic_lo=tuple(case.domain.lo[a] for a in axes), periodic_hi=tuple(case.domain.hi[a] for a in axes),
        viscosity_correction=physics.viscosity_correction, eddy_viscosity=physics.eddy_viscosity,
        eddy_walls=physics.eddy_viscosity_walls, dx=case.numerics.dx, density_diffusion=physics.density_diffusion,
    )
    state = SphState(x=np.array(scene.positions, dtype=float), v=np.array(scene.velocities, dtype=float),
                     rho=np.array(scene.densities, dtype=float), mass=np.array(scene.masses, dtype=float),
                     kind=np.array(scene.kind, dtype=np.int8),
                     material=None if not case.materials else np.array(scene.material, dtype=np.int64))
    return state, model
