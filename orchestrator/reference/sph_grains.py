"""Rigid grains in the reference SPH (orchestrator.reference.sph): the engine's eqs. G1-G5
(engines/sph/src/grains.h), written plainly. SI units.

A grain is a set of particles (kind 4) moved as one rigid body (orchestrator.reference.rigid_body) at its own
density: its mass and inertia are those of its particles with masses m_i rho_g / rho0 (the particles keep the
fluid's mass and density in the pair terms). sph.rates gives each grain particle the reaction of its fluid pairs
(eq. G1); their sums are the grain's force and torque about its centre (G2). One step (G3), with F, T of the previous
evaluation (of the initial state before the first step) and g_g the grain's body force per unit mass:
  predict:  X* = X + V dt/2, q* = rotor(q, L, dt/2); the fluid sees V* = V + dt/2 (F/M + g_g), L* = L + dt/2 T;
  the rates at the half step give F*, T*;
  correct:  V' = V + dt (F* + M g_g)/M, L' = L + dt T*, then X' = X* + V' dt/2, q' = rotor(q*, L', dt/2).
A particle moves by its grain's displacement, x' = x + (X' - X) + (R' - R) r, at V + omega x R r; its spin (the
state's `spin`, omega) makes its no-slip velocity mirror the fluid's relative to the grain's rotation (eq. G4).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, replace

import numpy as np

from orchestrator.reference import rigid_body as rb
from orchestrator.reference.sph import (
    FLUID,
    GRAIN,
    grain_levers,
    SphModel,
    SphState,
    last_rates,
    rates,
    wrap,
)


@dataclass(frozen=True)
class Grains:
    """The grains of a run: bodies (rigid_body.Body), states (rigid_body.State), each one's particle rows and
    body-frame offsets (n_k, 3) m, body force (3,) m/s^2, and the fluid's force (N) and torque (N m) of the last
    evaluation (None before the first)."""

    bodies: tuple
    states: tuple
    rows: tuple
    offsets: tuple
    body_force: tuple
    force: tuple | None = None
    torque: tuple | None = None


def grains_from_scene(scene, state: SphState) -> tuple[Grains, SphState]:
    """The scene's grains (scene.grain, scene.grains) and the state with their particles placed at their poses and
    rigid velocities, as the engine starts them."""
    x, v, spin = state.x.copy(), state.v.copy(), np.zeros((len(state.x), 3))
    rho0 = np.array([m.rho0 for m in scene.materials])[np.zeros(len(x), int) if scene.material is None
                                                        else np.asarray(scene.material)]
    parts = []
    for k, deck in enumerate(scene.grains):
        rows = np.nonzero(np.asarray(scene.grain) == k)[0]
        masses = state.mass[rows] * deck["density"] / rho0[rows]
        body, start, offsets = rb.body_from_particles(state.x[rows], masses, scene.case.numerics.dx)
        start = rb.with_velocities(body, start, deck["velocity"], deck["angular_velocity"])
        arm = offsets @ rb.rotation_matrix(start.orientation).T
        x[rows], v[rows] = start.position + arm, start.velocity + np.cross(start.angular_velocity, arm)
        spin[rows] = start.angular_velocity
        parts.append((body, start, rows, offsets, np.asarray(deck["body_force"], float)))
    return Grains(*(tuple(p) for p in zip(*parts))), replace(state, x=x, v=v, spin=spin)


def wrenches(grains: Grains, state: SphState, acc: np.ndarray, states, model: SphModel) -> tuple[tuple, tuple]:
    """Each grain's force (N) and torque about its centre (N m) from its particles' reactions acc (eq. G2), the arms
    R r of the poses `states`; the torque without the viscous reactions' answer to the grain's own rotation,
    m omega x q (eq. G5, sph.grain_levers, omega the state's spin)."""
    levers = grain_levers(state, model)
    forces, torques = [], []
    for rows, offsets, st in zip(grains.rows, grains.offsets, states):
        f = state.mass[rows][:, None] * acc[rows]
        rigid = state.mass[rows][:, None] * np.cross(state.spin[rows], levers[rows])
        arm = offsets @ rb.rotation_matrix(st.orientation).T
        forces.append(f.sum(axis=0))
        torques.append((np.cross(arm, f) - np.cross(arm, rigid)).sum(axis=0))
    return tuple(forces), tuple(torques)


def _drift(body, st, dt: float):
    q = rb.free_rotor(body, st.orientation, st.angular_momentum, dt)
    return dataclasses.replace(st, position=st.position + dt * st.velocity, orientation=q,
                               angular_velocity=rb.angular_velocity(body, q, st.angular_momentum))


def _move(x, v, spin, rows, offsets, before, after, velocity, omega):
    """x, v, spin of a grain's rows moved from pose `before` to pose `after` and given V + omega x R r, omega."""
    arm = offsets @ rb.rotation_matrix(after.orientation).T
    x[rows] = x[rows] + (after.position - before.position) + (arm - offsets @ rb.rotation_matrix(before.orientation).T)
    v[rows] = velocity + np.cross(omega, arm)
    spin[rows] = omega


def step(state: SphState, grains: Grains, model: SphModel, dt: float) -> tuple[SphState, Grains]:
    """One step of dt (s) of fluid and grains (sph.step with eq. G3)."""
    moves = state.kind == FLUID
    acc0, drho0 = last_rates(state, model)
    force, torque = (grains.force, grains.torque) if grains.force is not None else \
        wrenches(grains, state, acc0, grains.states, model)
    half = 0.5 * dt
    x_half, v_half, spin_half = state.x.copy(), state.v + half * acc0, state.spin.copy()
    x_half[moves] = wrap(state.x[moves] + half * state.v[moves], model)
    mids = []
    for body, st, rows, offsets, g, f, t in zip(grains.bodies, grains.states, grains.rows, grains.offsets,
                                                grains.body_force, force, torque):
        mid = _drift(body, st, half)
        seen = st.velocity + half * (f / body.mass + g)
        omega = rb.angular_velocity(body, mid.orientation, st.angular_momentum + half * t)
        _move(x_half, v_half, spin_half, rows, offsets, st, mid, seen, omega)
        mids.append(mid)
    halfway = replace(state, x=x_half, v=v_half, spin=spin_half, rho=state.rho + half * drho0)
    acc1, drho1 = rates(halfway, model)
    force, torque = wrenches(grains, halfway, acc1, mids, model)
    x_new, v_new, spin_new = state.x.copy(), state.v + dt * acc1, state.spin.copy()
    x_new[moves] = wrap(state.x[moves] + dt * (state.v[moves] + half * acc1[moves]), model)
    ends = []
    for body, st, mid, rows, offsets, g, f, t in zip(grains.bodies, grains.states, mids, grains.rows, grains.offsets,
                                                     grains.body_force, force, torque):
        velocity = st.velocity + dt / body.mass * (f + body.mass * g)
        momentum = st.angular_momentum + dt * t
        kicked = dataclasses.replace(mid, velocity=velocity, angular_momentum=momentum,
                                     angular_velocity=rb.angular_velocity(body, mid.orientation, momentum))
        end = _drift(body, kicked, half)
        _move(x_new, v_new, spin_new, rows, offsets, st, end, end.velocity, end.angular_velocity)
        ends.append(end)
    new = replace(state, x=x_new, v=v_new, spin=spin_new, rho=state.rho + dt * drho1, acc=acc1, drho=drho1)
    return new, replace(grains, states=tuple(ends), force=force, torque=torque)


__all__ = ["GRAIN", "Grains", "grains_from_scene", "step", "wrenches"]
