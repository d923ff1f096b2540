"""Scene: what every engine needs, built once from a Case.

A Scene holds arrays and meshes in SI units and the case it came from;
backends turn it into their own input files.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh

from orchestrator.case.common import rayleigh_timestep
from orchestrator.scene.geometry import load_stl
from orchestrator.scene.particles import draw_radii, random_cloud_in_cylinder

GRAVITY = (0.0, 0.0, -9.81)  # m/s^2


def bowl_mesh(inner_radius: float, height: float, segments: int) -> trimesh.Trimesh:
    """Open cylindrical bowl: a flat floor at z = 0 and a wall up to z = height, axis +z through the origin.

    The floor is a fan around the centre; the wall is one band of quads split
    into triangles. Normals point into the bowl (towards the media).
    """
    angles = np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    ring = np.column_stack([inner_radius * np.cos(angles), inner_radius * np.sin(angles)])
    centre = np.array([[0.0, 0.0, 0.0]])
    bottom = np.column_stack([ring, np.zeros(segments)])
    top = np.column_stack([ring, np.full(segments, height)])
    vertices = np.vstack([centre, bottom, top])
    i = np.arange(segments)
    j = (i + 1) % segments
    floor = np.column_stack([np.zeros(segments, int), 1 + i, 1 + j])
    wall_a = np.column_stack([1 + i, 1 + segments + i, 1 + j])
    wall_b = np.column_stack([1 + j, 1 + segments + i, 1 + segments + j])
    faces = np.vstack([floor, wall_a, wall_b])
    return trimesh.Trimesh(vertices=vertices, faces=faces, process=False)


def rod_mesh(radius: float, length: float, segments: int) -> trimesh.Trimesh:
    """Closed cylinder (rod) with its tip centred at the origin and its axis along +z, length in m."""
    rod = trimesh.creation.cylinder(radius=radius, height=length, sections=segments)
    rod.apply_translation([0.0, 0.0, length / 2.0])
    return rod


@dataclass(frozen=True)
class MeshPart:
    """A rigid triangle mesh of the scene (vertices in m, in its start position)."""

    name: str
    mesh: trimesh.Trimesh
    material: str


@dataclass(frozen=True)
class Scene:
    """Particles, meshes and materials of a DEM scene."""

    case: object  # the validated case model
    positions: np.ndarray  # (n,3) m
    radii: np.ndarray  # (n,) m
    meshes: dict[str, MeshPart]
    timestep: float  # s

    @property
    def n_particles(self) -> int:
        """Number of balls."""
        return len(self.radii)

    def write_meshes(self, directory: Path) -> dict[str, Path]:
        """Write each mesh as STL into directory; returns name -> path."""
        paths = {}
        for name, part in self.meshes.items():
            path = Path(directory) / f"{name}.stl"
            part.mesh.export(path)
            paths[name] = path
        return paths


def critical_timestep(case, stiffness_scale: float | None = None) -> float:
    """Rayleigh step of the smallest ball with the media material at a stiffness scale
    (default numerics.stiffness_scale), s."""
    media = case.media
    r_min = media.radius - (2.0 if media.distribution == "normal" else 1.0) * media.radius_spread
    scale = case.numerics.stiffness_scale if stiffness_scale is None else stiffness_scale
    return rayleigh_timestep(r_min, case.materials[media.material], scale)


def settling_timestep(case) -> float:
    """Time step while a drag-finishing bed settles and the rod goes in, s (the process uses Scene.timestep)."""
    return case.settling_timestep_factor * critical_timestep(case, case.settling_stiffness_scale)


def build_drag_finishing(case) -> Scene:
    """Bowl and rod meshes and the seeded particle cloud of a drag-finishing case.

    The rod starts parked with its tip above the highest ball of the cloud, at
    angle 0 of its path (x = path_radius, y = 0); engines lower it into the bed
    after settling.
    """
    rng = np.random.default_rng(case.case.seed)
    media = case.media
    radii = draw_radii(rng, media.count, media.radius, media.radius_spread, media.distribution)
    positions = random_cloud_in_cylinder(rng, radii, case.bowl.inner_radius, z_bottom=0.0)
    bowl = bowl_mesh(case.bowl.inner_radius, case.bowl.height, case.bowl.segments)
    wp = case.workpiece
    rod = load_stl(wp.mesh) if wp.mesh is not None else rod_mesh(wp.radius, wp.length, wp.segments)
    top = float(np.max(positions[:, 2] + radii))
    rod.apply_translation([wp.path_radius, 0.0, top + media.radius])
    meshes = {
        "bowl": MeshPart("bowl", bowl, case.bowl.material),
        "rod": MeshPart("rod", rod, wp.material),
    }
    dt = case.numerics.timestep_factor * critical_timestep(case)
    return Scene(case=case, positions=positions, radii=radii, meshes=meshes, timestep=dt)


def bed_weight(scene: Scene) -> float:
    """Weight of all particles, N."""
    rho = scene.case.materials[scene.case.media.material].density
    return float(np.sum(4.0 / 3.0 * math.pi * scene.radii**3) * rho * -GRAVITY[2])
