"""Contact detection for the reference DEM: spheres against spheres,
infinite planes and triangles, vectorised with numpy (k-d trees from scipy
for the candidate pairs). Lengths in m.

Every detector returns a Detected batch: the sphere, the other body, the
unit normal pointing from the sphere towards the other body, and the
overlap delta_n = (sum of radii) - (distance) > 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

FACE, EDGE, VERTEX = 0, 1, 2


@dataclass
class Detected:
    """Contacts found in one step (n of them); other is a sphere, plane or triangle index."""

    sphere: np.ndarray  # (n,) int
    other: np.ndarray  # (n,) int
    normal: np.ndarray  # (n,3) unit, from the sphere to the other body
    overlap: np.ndarray  # (n,) m

    @classmethod
    def empty(cls) -> "Detected":
        return cls(np.zeros(0, int), np.zeros(0, int), np.zeros((0, 3)), np.zeros(0))


def _rowdot(a, b):
    return np.einsum("ij,ij->i", a, b)


def sphere_sphere_contacts(positions, radii) -> Detected:
    """Overlapping sphere pairs i < j (normal from i to j) by a k-d tree search."""
    from scipy.spatial import cKDTree

    if len(radii) < 2:
        return Detected.empty()
    pairs = cKDTree(positions).query_pairs(2.0 * float(radii.max()), output_type="ndarray")
    if len(pairs) == 0:
        return Detected.empty()
    i, j = pairs[:, 0], pairs[:, 1]
    branch = positions[j] - positions[i]
    distance = np.linalg.norm(branch, axis=1)
    overlap = radii[i] + radii[j] - distance
    touching = (overlap > 0.0) & (distance > 0.0)
    i, j, branch, distance, overlap = i[touching], j[touching], branch[touching], distance[touching], overlap[touching]
    return Detected(i, j, branch / distance[:, None], overlap)


def sphere_plane_contacts(positions, radii, plane_points, plane_normals) -> Detected:
    """Spheres overlapping infinite planes. plane_normals: (P,3) unit, pointing to the
    side the spheres live on; a plane is a half-space wall, so a centre behind it
    still gets pushed back out (overlap = R - signed distance)."""
    if len(plane_points) == 0 or len(radii) == 0:
        return Detected.empty()
    signed = np.einsum("npk,pk->np", positions[:, None, :] - plane_points[None, :, :], plane_normals)
    overlap = radii[:, None] - signed
    sphere, plane = np.nonzero(overlap > 0.0)
    return Detected(sphere, plane, -plane_normals[plane], overlap[sphere, plane])


def closest_points_on_triangles(points, a, b, c):
    """Closest point (n,3) on each triangle (a, b, c: (n,3)) to each point (n,3), and
    which feature it lies on (FACE, EDGE or VERTEX), by Ericson's Voronoi-region test."""
    ab, ac = b - a, c - a
    ap, bp, cp = points - a, points - b, points - c
    d1, d2 = _rowdot(ab, ap), _rowdot(ac, ap)
    d3, d4 = _rowdot(ab, bp), _rowdot(ac, bp)
    d5, d6 = _rowdot(ab, cp), _rowdot(ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2

    def safe(num, den):
        return num / np.where(den != 0.0, den, 1.0)

    denom = va + vb + vc
    v_face, w_face = safe(vb, denom), safe(vc, denom)
    t_ab, t_ac = safe(d1, d1 - d3), safe(d2, d2 - d6)
    t_bc = safe(d4 - d3, (d4 - d3) + (d5 - d6))
    regions = [
        (d1 <= 0) & (d2 <= 0),  # vertex a
        (d3 >= 0) & (d4 <= d3),  # vertex b
        (vc <= 0) & (d1 >= 0) & (d3 <= 0),  # edge ab
        (d6 >= 0) & (d5 <= d6),  # vertex c
        (vb <= 0) & (d2 >= 0) & (d6 <= 0),  # edge ac
        (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0),  # edge bc
    ]
    candidates = [a, b, a + t_ab[:, None] * ab, c, a + t_ac[:, None] * ac, b + t_bc[:, None] * (c - b)]
    closest = a + v_face[:, None] * ab + w_face[:, None] * ac
    feature = np.full(len(points), FACE)
    # np.select semantics by hand: the first region that holds wins
    taken = np.zeros(len(points), bool)
    for region, point, kind in zip(regions, candidates, (VERTEX, VERTEX, EDGE, VERTEX, EDGE, EDGE)):
        use = region & ~taken
        closest[use] = point[use]
        feature[use] = kind
        taken |= use
    return closest, feature


class TriangleSearch:
    """Candidate triangles near each sphere for one rigidly translating mesh.

    A uniform grid of cells (at least 2 R_max wide) lists the triangles whose
    bounding box, widened by R_max, reaches into each cell; a sphere's
    candidates are the triangles listed in the cell of its centre. A k-d tree
    of the centroids serves the free-flight gap bound (nearest_gaps).
    """

    def __init__(self, vertices, faces):
        from scipy.spatial import cKDTree

        self.corners = np.asarray(vertices, float)[np.asarray(faces)]  # (T,3,3) at t = 0
        centroids = self.corners.mean(axis=1)
        self.reach = float(np.linalg.norm(self.corners - centroids[:, None, :], axis=2).max())
        self.tree = cKDTree(centroids)
        normals = np.cross(self.corners[:, 1] - self.corners[:, 0], self.corners[:, 2] - self.corners[:, 0])
        self.normals = normals / np.linalg.norm(normals, axis=1)[:, None]
        self.box_low, self.box_high = self.corners.min(axis=1), self.corners.max(axis=1)
        self._grid = None  # built on first use, when the largest sphere radius is known

    def _build_grid(self, largest_radius):
        extent = float((self.box_high.max(axis=0) - self.box_low.min(axis=0)).max())
        size = max(2.0 * largest_radius, extent / 100.0)
        origin = self.box_low.min(axis=0) - largest_radius - size
        low = np.floor((self.box_low - largest_radius - origin) / size).astype(np.int64)
        high = np.floor((self.box_high + largest_radius - origin) / size).astype(np.int64)
        shape = high.max(axis=0) + 2
        cells, triangles = [], []
        for t, (lo, hi) in enumerate(zip(low, high)):
            block = np.stack(np.meshgrid(*[np.arange(a, b + 1) for a, b in zip(lo, hi)], indexing="ij"), -1)
            ids = np.ravel_multi_index(block.reshape(-1, 3).T, shape)
            cells.append(ids)
            triangles.append(np.full(len(ids), t))
        cells, triangles = np.concatenate(cells), np.concatenate(triangles)
        order = np.argsort(cells, kind="stable")
        cells, triangles = cells[order], triangles[order]
        occupied, starts = np.unique(cells, return_index=True)
        ends = np.append(starts[1:], len(cells))
        self._grid = (origin, size, shape, occupied, starts, ends, triangles, largest_radius)

    def _candidates(self, local, radii):
        """(sphere, triangle) pairs whose widened box holds the sphere's centre cell."""
        if self._grid is None or self._grid[-1] < radii.max():
            self._build_grid(float(radii.max()))
        origin, size, shape, occupied, starts, ends, triangles, _ = self._grid
        index = np.floor((local - origin) / size).astype(np.int64)
        inside = np.all((index >= 0) & (index < shape), axis=1)
        sphere = np.nonzero(inside)[0]
        ids = np.ravel_multi_index(index[inside].T, shape)
        slot = np.minimum(np.searchsorted(occupied, ids), len(occupied) - 1)
        listed = occupied[slot] == ids
        sphere, slot = sphere[listed], slot[listed]
        counts = ends[slot] - starts[slot]
        first = np.repeat(starts[slot], counts)
        rank = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
        return np.repeat(sphere, counts), triangles[first + rank]

    def contacts(self, positions, radii, shift) -> tuple[Detected, np.ndarray]:
        """Spheres overlapping this mesh displaced by shift (3,), m; returns the batch
        (other = triangle index in the mesh) and the closest-point feature per contact."""
        local = positions - shift
        sphere, triangle = self._candidates(local, radii)
        # cheap cuts before the exact test: the triangle's plane and its box, widened by R
        centre, radius = local[sphere], radii[sphere][:, None]
        near = np.abs(_rowdot(centre - self.corners[triangle, 0], self.normals[triangle])) < radius[:, 0]
        near &= np.all((centre > self.box_low[triangle] - radius) & (centre < self.box_high[triangle] + radius), axis=1)
        sphere, triangle = sphere[near], triangle[near]
        if len(sphere) == 0:
            return Detected.empty(), np.zeros(0, int)
        corners = self.corners[triangle]
        closest, feature = closest_points_on_triangles(local[sphere], corners[:, 0], corners[:, 1], corners[:, 2])
        branch = closest - local[sphere]
        distance = np.linalg.norm(branch, axis=1)
        overlap = radii[sphere] - distance
        touching = (overlap > 0.0) & (distance > 0.0)
        sphere, triangle, feature = sphere[touching], triangle[touching], feature[touching]
        branch, distance, overlap = branch[touching], distance[touching], overlap[touching]
        keep = _one_contact_per_feature(sphere, feature, closest[touching], overlap, radii)
        normal = branch[keep] / distance[keep, None]
        return Detected(sphere[keep], triangle[keep], normal, overlap[keep]), feature[keep]


def _one_contact_per_feature(sphere, feature, closest, overlap, radii) -> np.ndarray:
    """Indices of the contacts to keep so that a mesh touches a sphere once per
    surface feature: a sphere that touches a face interior ignores edges and
    vertices (a ball on a flat mesh near a shared edge would otherwise be
    pushed twice, once askew); without a face contact, edge and vertex contacts
    at the same point (shared by several triangles) count once, the deepest."""
    order = np.arange(len(sphere))
    on_face = feature == FACE
    with_face = np.unique(sphere[on_face])
    keep = on_face | ~np.isin(sphere, with_face)
    rest = order[keep & ~on_face]
    if len(rest) < 2:
        return order[keep]
    dropped = set()
    rest = rest[np.lexsort((-overlap[rest], sphere[rest]))]
    for a_pos, a in enumerate(rest):
        if a in dropped:
            continue
        for b in rest[a_pos + 1:]:
            if sphere[b] != sphere[a]:
                break
            if np.linalg.norm(closest[a] - closest[b]) < 1e-6 * radii[sphere[a]]:
                dropped.add(b)
    return order[keep & ~np.isin(order, list(dropped))]


def nearest_gaps(positions, radii, plane_points, plane_normals, searches, shifts):
    """Lower bound of each sphere's gap, m, to any other sphere, plane or triangle
    (negative when touching): used to take long steps in free flight."""
    from scipy.spatial import cKDTree

    gaps = np.full(len(radii), np.inf)
    if len(radii) > 1:
        distance, _ = cKDTree(positions).query(positions, k=2)
        gaps = np.minimum(gaps, distance[:, 1] - radii - radii.max())
    if len(plane_points):
        signed = np.einsum("npk,pk->np", positions[:, None, :] - plane_points[None, :, :], plane_normals)
        gaps = np.minimum(gaps, (signed - radii[:, None]).min(axis=1))
    for search, shift in zip(searches, shifts):
        distance, _ = search.tree.query(positions - shift)
        gaps = np.minimum(gaps, distance - search.reach - radii)
    return gaps
