"""The numpy rigid body (orchestrator.reference.rigid_body) against closed forms: the inertia of particle lattices
against the solid cube and sphere, a torque-free top (angular momentum, energy at dt and dt/2, the intermediate
axis's flip time from Jacobi's elliptic functions, a symmetric top's precession), constant torque and force, a
kinematic body, the wrench of particle forces; and the expected values written into the C++ test
engines/sph/tests/test_rigid_body.cpp recomputed here, so the two cannot drift."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from paths import REPO

from orchestrator.errors import OrchestratorError
from orchestrator.reference import rigid_body as rb

CPP_TEST = REPO / "engines/sph/tests/test_rigid_body.cpp"
GLASS = 2500.0  # kg/m^3
ZERO = np.zeros(3)


def _lattice(cells: int, spacing: float) -> np.ndarray:
    """Cell centres (m) of a cubic lattice of cells^3 cells of side `spacing` (m) centred on the origin."""
    g = (np.arange(cells) - 0.5 * (cells - 1)) * spacing
    return np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3)


def _at_rest(q=(1.0, 0.0, 0.0, 0.0)) -> rb.State:
    """A state at rest at the origin with orientation q (w, x, y, z)."""
    return rb.State(ZERO, np.asarray(q, float), ZERO, ZERO, ZERO)


def test_a_cube_lattice_has_the_solid_cubes_inertia():
    spacing, cells = 1e-5, 6
    points = _lattice(cells, spacing) + np.array([3e-4, -1e-4, 2e-4])
    masses = np.full(len(points), GLASS * spacing ** 3)
    mass, centre, inertia = rb.mass_properties(points, masses, spacing)
    expected = rb.cube_inertia(mass, cells * spacing) * np.eye(3)
    assert np.max(np.abs(inertia - expected)) <= 1e-13 * expected[0, 0]
    assert centre == pytest.approx([3e-4, -1e-4, 2e-4], rel=1e-13)


@pytest.mark.parametrize("cells_per_radius", [5, 10, 20])
def test_a_sphere_lattice_has_the_solid_spheres_inertia_to_the_lattice_error(cells_per_radius):
    spacing = 1e-5
    points = _lattice(2 * cells_per_radius, spacing)
    points = points[np.linalg.norm(points, axis=1) < cells_per_radius * spacing]
    mass, _, inertia = rb.mass_properties(points, np.full(len(points), GLASS * spacing ** 3), spacing)
    radius = (len(points) * spacing ** 3 * 3 / (4 * math.pi)) ** (1 / 3)  # the volume-equivalent radius
    error = inertia[0, 0] / rb.sphere_inertia(mass, radius) - 1
    print(f"R / dx = {cells_per_radius}: I / (2/5 M R^2) - 1 = {error:.3e}, "
          f"x (R/dx)^2 = {error * cells_per_radius ** 2:.3f}")
    assert 0 < error < 0.5 / cells_per_radius ** 2
    assert np.allclose(np.diag(inertia), inertia[0, 0], rtol=1e-13, atol=0)
    assert np.max(np.abs(inertia - np.diag(np.diag(inertia)))) < 1e-13 * inertia[0, 0]


def test_the_inertia_is_the_sum_and_the_principal_frame_carries_the_particles():
    positions, masses, spacing = _fixed_scene()
    mass, centre, inertia = rb.mass_properties(positions, masses, spacing)
    about_origin = sum(m * (x @ x * np.eye(3) - np.outer(x, x)) for m, x in zip(masses, positions))
    parallel_axis = mass * (centre @ centre * np.eye(3) - np.outer(centre, centre))
    direct = about_origin - parallel_axis + mass * spacing ** 2 / 6 * np.eye(3)
    assert np.max(np.abs(inertia - direct)) < 1e-10 * np.max(np.abs(inertia))  # cancellation in the parallel axis
    body, state, offsets = rb.body_from_particles(positions, masses, spacing)
    r = rb.rotation_matrix(state.orientation)
    assert np.allclose(r.T @ inertia @ r, np.diag(body.moments), rtol=0, atol=1e-13 * body.moments[2])
    assert np.max(np.abs(rb.particle_positions(state, offsets) - positions)) < 1e-15
    assert body.moments[0] < body.moments[1] < body.moments[2]


def test_a_rotated_box_has_the_boxs_moments_and_axes():
    spacing, sides = 1e-5, np.array([6, 4, 2])
    grid = [(np.arange(n) - 0.5 * (n - 1)) * spacing for n in sides]
    points = np.stack(np.meshgrid(*grid, indexing="ij"), -1).reshape(-1, 3)
    turn = rb.quaternion_from_matrix(rb.rotation_matrix(np.array([0.9, 0.1, -0.3, 0.2]) / math.sqrt(0.95)))
    points = points @ rb.rotation_matrix(turn).T
    body, state, _ = rb.body_from_particles(points, np.full(len(points), GLASS * spacing ** 3), spacing)
    a, b, c = sides * spacing
    expected = body.mass / 12 * np.array([a * a + b * b, a * a + c * c, b * b + c * c])[::-1]
    assert np.allclose(body.moments, np.sort(expected), rtol=1e-12, atol=0)
    axes = np.abs(rb.rotation_matrix(state.orientation).T @ rb.rotation_matrix(turn))
    assert np.allclose(axes, np.eye(3), atol=1e-12)  # longest side about the smallest moment, and so on


def _top_run(body: rb.Body, omega_body, dt: float, steps: int):
    """Energy error (max relative), |pi| error, and the times (s) the body-frame omega_2 changes sign."""
    state = rb.with_velocities(body, _at_rest(), ZERO, np.asarray(omega_body, float))
    energy, momentum = rb.kinetic_energy(body, state), np.linalg.norm(state.angular_momentum)
    worst_energy = worst_momentum = 0.0
    previous, crossings = omega_body[1], []
    for k in range(1, steps + 1):
        state = rb.step(body, state, ZERO, ZERO, dt)
        pi = rb.rotation_matrix(state.orientation).T @ state.angular_momentum
        worst_energy = max(worst_energy, abs(rb.kinetic_energy(body, state) / energy - 1))
        worst_momentum = max(worst_momentum, abs(np.linalg.norm(pi) / momentum - 1))
        omega_2 = pi[1] / body.moments[1]
        if omega_2 * previous < 0:
            crossings.append(dt * (k - omega_2 / (omega_2 - previous)))
        previous = omega_2
    return worst_energy, worst_momentum, np.array(crossings), energy, momentum


def test_the_asymmetric_top_keeps_momentum_energy_to_second_order_and_flips_on_time():
    body, omega = rb.Body(1.5e-8, (1e-16, 2e-16, 3e-16)), (500.0, 1e4, 500.0)  # a glass grain spun near axis 2
    dt = 2e-6
    coarse, momentum_error, crossings, energy, momentum = _top_run(body, omega, dt, 2000)
    fine = _top_run(body, omega, dt / 2, 4000)[0]
    half_period = rb.intermediate_axis_half_period(body.moments, energy, momentum ** 2)
    flips = np.diff(crossings)
    print(f"energy error {coarse:.3e} at dt, {fine:.3e} at dt/2 (ratio {coarse / fine:.3f}); |L| {momentum_error:.1e};"
          f" flip {flips} s, closed form {half_period:.6e} s")
    assert momentum_error < 1e-12
    assert coarse / fine == pytest.approx(4.0, rel=0.02) and coarse < 1e-5
    assert len(flips) >= 1 and np.all(np.abs(flips / half_period - 1) < 0.01)


def test_the_symmetric_top_precesses_at_l_over_the_transverse_moment():
    body, dt, steps = rb.Body(1.0, (2.0, 2.0, 3.0)), 1e-3, 4000
    state = rb.with_velocities(body, _at_rest(), ZERO, np.array([0.3, 0.0, 1.0]))
    momentum = state.angular_momentum
    direction = momentum / np.linalg.norm(momentum)
    first = np.array([1.0, 0.0, 0.0]) - direction[0] * direction
    first /= np.linalg.norm(first)
    second = np.cross(direction, first)
    angles = []
    for _ in range(steps):
        state = rb.step(body, state, ZERO, ZERO, dt)
        axis = rb.rotation_matrix(state.orientation)[:, 2]
        angles.append(math.atan2(axis @ second, axis @ first))
    rate = np.polyfit(dt * np.arange(1, steps + 1), np.unwrap(angles), 1)[0]
    expected = np.linalg.norm(momentum) / body.moments[0]
    print(f"precession {rate:.8f} rad/s, L / I_1 = {expected:.8f} rad/s")
    assert abs(rate) == pytest.approx(expected, rel=1e-4)


def test_a_constant_torque_about_a_principal_axis_and_a_constant_force_are_exact():
    body, dt, steps = rb.Body(2.0, (1.0, 2.0, 3.0)), 1e-3, 1000
    q = rb.quaternion_from_matrix(rb.rotation_matrix(np.array([0.8, 0.2, 0.4, -0.4])))
    axis = rb.rotation_matrix(q)[:, 1]
    force, torque = np.array([0.5, -1.0, 2.0]), 3.0 * axis
    start, v0 = np.array([1.0, 2.0, 3.0]), np.array([0.1, 0.0, -0.2])
    state = rb.with_velocities(body, rb.State(start, q, ZERO, ZERO, ZERO), v0, ZERO)
    for _ in range(steps):
        state = rb.step(body, state, force, torque, dt)
    t = steps * dt
    assert np.allclose(state.angular_velocity, torque * t / body.moments[1], rtol=0, atol=1e-12 * 3.0 * t / 2.0)
    assert np.allclose(state.position, start + v0 * t + force * t * t / (2 * body.mass), rtol=1e-12, atol=0)


def test_a_kinematic_body_follows_its_prescription_and_ignores_forces():
    positions, masses, spacing = _fixed_scene()
    body, state, offsets = rb.body_from_particles(positions, masses, spacing)
    velocity, omega, dt, steps = np.array([2.0, -1.0, 0.5]), np.array([300.0, -100.0, 700.0]), 1e-5, 1000
    state = rb.with_velocities(body, state, velocity, omega, kinematic=True)
    start, q0 = state.position, state.orientation
    for _ in range(steps):
        state = rb.step(body, state, np.array([1.0, 2.0, 3.0]), np.array([4.0, 5.0, 6.0]), dt)
    t, angle = steps * dt, np.linalg.norm(omega) * steps * dt
    turn = np.array([math.cos(angle / 2), *(math.sin(angle / 2) * omega / np.linalg.norm(omega))])
    assert np.allclose(state.position, start + velocity * t, rtol=1e-12, atol=0)
    assert np.allclose(state.orientation, rb.quaternion_product(turn, q0), rtol=0, atol=1e-12)
    assert np.array_equal(state.velocity, velocity) and np.array_equal(state.angular_velocity, omega)
    x = rb.particle_positions(state, offsets)
    assert np.allclose(rb.rigid_velocity(state, x), velocity + np.cross(omega, x - state.position), rtol=1e-15)
    gaps = np.linalg.norm(x[:, None] - x[None], axis=2) - np.linalg.norm(positions[:, None] - positions[None], axis=2)
    assert np.max(np.abs(gaps)) < 1e-15


def test_the_wrench_of_gravity_and_of_a_couple():
    positions, masses, _ = _fixed_scene()
    state = rb.State(masses @ positions / masses.sum(), np.array([1.0, 0.0, 0.0, 0.0]), ZERO, ZERO, ZERO)
    force, torque = rb.wrench(state, positions, np.outer(masses, [0.0, 0.0, -9.81]))
    assert force == pytest.approx([0.0, 0.0, -9.81 * masses.sum()], rel=1e-14)
    assert np.max(np.abs(torque)) < 1e-14 * 9.81 * masses.sum() * 1e-3  # gravity has no torque about the centre
    forces = np.zeros_like(positions)
    forces[0], forces[-1] = [0.0, 1.0, 0.0], [0.0, -1.0, 0.0]
    force, torque = rb.wrench(state, positions, forces)
    assert np.array_equal(force, ZERO)
    assert torque == pytest.approx(np.cross(positions[0] - positions[-1], [0.0, 1.0, 0.0]), rel=1e-12)


def test_bad_bodies_are_refused():
    with pytest.raises(OrchestratorError, match="mass"):
        rb.Body(0.0, (1.0, 1.0, 1.0))
    with pytest.raises(OrchestratorError, match="ascending"):
        rb.intermediate_axis_half_period((2.0, 1.0, 3.0), 1.0, 1.0)


def _fixed_scene() -> tuple[np.ndarray, np.ndarray, float]:
    """The C++ test's fixed_scene: a jittered 5 x 4 x 3 glass lattice of spacing 100 um with uneven masses."""
    spacing = 1e-4
    cells = np.array([(a, b, c) for a in range(5) for b in range(4) for c in range(3)], float)
    i = np.arange(len(cells))
    jitter = 0.1 * np.stack([np.sin(i), np.cos(2.0 * i), np.sin(3.0 * i + 1.0)], axis=1)
    positions = spacing * (cells + jitter) + np.array([1e-3, 2e-3, -5e-4])
    return positions, GLASS * spacing ** 3 * (1.0 + 0.2 * np.sin(0.7 * i)), spacing


