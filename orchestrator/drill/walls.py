"""Fixed boundary particles for the walls of a drill scene: the lattice sites lo + (i + 1/2) dx of the fluid's own
lattice that lie inside the scene's solids (each kind names its solids and their membership tests) within the
kernel support 2h of the wetted regions' surface (layout.wetted: the fluid regions and the open boundaries'
buffers), each with its wall point, the nearest point of the wetted regions' surface (the solid's wetted face: the
engine extrapolates the no-slip velocity to it, engines/sph/README.md "Wall points"). SI units (m).

Solids of revolution are tested in closed form on their (r, z) polygons (in_solid; geometry.DrillGeometry.profiles).
The wall point is in closed form too: the nearest point of each wetted ring is its (r, z) rectangle's clamp at the
site's own angle, of each hole the clamp to its cylinder, of any other region its own `nearest`, and the nearest of
those is the wall's (the wetted regions and the solids share their faces, so the nearest wetted point of a site
inside a solid lies on the solid's wetted surface).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from orchestrator.drill.regions import Hole, Ring
from orchestrator.reference.sph import kernel_value


@dataclass(frozen=True)
class WallParticles:
    """The boundary particles: positions (n, 3) m, wall points (n, 3) m, the solid each lies in (n,) index into
    `parts`, and the support distance they were chosen within, m."""

    positions: np.ndarray
    wall_points: np.ndarray
    part: np.ndarray
    parts: tuple[str, ...]
    reach: float

    @property
    def n(self) -> int:
        """Number of boundary particles."""
        return len(self.positions)

    def distances(self) -> np.ndarray:
        """Each particle's distance to its wall point, m."""
        return np.linalg.norm(self.wall_points - self.positions, axis=1)


def lattice_offset(layout, dx: float) -> float:
    """The scene lattice's x and y offset from the axis, m: the inlet's columns (the engine puts them at
    (i + 1/2 - n/2) dx across its disc, n = round(2 radius / dx)) on the same sites as the walls and the fluid."""
    n = max(1, round(2.0 * layout.inlet.radius / dx))
    return 0.5 * dx if n % 2 == 0 else 0.0


def lattice_z0(layout, dx: float) -> float:
    """A z of the scene lattice's sites, m: the inlet's first layer, half a spacing upstream of its plane."""
    return layout.inlet.center[2] - 0.5 * dx * layout.inlet.normal[2]


def scene_lattice(layout, dx: float, r_max: float, z_lo: float, z_hi: float) -> np.ndarray:
    """The scene lattice's sites (n, 3) m with |x|, |y| <= r_max and z_lo <= z < z_hi (x, y on lattice_offset, z on
    lattice_z0)."""
    off, z0 = lattice_offset(layout, dx), lattice_z0(layout, dx)
    k = math.ceil(r_max / dx) + 1
    xy = off + dx * np.arange(-k, k + 1)
    xy = xy[np.abs(xy) <= r_max]
    zs = z0 + dx * np.arange(math.floor((z_lo - z0) / dx), math.ceil((z_hi - z0) / dx) + 1)
    zs = zs[(zs >= z_lo) & (zs < z_hi)]
    x, y, z = np.meshgrid(xy, xy, zs, indexing="ij")
    return np.column_stack([x.ravel(), y.ravel(), z.ravel()])


def in_polygon(r: np.ndarray, z: np.ndarray, polygon) -> np.ndarray:
    """Mask of the points (r, z) inside the closed polygon [(r, z), ...] (even-odd rule, m)."""
    p = np.asarray(polygon, dtype=float)
    inside = np.zeros(len(r), dtype=bool)
    for (r1, z1), (r2, z2) in zip(p, np.roll(p, -1, axis=0)):
        if z1 == z2:
            continue
        crosses = (z1 > z) != (z2 > z)
        r_at = r1 + (z - z1) * (r2 - r1) / (z2 - z1)
        inside ^= crosses & (r < r_at)
    return inside


def in_solid(points: np.ndarray, polygon, eps: float) -> np.ndarray:
    """Mask of the points (n, 3) m in the solid of revolution of `polygon` ((r, z), m), a point within eps of its
    surface counted in (sites on a face two solids share, e.g. the head's rear face and the outer tube's end)."""
    r, z = np.hypot(points[:, 0], points[:, 1]), points[:, 2]
    mask = np.zeros(len(points), dtype=bool)
    for dr, dz in ((0, 0), (eps, 0), (-eps, 0), (0, eps), (0, -eps)):
        mask |= in_polygon(r + dr, z + dz, polygon)
    return mask


def nearest_on_ring(points: np.ndarray, ring: Ring) -> np.ndarray:
    """Each point's nearest point (n, 3) m of the ring's solid of revolution (its (r, z) rectangle clamped at the
    point's angle; on the axis the angle is 0)."""
    r = np.hypot(points[:, 0], points[:, 1])
    rc = np.clip(r, ring.r_in, ring.r_out)
    zc = np.clip(points[:, 2], ring.z_lo, ring.z_hi)
    safe = np.where(r > 0.0, r, 1.0)
    cos, sin = np.where(r > 0.0, points[:, 0] / safe, 1.0), np.where(r > 0.0, points[:, 1] / safe, 0.0)
    return np.column_stack([rc * cos, rc * sin, zc])


