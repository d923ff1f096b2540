"""The scene of an SPH flow case: particle arrays (fluid and fixed boundary
particles on a lattice of spacing dx), wall meshes (trimesh in 3D, segment
lists in 2D), the smoothing length, sound speed and time step. SI units; in
2D masses are per metre of depth (kg/m).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from orchestrator.kinds.sph_flow.case import SphFlowCase, Wall
from orchestrator.kinds.sph_flow.case_grains import carve_grains, check_contact_duration, grain_decks
from orchestrator.kinds.sph_flow.case_impactors import check_clear
from orchestrator.kinds.sph_flow.case_limits import sph_timestep
from orchestrator.kinds.sph_flow.case_materials import (RunMaterial, block_materials, largest_c0_and_viscosity,
                                                       run_materials)
from orchestrator.scene.geometry import read_mesh

#: Particle kinds of the sph executable's input (engines/sph/src/physics_terms.h).
FLUID, BOUNDARY = 0, 1


@dataclass(frozen=True)
class WallMesh:
    """A wall as vertices (nv, D) m and faces (nf, D) vertex indices: triangles in 3D, segments in 2D."""

    name: str
    vertices: np.ndarray
    faces: np.ndarray


@dataclass(frozen=True)
class SphScene:
    """What the sph executable (and the reference SPH) needs to run an SPH flow case."""

    case: SphFlowCase
    positions: np.ndarray  # (n, D) m
    velocities: np.ndarray  # (n, D) m/s
    masses: np.ndarray  # (n,) kg (2D: kg/m)
    densities: np.ndarray  # (n,) kg/m^3
    kind: np.ndarray  # (n,) int8: 0 fluid, 1 fixed boundary, 4 a grain's particle
    block: np.ndarray  # (n,) index of the case block each particle comes from
    meshes: dict[str, WallMesh]
    h: float  # smoothing length, m (kernel support 2h)
    c0: float  # reference sound speed, m/s
    timestep: float  # fixed dt, or the adaptive CFL step at rest cfl h / c0, s
    physics: tuple[str, ...] = ()  # the terms the engine compiles in (physics.terms): what the deck switches on
    material: np.ndarray | None = None  # (n,) int32 index into materials of each particle
    materials: tuple[RunMaterial, ...] = ()  # the run's materials (one, "fluid", without [[materials]])
    wall_point: np.ndarray | None = None  # (n, D) m: a boundary particle's nearest point of the true wall (NaN: none)
    grain: np.ndarray | None = None  # (n,) int32: a grain particle's (kind 4) index into case.grains, else -1
    grains: tuple[dict, ...] = ()  # the deck's grain objects (case_grains.grain_decks)
    body_force: tuple[float, ...] | None = None  # the fluid's body force when it is not physics.body_force, m/s^2
    state: dict[str, np.ndarray] | None = None  # starting stresses the engine restores by row (mode_stress (n, modes D^2) Pa)

    @property
    def dimension(self) -> int:
        """2 or 3."""
        return self.positions.shape[1]

    @property
    def n_particles(self) -> int:
        """Number of particles in the input (fluid and boundary; inlets add more at run time)."""
        return len(self.masses)

    @property
    def n_fluid(self) -> int:
        """Number of fluid particles in the input."""
        return int(np.count_nonzero(self.kind == FLUID))


def lattice(lo, hi, dx: float) -> np.ndarray:
    """Points lo + (i + 1/2) dx filling the box lo..hi, (n, D) m (hi - lo a whole number of dx)."""
    axes = [lo_k + (np.arange(round((hi_k - lo_k) / dx)) + 0.5) * dx for lo_k, hi_k in zip(lo, hi)]
    grids = np.meshgrid(*axes, indexing="ij")
    return np.column_stack([g.ravel() for g in grids])


def hydrostatic_density(positions: np.ndarray, surface: float, body_force, rho0: float, c0: float,
                        gamma: float) -> np.ndarray:
    """Density (kg/m^3) under a free surface at height `surface` (m, along -body_force): the Tait EOS
    (eq. 6) inverted for the hydrostatic pressure rho0 |g| depth; rho0 above the surface."""
    g = np.asarray(body_force, dtype=float)
    up = -g / np.linalg.norm(g)
    depth = np.clip(surface - positions @ up, 0.0, None)
    b = rho0 * c0**2 / gamma
    return rho0 * (1.0 + rho0 * np.linalg.norm(g) * depth / b) ** (1.0 / gamma)


def _particles(case: SphFlowCase, materials: tuple[RunMaterial, ...]):
    dx, d = case.numerics.dx, case.dimension
    tree_points: list[np.ndarray] = []
    rows = []
    for index, (block, k) in enumerate(zip(case.blocks, block_materials(case))):
        rho0 = materials[k].rho0
        points = lattice(block.lo, block.hi, dx)
        if block.cylinder is not None:
            points = points[block.cylinder.keeps(points)]
        if tree_points:
            from scipy.spatial import cKDTree

            taken = cKDTree(np.vstack(tree_points))
            distance, _ = taken.query(points, distance_upper_bound=0.5 * dx)
            points = points[~np.isfinite(distance)]  # a site already filled by an earlier block stays as it is
        if not len(points):
            continue
        tree_points.append(points)
        velocity = np.zeros(d) if block.velocity is None else np.asarray(block.velocity, dtype=float)
        if block.hydrostatic_surface is not None:
            rho = hydrostatic_density(points, block.hydrostatic_surface, case.physics.body_force, rho0,
                                      materials[k].c0, materials[k].gamma)
        else:
            rho = np.full(len(points), rho0)
        if block.cylinder is not None and block.cylinder.wall is not None:
            wall_point = block.cylinder.wall_points(points)
        else:
            wall_point = np.full(points.shape, np.nan)
        rows.append((points, np.tile(velocity, (len(points), 1)), rho,
                     np.full(len(points), FLUID if block.kind == "fluid" else BOUNDARY, dtype=np.int8),
                     np.full(len(points), index, dtype=np.int32), np.full(len(points), rho0 * dx**d),
                     np.full(len(points), k, dtype=np.int32), wall_point))
    positions, velocities, densities, kind, block, masses, material, wall_point = (
        np.concatenate(parts) for parts in zip(*rows))
    if not any(b.cylinder is not None and b.cylinder.wall is not None for b in case.blocks):
        wall_point = None  # the particle file has no wall_point: Adami's mirror everywhere, as before
    return positions, velocities, masses, densities, kind, block, material, wall_point


def wall_mesh(wall: Wall, dimension: int) -> WallMesh:
    """The wall as vertices and faces (triangles in 3D, segments in 2D), m."""
    if wall.shape == "box":
        vertices, faces = _box(np.asarray(wall.lo, float), np.asarray(wall.hi, float), wall.open_sides, dimension)
    elif wall.shape == "plane":
        vertices, faces = _plane(wall, dimension)
    else:

        mesh = read_mesh(wall.file, f"the mesh file of wall {wall.name!r}")
        vertices = np.asarray(mesh.vertices, dtype=float) * (wall.scale or 1.0)
        if wall.translate is not None:
            vertices = vertices + np.asarray(wall.translate, dtype=float)
        faces = np.asarray(mesh.faces, dtype=np.int64)
        if not len(faces):
            raise ValueError(f"walls: the mesh file {wall.file} of wall {wall.name!r} holds no triangles")
    return WallMesh(wall.name, np.ascontiguousarray(vertices, dtype=float), np.ascontiguousarray(faces, np.int64))


def _box(lo: np.ndarray, hi: np.ndarray, open_sides, dimension: int):
    if dimension == 2:
        vertices = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
        sides = {"-y": (0, 1), "+x": (1, 2), "+y": (2, 3), "-x": (3, 0)}
        faces = [edge for side, edge in sides.items() if side not in open_sides]
        return vertices, np.array(faces, dtype=np.int64).reshape(-1, 2)
    import trimesh

    mesh = trimesh.creation.box(bounds=np.vstack([lo, hi]))
    keep = np.ones(len(mesh.faces), dtype=bool)
    for side in open_sides:
        axis, sign = "xyz".index(side[1]), 1.0 if side[0] == "+" else -1.0
        keep &= ~(mesh.face_normals[:, axis] * sign > 0.5)
    return np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces[keep], dtype=np.int64)


def _plane(wall: Wall, dimension: int):
    center = np.asarray(wall.center, dtype=float)
    normal = np.asarray(wall.normal, dtype=float)
    normal = normal / np.linalg.norm(normal)
    if dimension == 2:
        tangent = np.array([-normal[1], normal[0]]) * wall.half_extents[0]
        return np.array([center - tangent, center + tangent]), np.array([[0, 1]], dtype=np.int64)
    u = np.asarray(wall.u, dtype=float)
    u = u - (u @ normal) * normal
    u /= np.linalg.norm(u)
    w = np.cross(normal, u)
    a, b = wall.half_extents
    corners = [center - a * u - b * w, center + a * u - b * w, center + a * u + b * w, center - a * u + b * w]
    # Counter-clockwise seen from the normal's side.
    return np.array(corners), np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int64)


def build_sph_flow(case: SphFlowCase) -> SphScene:
    """Particles, wall meshes, h, c0 (the largest of the materials') and the time step of an SPH flow case."""
    materials = run_materials(case)
    c0 = max(m.c0 for m in materials)
    positions, velocities, masses, densities, kind, block, material, wall_point = _particles(case, materials)
    meshes = {wall.name: wall_mesh(wall, case.dimension) for wall in case.walls}
    grain, grains, body_force = None, (), None
    if case.grains:
        kind, velocities, grain = carve_grains(case.grains, positions, kind, velocities, case.numerics.dx)
        body_force, grains = grain_decks(case, masses, kind, grain, materials[0].rho0)
        grains = tuple(grains)
    check_clear(case.impactors, positions, kind == FLUID, case.numerics.dx)
    h = case.numerics.h
    dt = sph_timestep(case, *largest_c0_and_viscosity(materials))  # fixed, or the adaptive step at rest
    if case.grains:
        check_contact_duration(case, grain, dt)
    return SphScene(case=case, positions=positions, velocities=velocities, masses=masses, densities=densities,
                    kind=kind, block=block, meshes=meshes, h=h, c0=c0, timestep=dt,
                    physics=tuple(case.physics.terms), material=material, materials=materials,
                    wall_point=wall_point, grain=grain, grains=grains, body_force=body_force)
