"""Geometry and particle helpers shared by the kinds' scene builders (meshes, seeded clouds)."""
