"""Removed material: failed particles (damage >= 1) that separated from the workpiece, and the chips they form.
Positions in m."""

from __future__ import annotations

import numpy as np

#: A failed particle with no unfailed one within this many dx has separated; chips link at this distance too.
REACH = 1.5

#: The measured quantities of the removal (a kind's QUANTITIES takes them): name -> (SI unit, meaning).
REMOVAL_QUANTITIES: dict[str, tuple[str, str]] = {
    "failed_count": ("-", "particles of the solid with damage >= 1 at the end"),
    "removed_count": ("-", f"failed particles with no unfailed or held one within {REACH} dx at the end"),
    "removed_volume": ("m^3", "removed_count dx^3"),
}


def removed(positions: np.ndarray, damage: np.ndarray, attached: np.ndarray, dx: float) -> np.ndarray:
    """Mask of the removed particles: failed (damage >= 1) and no attached particle (unfailed or held: `attached`
    True) within REACH dx. positions (n, 3) m, damage (n,) -."""
    from scipy.spatial import cKDTree

    failed = damage >= 1.0
    out = np.zeros(len(positions), dtype=bool)
    if not failed.any():
        return out
    anchors = positions[attached & ~failed]
    if not len(anchors):
        out[failed] = True
        return out
    distance, _ = cKDTree(anchors).query(positions[failed], k=1)
    out[np.flatnonzero(failed)] = distance > REACH * dx
    return out


def chips(positions: np.ndarray, dx: float) -> np.ndarray:
    """The chip label (0, 1, ...) of each of the particles (n, 3) m: connected clusters linked within REACH dx."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    if not len(positions):
        return np.zeros(0, dtype=int)
    pairs = cKDTree(positions).query_pairs(REACH * dx, output_type="ndarray")
    n = len(positions)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    return connected_components(graph, directed=False)[1]
