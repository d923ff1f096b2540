"""Triangle meshes read from files (STL, OBJ, PLY, OFF) with trimesh, in m; a kind builds its own parts' meshes
in its scene module."""

from __future__ import annotations

import numpy as np
import trimesh


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
