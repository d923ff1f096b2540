"""The ejector drill's boundary-particle walls (kinds/ejector_drill/walls.py) on a coarse flow-exit scene
(dx = 0.5 mm, the inlet 5 mm up the gap): every particle lies inside a solid (checked with trimesh on the cut
meshes) and within 2h of the wetted regions; every wetted lattice site has all the solid sites of its kernel
support as boundary particles; the wall points lie on the meshes' surface and are the nearest point of it; the
initial densities are rho0 less the empty sites' kernel share."""

import math
from functools import lru_cache

import numpy as np
import pytest

from orchestrator.case.loader import load_case
from orchestrator.drill.regions import Ring
from orchestrator.drill.walls import initial_densities, scene_lattice
from orchestrator.kinds.ejector_drill.build import inlet_buffer_points, prefill_points, wall_meshes
from orchestrator.kinds.ejector_drill.layout import drill_layout
from orchestrator.kinds.ejector_drill.walls import drill_boundary_particles, solid_masks
from orchestrator.reference.sph import kernel_value
from paths import CASES

CASE = CASES / "ejector_drill_canini.toml"
#: The meshes' sides: the 96-gon of the solids of revolution lies 15 mm x (1 - cos(pi / 96)) = 8 um inside the
#: circle at the bore, the holes' 24-gon 2 mm x (1 - cos(pi / 24)) = 17 um inside theirs.
MESH_TOLERANCE = 20e-6


@lru_cache(maxsize=1)
def _scene(*overrides):
    case = load_case(CASE, preset="flow_exit_quick", overrides=["numerics.dx=0.5e-3", "numerics.h_over_dx=1.2",
                                                                "scene.inlet_distance=5e-3",
                                                                "scene.prefill=1e-3", *overrides]).model
    layout = drill_layout(case)
    return case, layout, drill_boundary_particles(case, layout), wall_meshes(case, layout)


def _winding(mesh, points):
    """Generalised winding number of each point (n, 3) m about a closed mesh (1 inside, 0 outside; Van Oosterom &
    Strackee's solid angles; no spatial index needed)."""
    tri = np.asarray(mesh.triangles)
    out = np.zeros(len(points))
    for i, p in enumerate(points):
        a, b, c = (tri[:, k] - p for k in range(3))
        la, lb, lc = (np.linalg.norm(v, axis=1) for v in (a, b, c))
        det = np.einsum("ij,ij->i", a, np.cross(b, c))
        div = la * lb * lc + np.einsum("ij,ij->i", a, b) * lc + np.einsum("ij,ij->i", a, c) * lb \
            + np.einsum("ij,ij->i", b, c) * la
        out[i] = np.sum(2.0 * np.arctan2(det, div)) / (4.0 * math.pi)
    return out


