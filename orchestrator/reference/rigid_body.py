"""A rigid body made of SPH particles, free (Newton-Euler) or kinematic (prescribed motion), as numpy functions.

SI units: masses in kg, lengths in m, times in s, velocities in m/s, angular velocities in rad/s, inertia in kg m^2,
forces in N, torques in N m, angular momenta in kg m^2/s. Vectors are numpy arrays of 3 in the world frame unless
named body-frame; a quaternion is an array (w, x, y, z) of norm 1 that turns body-frame vectors into world ones.

The body from its particles (masses m_i, positions x_i, spacing dx; each particle a small cube of side dx):

    M = sum m_i,   X = sum m_i x_i / M,   r_i = x_i - X
    I = sum m_i (|r_i|^2 1 - r_i r_i^T) + sum m_i dx^2 / 6 1

The second sum is each particle's own inertia about its centre (a cube's m dx^2 / 6 about any axis): with it, a
lattice of n^3 particles that fills a cube has exactly the solid cube's inertia. The principal axes (eigenvectors of
I, moments ascending, each axis with its largest component positive, the set right-handed) are the body frame; the
orientation q0 turns them into the world axes, and the particles' body-frame offsets are R(q0)^T r_i.

The state is X, q, V and the world-frame angular momentum L about X, with omega = R diag(1/I_k) R^T L kept beside
it. L is the integration variable because a torque changes it in the world frame directly (dL/dt = T) and a free
rotation leaves it untouched, so a torque-free body keeps L to the last bit. One step of dt under a force F and a
torque T constant over the step is a kick-drift-kick leapfrog (velocity Verlet):

    V += F dt / (2 M),  L += T dt / 2                          (half kick)
    X += V dt;  q <- the free rotor's flow over dt              (drift)
    V += F dt / (2 M),  L += T dt / 2                          (half kick)

The free rotor's flow is the splitting of Dullweber, Leimkuhler and McLachlan (1997): H = sum_k pi_k^2 / (2 I_k),
pi = R^T L the body-frame angular momentum, is a sum of three terms whose flows are exact rotations about one body
axis, q <- q (cos(theta/2), sin(theta/2) e_k) with theta = pi_k h / I_k (pi_k is constant in that flow); composed
symmetrically, axes 1, 2, 3, 2, 1 with steps dt/2, dt/2, dt, dt/2, dt/2, the step is symplectic, time-reversible and
second order, conserves L exactly and the energy to O(dt^2) without drift. Each factor is a unit quaternion, so q
drifts from norm 1 by rounding alone; it is renormalised after each step, a change of order 1e-16 that moves no
result above rounding.

A kinematic body moves with a prescribed V and omega (world frame) and ignores forces:
X += V dt, q <- (cos(|omega| dt/2), sin(|omega| dt/2) omega/|omega|) q, exact for a constant omega.

Its particles sit at x_i = X + R r_i^body with the rigid velocity V + omega x (x_i - X); the force and torque on the
body from per-particle forces f_i are F = sum f_i and T = sum (x_i - X) x f_i.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from scipy.special import ellipk

from orchestrator.errors import OrchestratorError

#: The free rotor's sub-flows: (principal axis, fraction of dt), symmetric.
ROTOR_SPLITTING = ((0, 0.5), (1, 0.5), (2, 1.0), (1, 0.5), (0, 0.5))


@dataclass(frozen=True)
class Body:
    """Mass (kg) and principal moments of inertia about the centre of mass, ascending (kg m^2)."""

    mass: float
    moments: tuple[float, float, float]

    def __post_init__(self):
        if not (self.mass > 0.0 and all(m > 0.0 for m in self.moments)):
            raise OrchestratorError(f"rigid body: mass {self.mass} kg and moments {self.moments} kg m^2 must be > 0")


@dataclass(frozen=True)
class State:
    """Position X (m), orientation q (w, x, y, z), velocity V (m/s), world angular momentum L about X (kg m^2/s),
    world angular velocity omega (rad/s), and whether the motion is prescribed (kinematic)."""

    position: np.ndarray
    orientation: np.ndarray
    velocity: np.ndarray
    angular_momentum: np.ndarray
    angular_velocity: np.ndarray
    kinematic: bool = False


def quaternion_product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The Hamilton product a b of quaternions (w, x, y, z)."""
    return np.array([a[0] * b[0] - a[1:] @ b[1:], *(a[0] * b[1:] + b[0] * a[1:] + np.cross(a[1:], b[1:]))])


