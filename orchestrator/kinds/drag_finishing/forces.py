"""The force on the rod in the process phase: its statistics after the start-up transient (mean, standard
deviation, block-averaged standard error) and the peak contact forces of a network snapshot, in N."""

from __future__ import annotations

import math

import numpy as np

#: The phase code of the process (the rod dragged through the settled bed) in the engines' phase series.
PROCESS_PHASE = 3


def force_statistics(process_time: np.ndarray, force: np.ndarray, transient_time: float) -> dict[str, float]:
    """Mean and std (N) of the three workpiece-frame components for process_time >= transient_time (s)."""
    keep = (process_time >= transient_time) & np.all(np.isfinite(force), axis=1)
    stats = {"n_samples": int(keep.sum())}
    for i, name in enumerate(("fn", "ft", "fv")):
        values = force[keep, i]
        stats[f"{name}_mean"] = float(values.mean()) if values.size else math.nan
        stats[f"{name}_std"] = float(values.std(ddof=1)) if values.size > 1 else math.nan
    return stats


def standard_error(values: np.ndarray, blocks: int = 10) -> float:
    """Standard error of the mean of a correlated series by block averaging, in its units.

    The series is cut into `blocks` equal blocks; the error is the standard
    deviation of the block means over sqrt(blocks). Valid while a block is
    longer than the correlation time (about 0.05 s for the force on the rod
    in the quick preset: 10 blocks need 0.5 s of data; shorter windows
    understate the error). nan with fewer than 2 samples per block.
    """
    n = len(values) // blocks
    if n < 2:
        return math.nan
    means = np.asarray(values[: n * blocks], dtype=float).reshape(blocks, n).mean(axis=1)
    return float(means.std(ddof=1) / math.sqrt(blocks))


def contact_force_peaks(contacts) -> dict[str, float]:
    """Largest and 99th-percentile normal contact force (N) in the last interaction-network snapshot."""
    if not contacts:
        return {}
    forces = np.asarray(contacts[-1][1]["normal_force"], dtype=float)
    if forces.size == 0:
        return {}
    return {"contact_fn_max": float(forces.max()), "contact_fn_p99": float(np.percentile(forces, 99))}


def process_series(time: np.ndarray, phase: np.ndarray, force: np.ndarray, process_start: float):
    """(process time s, workpiece force N) of the process phase only."""
    sel = phase == PROCESS_PHASE
    return time[sel] - process_start, force[sel]
