"""Scenes: particles, meshes and materials built once from a case, fed to every engine."""

from .build import MeshPart, Scene, bed_weight, build_scene

__all__ = ["MeshPart", "Scene", "bed_weight", "build_scene"]