def rotation_matrix(q: np.ndarray) -> np.ndarray:
    """R(q) of a unit quaternion (w, x, y, z): world = R body."""
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def quaternion_from_matrix(r: np.ndarray) -> np.ndarray:
    """The unit quaternion (w >= 0) of a rotation matrix, from its largest diagonal combination (Shepperd 1978)."""
    candidates = [np.trace(r), r[0, 0], r[1, 1], r[2, 2]]
    k = int(np.argmax(candidates))
    if k == 0:
        s = 2.0 * math.sqrt(1.0 + np.trace(r))
        q = np.array([s / 4, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s])
    else:
        i, j, l = k - 1, k % 3, (k + 1) % 3
        s = 2.0 * math.sqrt(1.0 + r[i, i] - r[j, j] - r[l, l])
        q = np.empty(4)
        q[0], q[1 + i] = (r[l, j] - r[j, l]) / s, s / 4
        q[1 + j], q[1 + l] = (r[j, i] + r[i, j]) / s, (r[l, i] + r[i, l]) / s
    q /= np.linalg.norm(q)
    return -q if q[0] < 0 else q


def mass_properties(positions: np.ndarray, masses: np.ndarray, spacing: float) -> tuple[float, np.ndarray, np.ndarray]:
    """Total mass (kg), centre of mass (m) and the inertia tensor about it (kg m^2, world axes) of particles at
    positions (n, 3) (m) with masses (n,) (kg), each a cube of side `spacing` (m) with its own m dx^2 / 6."""
    mass = float(np.sum(masses))
    centre = masses @ positions / mass
    r = positions - centre
    inertia = (np.sum(masses * np.einsum("ij,ij->i", r, r)) + mass * spacing ** 2 / 6) * np.eye(3)
    return mass, centre, inertia - np.einsum("i,ij,ik->jk", masses, r, r)


