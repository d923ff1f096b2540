"""The flow-exit and drill-head scenes' walls: fixed boundary particles (drill/walls.boundary_particles) inside the
drill's solids, the workpiece, the head with its adduction holes and the cutting edges' chip mouths cut out and its
guide pads and cutting edges' blades added (head.py), the outer and the inner tube, each tested in closed form on its
(r, z) polygon or sectors, or with trimesh where a user's mesh replaces it ([parts]). SI units."""

from __future__ import annotations

import numpy as np

from orchestrator.drill.regions import Hole
from orchestrator.drill.walls import WallParticles, boundary_particles, in_solid
from orchestrator.kinds.ejector_drill.head import edge_mouths, edge_solids, pad_solids

#: The parts that are walls (the passages are cut out of the head; the nozzles are at the feed, outside both
#: scenes).
WALL_PARTS = ("workpiece", "head", "outer_tube", "inner_tube")


def solid_masks(points: np.ndarray, case, layout, cut_meshes: dict | None = None) -> dict[str, np.ndarray]:
    """part name -> mask of the points (n, 3) m inside that solid (the head with its pads and blades, without its
    holes and chip mouths); a part replaced by a
    user mesh is tested with trimesh's `contains` (cut_meshes: name -> trimesh, build.wall_meshes; it needs rtree,
    which the environment may lack: the case refuses user meshes with boundary-particle walls)."""
    eps = 1e-6 * case.numerics.dx
    profiles = case.geometry().profiles()
    out = {}
    for name in WALL_PARTS:
        if name in case.parts:
            mesh = (cut_meshes or {}).get(name)
            out[name] = mesh.contains(points) if mesh is not None else np.zeros(len(points), dtype=bool)
        else:
            out[name] = in_solid(points, profiles[name], eps)
    holes = [r for r in layout.regions if isinstance(r, Hole)]
    for solid in (*pad_solids(case), *edge_solids(case)):
        out["head"] |= solid.contains(points)
    for hole in (*holes, *edge_mouths(case)):  # cut out of the head (a hole from the gap's outer wall out)
        out["head"] &= ~hole.contains(points)
    return out


def drill_boundary_particles(case, layout, cut_meshes: dict | None = None) -> WallParticles:
    """The scene's boundary particles: lattice sites in WALL_PARTS (solid_masks), outside the wetted regions, within
    2h of them, each with its wall point."""
    return boundary_particles(case, layout, WALL_PARTS, lambda sites: solid_masks(sites, case, layout, cut_meshes))