def _closest_on_triangles(tri, p):
    """The nearest point (m, 3) of each triangle tri (m, 3, 3) to the point p (3,) (Ericson, Real-Time Collision
    Detection, 5.1.5: the Voronoi regions of the vertices, edges and face)."""
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    ab, ac, ap = b - a, c - a, p - a
    dot = lambda u, v: np.einsum("ij,ij->i", u, v)  # noqa: E731
    d1, d2 = dot(ab, ap), dot(ac, ap)
    bp, cp = p - b, p - c
    d3, d4, d5, d6 = dot(ab, bp), dot(ac, bp), dot(ab, cp), dot(ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    tiny = 1e-300
    denom = va + vb + vc
    v, w = vb / np.where(np.abs(denom) > tiny, denom, tiny), vc / np.where(np.abs(denom) > tiny, denom, tiny)
    out = a + ab * v[:, None] + ac * w[:, None]  # the face
    cases = [
        ((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0),
         b + (c - b) * ((d4 - d3) / np.maximum((d4 - d3) + (d5 - d6), tiny))[:, None]),  # edge bc
        ((vb <= 0) & (d2 >= 0) & (d6 <= 0), a + ac * (d2 / np.maximum(d2 - d6, tiny))[:, None]),  # edge ac
        ((vc <= 0) & (d1 >= 0) & (d3 <= 0), a + ab * (d1 / np.maximum(d1 - d3, tiny))[:, None]),  # edge ab
        ((d6 >= 0) & (d5 <= d6), c), ((d3 >= 0) & (d4 <= d3), b), ((d1 <= 0) & (d2 <= 0), a),  # vertices
    ]
    for mask, value in cases:  # the last that applies wins: vertices before edges before the face
        out = np.where(mask[:, None], value, out)
    return out


def _closest(mesh, points):
    """Each point's nearest point (n, 3) m of the mesh's surface and its distance (brute force over the faces)."""
    tri = np.asarray(mesh.triangles, dtype=float)
    near = np.empty_like(points)
    for i, p in enumerate(points):
        candidates = _closest_on_triangles(tri, p)
        near[i] = candidates[np.argmin(np.linalg.norm(candidates - p, axis=1))]
    return near, np.linalg.norm(near - points, axis=1)


def _open_tops(layout):
    """z of the wetted rings' ends that are open boundaries' buffer ends (no wall there), m."""
    return [w.z_hi for w, r in zip(layout.wetted, layout.regions) if isinstance(w, Ring) and w.z_hi != r.z_hi]


def test_boundary_particles_lie_in_the_solids_within_the_support():
    case, layout, walls, meshes = _scene()
    h = case.numerics.h
    assert walls.n > 10_000
    assert not layout.wetted_contains(walls.positions).any()
    d = walls.distances()
    assert d.max() <= 2 * h * (1 + 1e-12) and d.min() >= 0.0
    far = d > MESH_TOLERANCE  # the particles a 96-gon could leave outside its solid
    rng = np.random.default_rng(1)
    for k, name in enumerate(walls.parts):
        mine = np.nonzero((walls.part == k) & far)[0]
        if not len(mine):
            continue
        sample = walls.positions[rng.choice(mine, size=min(100, len(mine)), replace=False)]
        assert np.allclose(_winding(meshes[name], sample), 1.0, atol=1e-6), name


def test_every_wetted_site_has_a_full_support_of_wall_particles():
    """Around every fluid lattice site within 2h of a wall, each lattice site inside a solid is a boundary particle
    (where a face lies off the lattice, e.g. the front gap's floor 0.25 dx below a fluid layer, the walls need fewer
    than ceil(2h / dx) layers: the nearest fluid site's support reaches 2h less its distance to the face)."""
    from scipy.spatial import cKDTree

    case, layout, walls, _ = _scene()
    dx, h = case.numerics.dx, case.numerics.h
    z_lo = min(r.z_lo for r in layout.wetted if isinstance(r, Ring))
    sites = scene_lattice(layout, dx, layout.r_max, z_lo - 3 * h, max(_open_tops(layout)))
    wet = layout.wetted_contains(sites)
    fluid, other = sites[wet], sites[~wet]
    solid = np.zeros(len(other), dtype=bool)
    for mask in solid_masks(other, case, layout).values():
        solid |= mask
    solid_sites = other[solid]
    needed = cKDTree(fluid).query(solid_sites, distance_upper_bound=2 * h)[0] < 2 * h
    have = cKDTree(walls.positions).query(solid_sites[needed], distance_upper_bound=1e-3 * dx)[0] < 1e-3 * dx
    assert needed.sum() > 10_000 and have.all()
    # the layers along a wall's normal: below the head's face, on the axis (the front gap's floor is the workpiece)
    column = walls.positions[(np.abs(walls.positions[:, 0]) < dx) & (np.abs(walls.positions[:, 1]) < dx)
                             & (walls.positions[:, 2] < 0.0)]
    floor = -case.geometry().front_clearance
    lowest = scene_lattice(layout, dx, dx, floor, 0.0)[:, 2].min() - floor  # the lowest fluid layer above the floor
    deepest = floor - column[:, 2].min()  # the deepest wall layer below it
    assert lowest + deepest < 2 * h <= lowest + deepest + dx  # the next layer down is out of that fluid's support


def test_wall_points_are_the_nearest_points_of_the_meshes_surface():
    import trimesh

    case, layout, walls, meshes = _scene()
    h = case.numerics.h
    tops = np.array(_open_tops(layout))
    z = walls.positions[:, 2]
    away = np.all(np.abs(z[:, None] - tops[None, :]) > 2 * h, axis=1)  # the open ends have no wall
    rng = np.random.default_rng(2)
    rows = rng.choice(np.nonzero(away)[0], size=200, replace=False)
    solid = trimesh.boolean.union(list(meshes.values()), engine="manifold")
    x, w = walls.positions[rows], walls.wall_points[rows]
    near, d_mesh = _closest(solid, x)
    _, on_surface = _closest(solid, w)
    assert on_surface.max() < MESH_TOLERANCE  # the wall point lies on the surface
    # the nearest point of the surface that faces the fluid: a surface beside an empty space (e.g. the inner tube's
    # bore, not in the scene) is nobody's wall
    beyond = near + (near - x) / d_mesh[:, None] * 0.05 * case.numerics.dx
    wetted = layout.wetted_contains(beyond)
    assert wetted.sum() > 100
    assert np.abs(np.linalg.norm(w - x, axis=1) - d_mesh)[wetted].max() < MESH_TOLERANCE
    assert (np.linalg.norm(w - x, axis=1) >= d_mesh - MESH_TOLERANCE).all()  # none nearer than the surface


def test_initial_densities_book_out_the_empty_sites():
    from scipy.spatial import cKDTree

    # without the collector chamber, whose empty sites would reach the walls beside this short scene's prefill
    case, layout, walls, _ = _scene("drill.groove_depth=0.0")
    dx, h, rho0 = case.numerics.dx, case.numerics.h, case.fluid.density
    occupied = np.vstack([prefill_points(case, layout), inlet_buffer_points(case, layout, 3)])
    rho = initial_densities(walls, case, layout, occupied)
    assert rho.max() <= rho0 and rho.min() > 0.3 * rho0
    # against the direct sum over the lattice's empty wetted sites for a few particles
    sites = scene_lattice(layout, dx, layout.r_max, layout.z_lo, layout.z_hi)
    sites = sites[layout.wetted_contains(sites)]
    empty = sites[~(cKDTree(occupied).query(sites, distance_upper_bound=0.25 * dx)[0] < 0.25 * dx)]
    for b in np.random.default_rng(3).choice(walls.n, size=20, replace=False):
        r = np.linalg.norm(empty - walls.positions[b], axis=1)
        expected = rho0 - rho0 * dx ** 3 * kernel_value(r, h, 3).sum()
        assert rho[b] == pytest.approx(expected, rel=1e-12, abs=1e-9)
    # with every wetted site filled the walls start at rho0 (the fluid's lattice state)
    assert np.allclose(initial_densities(walls, case, layout, sites), rho0, rtol=0, atol=1e-9)
    # the walls of the empty gap ahead of the prefill (2 mm above the groove's floor) start below rho0 (0.55-0.96 at
    # dx = 0.5 mm), those beside the prefill and the inlet's buffer (0.5 mm below the inlet) far less so
    near_wall = walls.distances() < dx
    empty = near_wall & (np.abs(walls.positions[:, 2] - (layout.channel.z_lo + 2e-3)) < dx)
    filled = near_wall & (np.abs(walls.positions[:, 2] - (layout.channel.z_hi - 0.5e-3)) < dx)
    assert empty.sum() > 500 and rho[empty].max() < 0.97 * rho0 and np.median(rho[empty]) < 0.85 * rho0
    assert np.median(rho[filled]) > np.median(rho[empty]) + 0.02 * rho0
