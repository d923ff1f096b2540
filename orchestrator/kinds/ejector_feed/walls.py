"""The feed scene's walls: fixed boundary particles (drill/walls.boundary_particles, the same lattice, reach and
closed-form wall points as the drill kind's) inside its two solids, the outer tube (the gap's outer wall, carried on
into the feed chamber: layout.py) and the inner tube with the nozzles drilled through it. The wall points of the
nozzles' walls are layout.Nozzle.nearest (a tilted cylinder); SI units (m)."""

from __future__ import annotations

import numpy as np

from orchestrator.drill.walls import WallParticles, boundary_particles

#: The feed scene's solids (FeedLayout.solids).
FEED_PARTS = ("outer_tube", "inner_tube")


def feed_solid_masks(points: np.ndarray, layout, eps: float) -> dict[str, np.ndarray]:
    """part -> mask of the points (n, 3) m inside it: the solids' rings (a point within eps of a face counted in),
    the inner tube less its nozzles."""
    r, z = np.hypot(points[:, 0], points[:, 1]), points[:, 2]
    out = {}
    for name in FEED_PARTS:
        ring = layout.solids[name]
        out[name] = (r >= ring.r_in - eps) & (r <= ring.r_out + eps) & (z >= ring.z_lo) & (z <= ring.z_hi)
    for nozzle in layout.nozzles:
        out["inner_tube"] &= ~nozzle.contains(points)
    return out


def feed_boundary_particles(case, layout) -> WallParticles:
    """The feed scene's boundary particles: lattice sites in the solids, outside the wetted regions, within 2h of
    them, each with its wall point (the nearest point of the wetted regions)."""
    eps = 1e-6 * case.numerics.dx
    return boundary_particles(case, layout, FEED_PARTS, lambda sites: feed_solid_masks(sites, layout, eps))


def feed_wall_meshes(layout, sections: int = 96) -> dict:
    """name -> trimesh of the feed scene's solids (for pictures): the rings of layout.solids, the inner tube with
    the nozzles cut (manifold3d; each nozzle a cylinder carried 1 mm beyond both faces, so no face is shared)."""
    import trimesh

    out = {}
    for name, ring in layout.solids.items():
        mesh = trimesh.creation.annulus(r_min=ring.r_in, r_max=ring.r_out, height=ring.z_hi - ring.z_lo,
                                        sections=sections)
        mesh.apply_translation((0.0, 0.0, 0.5 * (ring.z_lo + ring.z_hi)))
        out[name] = mesh
    cutters = []
    for nozzle in layout.nozzles:
        lo, hi = nozzle.span(1e-3)
        cutters.append(trimesh.creation.cylinder(radius=0.5 * nozzle.d, sections=32, segment=[
            nozzle.base + lo * nozzle.axis, nozzle.base + hi * nozzle.axis]))
    out["inner_tube"] = out["inner_tube"].difference(trimesh.util.concatenate(cutters), engine="manifold")
    return out
