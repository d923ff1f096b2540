"""Penalty walls of the reference SPH (Canini et al., eq. 14), as the sph executable
computes them (engines/sph/src/wall_geometry.h, wall_penalty.h), in numpy.

A particle feels every face (triangle in 3D, segment in 2D) within range R,
along the line from the face's closest point to the particle (the face normal
when it lies on the face). A face interior always counts; an edge or vertex
counts once, and only when every face sharing it finds it closest. Brute
force over faces: meant for small scenes.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

#: Barycentric weights below this count as zero (a shared edge or vertex is named alike by every face).
FEATURE_EPS = 1e-10
FACE, EDGE, VERTEX = 0, 1, 2


def penalty_force(d, range_m: float, s: float, psi: float):
    """Eq. 14: psi ((R-d)^4 - (R-s)^2 (R-d)^2) / (R^2 s (2R - s)) for d <= R, else 0; N (2D: N/m).

    d: distance particle-face, m (scalar or array); F(0) = psi, F(s) = 0, attractive between s and R.
    """
    d = np.asarray(d, dtype=float)
    e = range_m - d
    e2 = e * e
    rs = range_m - s
    force = psi * (e2 * e2 - rs * rs * e2) / (range_m * range_m * s * (2.0 * range_m - s))
    return np.where(d > range_m, 0.0, force)


@dataclass
class PenaltyWalls:
    """Meshes (name -> (vertices (nv, D) m, faces (nf, D) vertex ids)) and the parameters of eq. 14."""

    meshes: dict[str, tuple[np.ndarray, np.ndarray]]
    range_m: float  # R, m
    s: float  # m
    psi: float  # N (2D: N/m)
    _incidence: dict = field(default_factory=dict, repr=False)

    def __post_init__(self):
        for name, (vertices, faces) in self.meshes.items():
            faces = np.asarray(faces, dtype=np.int64)
            counts: dict[tuple, int] = {}
            for face in faces:
                for v in face:
                    counts[(VERTEX, int(v))] = counts.get((VERTEX, int(v)), 0) + 1
                if faces.shape[1] == 3:
                    for i in range(3):
                        key = (EDGE,) + tuple(sorted((int(face[i]), int(face[(i + 1) % 3]))))
                        counts[key] = counts.get(key, 0) + 1
            self._incidence[name] = counts

    def forces(self, x: np.ndarray) -> np.ndarray:
        """Total penalty force on particles at x (n, D) m, (n, D) N (2D: N/m)."""
        return self.forces_by_mesh(x)[0]

    def forces_by_mesh(self, x: np.ndarray) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """(total force on each particle (n, D), name -> force of that mesh on each particle (n, D)), N."""
        x = np.asarray(x, dtype=float)
        total = np.zeros_like(x)
        per_mesh = {}
        for name, (vertices, faces) in self.meshes.items():
            force = self._mesh_force(name, np.asarray(vertices, float), np.asarray(faces, np.int64), x)
            per_mesh[name] = force
            total += force
        return total, per_mesh

    def _mesh_force(self, name, vertices, faces, x):
        out = np.zeros_like(x)
        corners: dict[tuple[int, tuple], list] = {}  # (particle, feature) -> [reports, force]
        for f, ids in enumerate(faces):
            corner = vertices[ids]
            point, feature = (_closest_on_triangle(x, *corner, ids) if len(ids) == 3
                              else _closest_on_segment(x, *corner, ids))
            delta = x - point
            d = np.linalg.norm(delta, axis=1)
            near = np.nonzero(d <= self.range_m)[0]
            if not len(near):
                continue
            normal = _face_normal(corner)
            on_face = d[near] > 1e-12 * self.range_m
            direction = np.where(on_face[:, None], delta[near] / np.where(on_face, d[near], 1.0)[:, None], normal)
            force = penalty_force(d[near], self.range_m, self.s, self.psi)[:, None] * direction
            for row, i in enumerate(near):
                key = feature[i]
                if key[0] == FACE:
                    out[i] += force[row]
                    continue
                entry = corners.setdefault((int(i), key), [0, force[row]])
                entry[0] += 1
        incidence = self._incidence[name]
        for (i, key), (reports, force) in corners.items():
            if reports == incidence.get(key, 1):
                out[i] += force
        return out


def _face_normal(corner: np.ndarray) -> np.ndarray:
    if len(corner) == 3:
        n = np.cross(corner[1] - corner[0], corner[2] - corner[0])
        return n / np.linalg.norm(n)
    t = (corner[1] - corner[0]) / np.linalg.norm(corner[1] - corner[0])
    return np.array([-t[1], t[0]])


def _closest_on_segment(p, a, b, ids):
    ab = b - a
    t = np.clip((p - a) @ ab / (ab @ ab), 0.0, 1.0)
    point = a + t[:, None] * ab
    point = np.where((t <= FEATURE_EPS)[:, None], a, np.where((t >= 1.0 - FEATURE_EPS)[:, None], b, point))
    features = [(VERTEX, int(ids[0])) if ti <= FEATURE_EPS else (VERTEX, int(ids[1])) if ti >= 1.0 - FEATURE_EPS
                else (FACE,) for ti in t]
    return point, features


def _closest_on_triangle(p, a, b, c, ids):
    """Closest points on triangle abc (Ericson's Voronoi regions, in the executable's order) and their features."""
    ab, ac = b - a, c - a
    ap, bp, cp = p - a, p - b, p - c
    d1, d2 = ap @ ab, ap @ ac
    d3, d4 = bp @ ab, bp @ ac
    d5, d6 = cp @ ab, cp @ ac
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    n = len(p)
    w = np.zeros((n, 3))
    done = np.zeros(n, dtype=bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        regions = [
            (d1 <= 0.0) & (d2 <= 0.0), (d3 >= 0.0) & (d4 <= d3), (vc <= 0.0) & (d1 >= 0.0) & (d3 <= 0.0),
            (d6 >= 0.0) & (d5 <= d6), (vb <= 0.0) & (d2 >= 0.0) & (d6 <= 0.0),
            (va <= 0.0) & (d4 - d3 >= 0.0) & (d5 - d6 >= 0.0),
        ]
        t_ab, t_ac = d1 / (d1 - d3), d2 / (d2 - d6)
        t_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        weights = [
            (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (1.0 - t_ab, t_ab, 0.0), (0.0, 0.0, 1.0), (1.0 - t_ac, 0.0, t_ac),
            (0.0, 1.0 - t_bc, t_bc),
        ]
        for mask, (wa, wb, wc) in zip(regions, weights):
            take = mask & ~done
            for k, value in enumerate((wa, wb, wc)):
                w[take, k] = value[take] if np.ndim(value) else value
            done |= take
        inv = 1.0 / (va + vb + vc)
        v, ww = vb * inv, vc * inv
        rest = ~done
        w[rest, 0], w[rest, 1], w[rest, 2] = (1.0 - v - ww)[rest], v[rest], ww[rest]
    point = w[:, :1] * a + w[:, 1:2] * b + w[:, 2:3] * c
    return point, [_feature(row, ids) for row in w]


def _feature(weights, ids) -> tuple:
    kept = weights > FEATURE_EPS
    count = int(kept.sum())
    if count == 3:
        return (FACE,)
    if count == 2:
        i, j = np.nonzero(kept)[0]
        return (EDGE,) + tuple(sorted((int(ids[i]), int(ids[j]))))
    wa, wb, wc = weights
    i = 0 if wa >= wb and wa >= wc else 1 if wb >= wc else 2
    return (VERTEX, int(ids[i]))