def principal_frame(inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments (ascending, kg m^2) and the orientation (w, x, y, z) whose body axes are the principal
    axes: each axis with its largest-magnitude component positive, the third flipped to make the frame right-handed."""
    moments, axes = np.linalg.eigh(inertia)
    for k in range(3):
        if axes[np.argmax(np.abs(axes[:, k])), k] < 0:
            axes[:, k] = -axes[:, k]
    if np.linalg.det(axes) < 0:
        axes[:, 2] = -axes[:, 2]
    return moments, quaternion_from_matrix(axes)


def body_from_particles(positions: np.ndarray, masses: np.ndarray, spacing: float) -> tuple[Body, State, np.ndarray]:
    """The body (mass, principal moments), its state at rest and the particles' body-frame offsets (n, 3) (m)."""
    mass, centre, inertia = mass_properties(positions, masses, spacing)
    moments, q = principal_frame(inertia)
    offsets = (positions - centre) @ rotation_matrix(q)
    zero = np.zeros(3)
    return Body(mass, tuple(float(m) for m in moments)), State(centre, q, zero, zero, zero), offsets


def angular_velocity(body: Body, q: np.ndarray, angular_momentum: np.ndarray) -> np.ndarray:
    """omega = R diag(1 / I_k) R^T L (rad/s) for the world angular momentum L (kg m^2/s)."""
    r = rotation_matrix(q)
    return r @ ((r.T @ angular_momentum) / np.asarray(body.moments))


def with_velocities(body: Body, state: State, velocity, omega, kinematic: bool | None = None) -> State:
    """The state moving with V (m/s) and the world angular velocity omega (rad/s); L follows from omega."""
    r = rotation_matrix(state.orientation)
    omega = np.asarray(omega, float)
    momentum = r @ (np.asarray(body.moments) * (r.T @ omega))
    return dataclasses.replace(state, velocity=np.asarray(velocity, float), angular_momentum=momentum,
                               angular_velocity=omega,
                               kinematic=state.kinematic if kinematic is None else kinematic)


def free_rotor(body: Body, q: np.ndarray, angular_momentum: np.ndarray, dt: float) -> np.ndarray:
    """The orientation after dt (s) of a torque-free body with the world angular momentum L: the symmetric
    splitting of Dullweber, Leimkuhler and McLachlan (1997) into exact rotations about single body axes."""
    for axis, fraction in ROTOR_SPLITTING:
        component = (rotation_matrix(q).T @ angular_momentum)[axis]
        half_angle = 0.5 * component * fraction * dt / body.moments[axis]
        factor = np.zeros(4)
        factor[0], factor[1 + axis] = math.cos(half_angle), math.sin(half_angle)
        q = quaternion_product(q, factor)
    return q / np.linalg.norm(q)


def step(body: Body, state: State, force, torque, dt: float) -> State:
    """One kick-drift-kick step of dt (s) under a force (N) and a torque about X (N m), both world frame and constant
    over the step; a kinematic body moves with its prescribed V and omega and ignores both."""
    if state.kinematic:
        omega = state.angular_velocity
        angle = float(np.linalg.norm(omega)) * dt
        turn = np.array([1.0, 0.0, 0.0, 0.0])
        if angle > 0.0:
            turn = np.array([math.cos(angle / 2), *(math.sin(angle / 2) * omega * dt / angle)])
        q = quaternion_product(turn, state.orientation)
        moved = dataclasses.replace(state, position=state.position + state.velocity * dt,
                                    orientation=q / np.linalg.norm(q))
        return with_velocities(body, moved, state.velocity, omega)
    force, torque = np.asarray(force, float), np.asarray(torque, float)
    velocity = state.velocity + 0.5 * dt / body.mass * force
    momentum = state.angular_momentum + 0.5 * dt * torque
    position = state.position + velocity * dt
    q = free_rotor(body, state.orientation, momentum, dt)
    velocity = velocity + 0.5 * dt / body.mass * force
    momentum = momentum + 0.5 * dt * torque
    return State(position, q, velocity, momentum, angular_velocity(body, q, momentum))


def kinetic_energy(body: Body, state: State) -> float:
    """M |V|^2 / 2 + sum_k pi_k^2 / (2 I_k), J, with pi = R^T L the body-frame angular momentum."""
    pi = rotation_matrix(state.orientation).T @ state.angular_momentum
    return 0.5 * body.mass * float(state.velocity @ state.velocity) + 0.5 * float(np.sum(pi ** 2 / body.moments))


def particle_positions(state: State, offsets: np.ndarray) -> np.ndarray:
    """x_i = X + R r_i (m) for body-frame offsets (n, 3) (m)."""
    return state.position + offsets @ rotation_matrix(state.orientation).T


def rigid_velocity(state: State, points: np.ndarray) -> np.ndarray:
    """V + omega x (x - X) (m/s) at points (n, 3) or (3,) (m)."""
    return state.velocity + np.cross(state.angular_velocity, np.asarray(points) - state.position)


def wrench(state: State, points: np.ndarray, forces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The force (N) and the torque about X (N m) of per-particle forces (n, 3) (N) at points (n, 3) (m)."""
    return forces.sum(axis=0), np.cross(points - state.position, forces).sum(axis=0)


def intermediate_axis_half_period(moments, energy: float, momentum_squared: float) -> float:
    """The time (s) between successive sign changes of the body-frame angular velocity about the intermediate axis
    of a torque-free body with moments I1 < I2 < I3 (kg m^2), rotational energy E (J) and |L|^2 (kg^2 m^4/s^2):
    2 K(k) / lambda, from Euler's equations solved by Jacobi's elliptic functions (Landau and Lifshitz, section 37).
    For L^2 > 2 E I2:  lambda^2 = (I3 - I2)(L^2 - 2 E I1) / (I1 I2 I3),
                       k^2 = (I2 - I1)(2 E I3 - L^2) / ((I3 - I2)(L^2 - 2 E I1));  I1 and I3 swap otherwise."""
    i1, i2, i3 = moments
    if not i1 < i2 < i3:
        raise OrchestratorError(f"moments {moments} kg m^2 must be distinct and ascending")
    if momentum_squared < 2 * energy * i2:
        i1, i3 = i3, i1
    rate = math.sqrt((i3 - i2) * (momentum_squared - 2 * energy * i1) / (i1 * i2 * i3))
    modulus_squared = ((i2 - i1) * (2 * energy * i3 - momentum_squared)
                       / ((i3 - i2) * (momentum_squared - 2 * energy * i1)))
    return 2 * float(ellipk(modulus_squared)) / rate


def cube_inertia(mass: float, side: float) -> float:
    """M a^2 / 6 (kg m^2): a solid cube's moment about any axis through its centre."""
    return mass * side ** 2 / 6


def sphere_inertia(mass: float, radius: float) -> float:
    """2 M R^2 / 5 (kg m^2): a solid sphere's moment about any axis through its centre."""
    return 0.4 * mass * radius ** 2