def nearest_on_hole(points: np.ndarray, hole: Hole) -> np.ndarray:
    """Each point's nearest point (n, 3) m of the hole's cylinder (axis along its angle at height z, r_in..r_out)."""
    e = np.array([math.cos(hole.angle), math.sin(hole.angle), 0.0])
    base = np.array([0.0, 0.0, hole.z])
    s = (points - base) @ e
    q = points - base - np.outer(s, e)
    dist = np.linalg.norm(q, axis=1)
    scale = np.minimum(1.0, 0.5 * hole.d / np.where(dist > 0.0, dist, 1.0))
    return base + np.outer(np.clip(s, hole.r_in, hole.r_out), e) + q * scale[:, None]


def wall_points(points: np.ndarray, layout) -> np.ndarray:
    """Each point's nearest point (n, 3) m of the wetted regions (for a point in a solid: the nearest point of the
    solid's wetted surface)."""
    best = np.full(points.shape, np.nan)
    best_d = np.full(len(points), np.inf)
    for region in layout.wetted:
        if isinstance(region, (Hole, Ring)):
            near = nearest_on_hole(points, region) if isinstance(region, Hole) else nearest_on_ring(points, region)
        else:  # a region with its own closed form (the feed's nozzles: kinds/ejector_feed/layout.py)
            near = region.nearest(points)
        d = np.linalg.norm(near - points, axis=1)
        closer = d < best_d
        best[closer], best_d[closer] = near[closer], d[closer]
    return best


def boundary_particles(case, layout, parts: tuple[str, ...], masks_of, slab: int = 40) -> WallParticles:
    """The scene's boundary particles (see the module docstring): sites inside a solid, outside the wetted regions,
    at most 2h from them. parts: the solids' names, in the order a site shared by two is given to the first;
    masks_of: points (n, 3) m -> {part: mask of the points inside it}; slab: lattice planes handled at a time
    (memory)."""
    dx, h = case.numerics.dx, case.numerics.h
    reach = 2.0 * h
    r_max = max(r.r_out for r in layout.wetted if isinstance(r, Ring)) + reach + dx
    z_lo = min(r.z_lo for r in layout.wetted if isinstance(r, Ring)) - reach - dx
    z_top = max(r.z_hi for r in layout.wetted if isinstance(r, Ring)) + reach + dx
    z_lo, z_top = max(z_lo, layout.z_lo), min(z_top, layout.z_hi)
    positions, points_w, part_of = [], [], []
    z = z_lo
    while z < z_top:
        z_next = min(z_top, z + slab * dx)
        sites = scene_lattice(layout, dx, r_max, z, z_next)
        z = z_next
        if not len(sites):
            continue
        sites = sites[~layout.wetted_contains(sites)]
        near = wall_points(sites, layout)
        keep = np.linalg.norm(near - sites, axis=1) <= reach
        sites, near = sites[keep], near[keep]
        masks = masks_of(sites)
        part = np.full(len(sites), -1)
        for k, name in enumerate(parts):
            part[(part < 0) & masks[name]] = k
        solid = part >= 0
        positions.append(sites[solid]), points_w.append(near[solid]), part_of.append(part[solid])
    return WallParticles(positions=np.concatenate(positions), wall_points=np.concatenate(points_w),
                         part=np.concatenate(part_of).astype(np.int8), parts=tuple(parts), reach=reach)


def initial_densities(walls: WallParticles, case, layout, occupied: np.ndarray, slab: int = 40) -> np.ndarray:
    """Each boundary particle's density at t = 0, kg/m^3: rho0 less the kernel sum m W of the wetted lattice sites
    around it that hold no particle at the start (occupied: the prefill and the inlet's buffer, (n, 3) m).

    The engine evolves a boundary particle's density as the rate of the summation density over the moving particles
    (engines/sph/src/physics_terms.h), so rho_b(t) = rho_b(0) + sum m W(t) - sum m W(0): starting at rho0 beside an
    empty gap, a wall would reach rho0 plus the fluid's whole share (+17 % in 12 us, 600 MPa at c0 = 1500 m/s) when
    the fluid arrives. With this start it reaches rho0 when the wetted sites around it are filled at the lattice
    spacing, and stays below (at pressure 0: the engine takes max(rho_b, rho0)) while they are empty."""
    from scipy.spatial import cKDTree

    dx, h, rho0 = case.numerics.dx, case.numerics.h, case.fluid.density
    mass = rho0 * dx ** 3
    out = np.full(walls.n, rho0)
    if not walls.n:
        return out
    occupied_tree = cKDTree(occupied) if len(occupied) else None
    r_max = float(np.max(np.abs(walls.positions[:, :2]))) + 2 * h
    z = walls.positions[:, 2]
    for z_lo in np.arange(float(z.min()), float(z.max()) + slab * dx, slab * dx):
        z_hi = z_lo + slab * dx
        rows = np.nonzero((z >= z_lo) & (z < z_hi))[0]
        if not len(rows):
            continue
        sites = scene_lattice(layout, dx, r_max, z_lo - 2 * h, z_hi + 2 * h)
        sites = sites[layout.wetted_contains(sites)]
        if occupied_tree is not None and len(sites):
            d, _ = occupied_tree.query(sites, distance_upper_bound=0.25 * dx)
            sites = sites[~np.isfinite(d)]  # the empty ones
        if not len(sites):
            continue
        pairs = cKDTree(walls.positions[rows]).sparse_distance_matrix(cKDTree(sites), 2 * h, output_type="ndarray")
        share = np.bincount(pairs["i"], weights=kernel_value(pairs["v"], h, 3), minlength=len(rows))
        out[rows] = rho0 - mass * share
    return out