def _cross_check_values() -> dict[str, float]:
    """The fixed scene under gravity, a linear spring to the origin and a drag on every particle (forces at the
    step's start), 200 steps of 1e-5 s from V0 and omega0: the quantities the C++ test holds as constants."""
    positions, masses, spacing = _fixed_scene()
    body, state, offsets = rb.body_from_particles(positions, masses, spacing)
    state = rb.with_velocities(body, state, np.array([1.5, -0.5, 0.25]), np.array([300.0, -200.0, 500.0]))
    for _ in range(200):
        x = rb.particle_positions(state, offsets)
        forces = masses[:, None] * ([0.0, 0.0, -9.81] - 50.0 * rb.rigid_velocity(state, x)) - 2.5e-5 * x
        state = rb.step(body, state, *rb.wrench(state, x, forces), 1e-5)
    x = rb.particle_positions(state, offsets)
    values = {"kMass": body.mass, "kMoment1": body.moments[0], "kMoment2": body.moments[1],
              "kMoment3": body.moments[2], "kEnergy": rb.kinetic_energy(body, state)}
    for name, vector in (("Position", state.position), ("Velocity", state.velocity),
                         ("Momentum", state.angular_momentum), ("Omega", state.angular_velocity),
                         ("FirstParticle", x[0]), ("LastParticle", x[-1])):
        values |= {f"k{name}{axis}": float(v) for axis, v in zip("XYZ", vector)}
    return values | {f"kQuat{c}": float(v) for c, v in zip("WXYZ", state.orientation)}


def test_the_cpp_test_holds_the_reference_values():
    constants = {name: float(value) for name, value in
                 re.findall(r"constexpr double (k\w+) = ([-+0-9.eE]+);", CPP_TEST.read_text())}
    values = _cross_check_values()
    assert set(values) <= set(constants), f"missing in {CPP_TEST.name}: {sorted(set(values) - set(constants))}"
    for name, value in values.items():
        assert constants[name] == pytest.approx(value, rel=1e-12), name
