"""Triangle meshes of the machine parts, built with trimesh from case parameters (m)."""

from __future__ import annotations

import numpy as np
import trimesh


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


def load_stl(path) -> trimesh.Trimesh:
    """An STL file as a single triangle mesh (m)."""
    return read_mesh(path, "the workpiece mesh")


def read_mesh(path, what: str = "the mesh file") -> trimesh.Trimesh:
    """A mesh file (STL, OBJ, PLY, OFF) as one triangle mesh; ValueError naming `what` and the file when it
    cannot be read or holds no triangles."""
    try:
        mesh = trimesh.load(path, force="mesh")
    except Exception as exc:  # noqa: BLE001 - trimesh raises many kinds on a file that is not a mesh
        raise ValueError(f"cannot read {what} {path}: {type(exc).__name__}: {exc}"[:300]) from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise ValueError(f"{what} {path} holds no triangles")
    if not np.all(np.isfinite(mesh.vertices)):
        raise ValueError(f"{what} {path} has vertices that are not finite numbers")
    return mesh
