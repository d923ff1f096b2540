"""The reference DEM on small scenes: triangle walls, many spheres, statics,
conservation, and the messages for bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orchestrator.reference import closed_form, contact
from orchestrator.reference.dem import MAX_SPHERES, DemBlewUp, Material, Plane, TriangleMesh, simulate
from orchestrator.reference.dem_geometry import EDGE, FACE, VERTEX, closest_points_on_triangles

CERAMIC = Material(77e9, 0.19, 2656.0)
STEEL = Material(210e9, 0.30, 7610.0)
PAIRS = {(0, 0): (0.86, 0.34), (0, 1): (0.68, 0.28)}
RADIUS = 3.27e-3
MASS = CERAMIC.density * 4 / 3 * math.pi * RADIUS**3
#: Two triangles making a 10 cm square plate at z = 0, split along its diagonal x = y.
PLATE = TriangleMesh(vertices=np.array([[-0.05, -0.05, 0], [0.05, -0.05, 0], [0.05, 0.05, 0], [-0.05, 0.05, 0]]),
                     faces=np.array([[0, 1, 2], [0, 2, 3]]), material=1, name="plate")


def impact_time_step(speed=0.5):
    e_eq = contact.effective_modulus(77e9, 0.19, 210e9, 0.3)
    return closed_form.hertz_contact_duration(MASS, RADIUS, e_eq, speed) / 400


def test_closest_points_on_a_triangle_by_feature():
    a, b, c = np.array([[0.0, 0, 0]]), np.array([[1.0, 0, 0]]), np.array([[0.0, 1, 0]])
    points = np.array([[0.2, 0.2, 1.0], [0.5, -1.0, 0.3], [-1.0, -1.0, 0.0], [2.0, 2.0, 0.0]])
    closest, feature = closest_points_on_triangles(points, *(np.repeat(v, 4, axis=0) for v in (a, b, c)))
    assert closest == pytest.approx(np.array([[0.2, 0.2, 0], [0.5, 0, 0], [0, 0, 0], [0.5, 0.5, 0]]))
    assert feature.tolist() == [FACE, EDGE, VERTEX, EDGE]


@pytest.mark.parametrize("xy", [(0.01, -0.02), (0.0, 0.0), (0.01, 0.0101), (0.05, 0.0), (0.05, 0.05)])
def test_a_sphere_hits_a_flat_mesh_once_and_like_a_plane(xy):
    # on a face, on the shared diagonal, next to it, on the outer edge, on a corner
    dt = impact_time_step()
    common = dict(positions=[[xy[0], xy[1], RADIUS * (1 + 1e-9)]], velocities=[[0, 0, -0.5]], radii=[RADIUS],
                  sphere_material=[0], materials=[CERAMIC, STEEL], pair_table=PAIRS, gravity=(0, 0, 0), dt=dt,
                  t_end=500 * dt, record_every=100 * dt)
    on_mesh = simulate(meshes=[PLATE], **common)
    on_plane = simulate(planes=[Plane((0, 0, 0), (0, 0, 1), 1)], **common)
    assert len(on_mesh["contacts"]["start_time"]) == 1
    assert on_mesh["contacts"]["peak_normal_force"] == pytest.approx(
        on_plane["contacts"]["peak_normal_force"], rel=1e-9)
    assert on_mesh["velocities"][-1] == pytest.approx(on_plane["velocities"][-1], rel=1e-9, abs=1e-12)
    assert on_mesh["wall_names"] == ["plate"]


def test_a_sphere_on_a_convex_ridge_touches_it_once():
    ridge = TriangleMesh(vertices=np.array([[-0.05, -0.05, -0.01], [0, -0.05, 0], [0, 0.05, 0], [-0.05, 0.05, -0.01],
                                            [0.05, -0.05, -0.01], [0.05, 0.05, -0.01]]),
                         faces=np.array([[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]]), material=1)
    dt = impact_time_step()
    run = simulate([[0, 0, RADIUS * (1 + 1e-9)]], [[0, 0, -0.5]], [RADIUS], [0], [CERAMIC, STEEL], PAIRS,
                   meshes=[ridge], gravity=(0, 0, 0), dt=dt, t_end=500 * dt, record_every=100 * dt)
    assert len(run["contacts"]["start_time"]) == 1
    # edges count as flats (R_eq = R_sphere); eq. 10's alpha for 0.68 rebounds at 0.7007 (no tension)
    assert run["velocities"][-1, 0] == pytest.approx([0, 0, 0.7007 * 0.5], abs=2e-3)


def test_a_sphere_settles_on_the_floor_under_its_weight():
    # released at 1.5 times the static overlap it rings down (damping ratio ~0.1, period
    # 155 us) to Hertz's static overlap (m g / k_n)^(2/3), loading the floor with m g
    e_eq = contact.effective_modulus(77e9, 0.19, 210e9, 0.3)
    static_overlap = (MASS * 9.81 / contact.hertz_stiffness(e_eq, RADIUS)) ** (2 / 3)
    run = simulate([[0, 0, RADIUS - 1.5 * static_overlap]], [[0, 0, 0]], [RADIUS], [0], [CERAMIC, STEEL], PAIRS,
                   planes=[Plane((0, 0, 0), (0, 0, 1), 1, name="floor")], dt=1e-6, t_end=3e-3, record_every=5e-4)
    assert run["wall_force"][-1, 0] == pytest.approx([0, 0, -MASS * 9.81], rel=1e-3, abs=1e-9)
    assert run["positions"][-1, 0, 2] == pytest.approx(RADIUS - static_overlap, abs=1e-3 * static_overlap)
    assert run["contacts"]["end_time"] == pytest.approx([np.nan], nan_ok=True)  # one contact, still open
    assert run["wall_names"] == ["floor"]


def test_colliding_spheres_keep_momentum_and_angular_momentum():
    # 27 spheres on a loose lattice, thrown at each other with spin: forces are pairwise
    # opposite and act at one contact point, so both momenta stay to round-off
    rng = np.random.default_rng(7)
    grid = np.stack(np.meshgrid(*[np.arange(3)] * 3, indexing="ij"), -1).reshape(-1, 3) - 1.0
    positions = grid * (2 * RADIUS + 2e-4)
    count = len(positions)
    velocities = -positions * 300.0 + rng.normal(0, 0.3, (count, 3))
    spins = rng.normal(0, 100.0, (count, 3))
    run = simulate(positions, velocities, np.full(count, RADIUS), np.zeros(count, int), [CERAMIC],
                   {(0, 0): PAIRS[(0, 0)]}, angular_velocities=spins, gravity=(0, 0, 0), dt=5e-7, t_end=1e-3,
                   record_every=1e-3)
    assert len(run["contacts"]["start_time"]) > count  # it did collide
    inertia = 0.4 * MASS * RADIUS**2

    def momenta(k):
        x, v, w = run["positions"][k], run["velocities"][k], run["angular_velocities"][k]
        return MASS * v.sum(axis=0), (MASS * np.cross(x, v) + inertia * w).sum(axis=0)

    (p0, l0), (p1, l1) = momenta(0), momenta(-1)
    momentum_scale = MASS * np.abs(velocities).sum()
    angular_scale = MASS * np.abs(np.cross(positions, velocities)).sum() + inertia * np.abs(spins).sum()
    assert p1 == pytest.approx(p0, abs=1e-12 * momentum_scale)
    assert l1 == pytest.approx(l0, abs=1e-12 * angular_scale)
    assert run["kinetic_energy"][-1] < 0.9 * run["kinetic_energy"][0]


def test_too_many_spheres_is_refused_with_the_limit_named():
    count = MAX_SPHERES + 1
    with pytest.raises(ValueError, match=f"at most {MAX_SPHERES} spheres.*{count}"):
        simulate(np.zeros((count, 3)), np.zeros((count, 3)), np.full(count, RADIUS), np.zeros(count, int), [CERAMIC],
                 {(0, 0): (0.9, 0.3)}, dt=1e-6, t_end=1e-5, record_every=1e-6)


@pytest.mark.parametrize("change, message", [
    (dict(pair_table={(0, 0): (0.86, 0.34)}), r"no \(e_n, mu\) for material pairs \[\(0, 1\)\]"),
    (dict(radii=[-1.0]), "radius must be a finite number > 0"),
    (dict(velocities=[[0, 0]]), r"velocities must be a finite \(1, 3\) array"),
    (dict(sphere_material=[5]), "material index is outside 0..1"),
    (dict(pair_table={(0, 1): (1.5, 0.3)}), "need 0 < e_n <= 1"),
    (dict(pair_table={(0, 1): (0.5, 0.3), (0, 2): (0.5, 0.3)}), r"material pair \(0, 2\); materials are 0..1"),
    (dict(damping="tsuji"), "damping must be 'eq10' or 'exact'"),
    (dict(planes=[Plane((0, 0, 0), (0, 0, 0), 1)]), "plane 0: point and normal must be 3-vectors"),
    (dict(meshes=[TriangleMesh(PLATE.vertices, np.array([[0, 1, 4]]), 1, name="lid")]),
     r"mesh lid: a face names a vertex outside 0..3"),
    (dict(dt=0.0), "must be > 0"),
])
def test_bad_input_gets_a_clear_message(change, message):
    arguments = dict(positions=[[0, 0, 0.01]], velocities=[[0, 0, 0]], radii=[RADIUS], sphere_material=[0],
                     materials=[CERAMIC, STEEL], pair_table=PAIRS, planes=[Plane((0, 0, 0), (0, 0, 1), 1)],
                     dt=1e-6, t_end=1e-5, record_every=1e-6)
    arguments.update(change)
    with pytest.raises(ValueError, match=message):
        simulate(**arguments)


def test_a_blow_up_is_reported_with_the_step_and_keeps_what_was_recorded():
    with pytest.raises(DemBlewUp, match="reduce dt") as blown:
        simulate([[0, 0, 2 * RADIUS]], [[0, 0, -50.0]], [RADIUS], [0], [CERAMIC, STEEL], PAIRS,
                 planes=[Plane((0, 0, 0), (0, 0, 1), 1)], gravity=(0, 0, 0), dt=5e-5, t_end=1e-3, record_every=1e-4)
    assert blown.value.partial["time"][0] == 0.0
    assert blown.value.partial["steps"] >= 1


def test_spheres_that_start_deep_in_a_wall_are_refused():
    with pytest.raises(ValueError, match="sphere 0 starts overlapping a sphere or wall"):
        simulate([[0, 0, 0.5 * RADIUS]], [[0, 0, 0]], [RADIUS], [0], [CERAMIC, STEEL], PAIRS,
                 planes=[Plane((0, 0, 0), (0, 0, 1), 1)], dt=1e-6, t_end=1e-5, record_every=1e-6)
