"""What a channel run measured (run.h5 /measured) from the grain's series, the flow plane and the workpiece's
frames. Lengths in m, forces in N, temperatures in K; z from the bottom wall's face.

Definitions (dx the spacing; the edge is the line x = workpiece.front, z = workpiece.height across y):
- the workpiece's particles are the moving ones that start inside its box (the first frame);
- edge penetration: the most the grain's sphere reached past the edge line, R - (distance from its centre to the
  line), over the series records (negative: it never touched the edge itself);
- contact: the grain's contact force series (eq. G8, all of it from the workpiece: the grain has no other
  contact), its largest magnitude, its impulse (the time integral of the magnitude) and how long it is non-zero;
- removed particles: failed ones (damage >= 1) with no unfailed workpiece particle or wall particle within REACH
  dx at the end (kinds/sph_flow/removal.py; the medium's particles do not hold them); their volume is count dx^3;
- the surface: at the lattice's columns (x, y) of the workpiece's top row, the highest remaining workpiece particle
  within SAMPLE dx horizontally; edge drop: the most a column of the two front columns came down; lowered volume:
  the sum over all columns of how far they came down, times dx^2 (the deburred volume, removed particles in it);
- the flow rate: the medium's volume crossing the flow plane upstream of the grain, the mean over the run's second
  half, against the empty channel's plane Poiseuille rate f H^3 W / (12 nu) and lubrication theory's rate past
  the workpiece (two plane channels in series, lubrication_rate).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.kinds.afm_channel.medium import flow_rate
from orchestrator.kinds.afm_channel.pictures import plot_panels, plot_series
from orchestrator.kinds.afm_channel.scene import GRAIN, SECTION, workpiece_mask
from orchestrator.kinds.sph_flow.removal import REMOVAL_QUANTITIES, removed
from orchestrator.kinds.base import print_run_measures

#: The surface's height at a column is the highest remaining particle within this many dx of it horizontally.
SAMPLE = 0.75
#: Plastic strain above which a particle counts as plastically deformed (the 0.2 % offset of a yield stress).
PLASTIC = 0.002

#: The measured quantities: name -> (SI unit, meaning).
QUANTITIES: dict[str, tuple[str, str]] = {
    "grain_travel": ("m", "the grain's centre's displacement along x over the run"),
    "grain_speed_max": ("m/s", "the grain's largest speed"),
    "grain_speed_mean": ("m/s", "grain_travel over the run's duration"),
    "grain_turn": ("rad", "the grain's rotation about y over the run (the time integral of omega_y)"),
    "edge_penetration": ("m", "the most the grain's sphere reached past the edge line (negative: clear of it)"),
    "contact_force_max": ("N", "the largest magnitude of the contact force on the grain over every step"),
    "contact_impulse": ("N s", "the magnitude of the contact force's time integral (the momentum it gave the grain)"),
    "contact_time": ("s", "how long the contact force is non-zero"),
    "max_plastic_strain": ("-", "the largest equivalent plastic strain in the workpiece at the end"),
    "plastic_volume": ("m^3", f"the workpiece's volume with plastic strain above {PLASTIC} at the end"),
    "max_temperature": ("K", "the highest temperature in the workpiece over the frames"),
    **REMOVAL_QUANTITIES,
    "edge_drop": ("m", "the most a surface column of the two front columns came down"),
    "lowered_volume": ("m^3", "the sum of the surface columns' descents times dx^2"),
    "flow_rate": ("m^3/s", "the medium's flow rate through the plane upstream, mean over the second half"),
    "flow_rate_empty": ("m^3/s", "the empty channel's plane Poiseuille rate f H^3 W / (12 nu) (a PTT medium: its "
                        "developed flow's, medium.py)"),
    "flow_rate_lubrication": ("m^3/s", "lubrication theory's rate past the workpiece (analysis.lubrication_rate)"),
}


def _series(result, name: str) -> np.ndarray | None:
    return np.asarray(result.series[name].values, dtype=float) if name in result.series else None


def grain_quantities(case, result) -> dict[str, float]:
    """The grain's travel, speeds, turn and its reach past the edge, from its series."""
    t = np.asarray(result.time, dtype=float)
    x = _series(result, f"grain_{GRAIN}_position")
    v = _series(result, f"grain_{GRAIN}_velocity")
    w = _series(result, f"grain_{GRAIN}_angular_velocity")
    if x is None or v is None or len(t) < 2:
        return {}
    wall, r = case.channel.wall_layers * case.numerics.dx, 0.5 * case.grain.diameter
    edge = np.array([case.workpiece.front, wall + case.workpiece.height])
    reach = r - np.hypot(x[:, 0] - edge[0], x[:, 2] - edge[1])
    out = {"grain_travel": float(x[-1, 0] - x[0, 0]), "grain_speed_max": float(np.linalg.norm(v, axis=1).max()),
           "grain_speed_mean": float((x[-1, 0] - x[0, 0]) / (t[-1] - t[0])), "edge_penetration": float(reach.max())}
    if w is not None:
        out["grain_turn"] = float(np.trapezoid(w[:, 1], t))
    return out


def contact_quantities(result) -> dict[str, float]:
    """The contact force's peak, impulse (magnitude of its time integral) and duration: over every step from the
    engine's interval series (contact_peak, contact_impulse, contact_time); from the sampled force where a run has
    none."""
    peak = _series(result, f"grain_{GRAIN}_contact_peak")
    if peak is not None and len(peak):
        impulse = np.sum(_series(result, f"grain_{GRAIN}_contact_impulse"), axis=0)
        return {"contact_force_max": float(np.max(peak)), "contact_impulse": float(np.linalg.norm(impulse)),
                "contact_time": float(np.sum(_series(result, f"grain_{GRAIN}_contact_time")))}
    f = _series(result, f"grain_{GRAIN}_contact")
    t = np.asarray(result.time, dtype=float)
    if f is None or len(t) < 2:
        return {}
    size = np.linalg.norm(f, axis=1)
    on = size > 0.0
    steps = np.diff(t)
    return {"contact_force_max": float(size.max()), "contact_impulse": float(np.trapezoid(size, t)),
            "contact_time": float(np.sum(steps[on[1:] | on[:-1]]))}


def surface_columns(case, x0: np.ndarray, x: np.ndarray, keep: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(the workpiece's top-row columns (k, 2) x, y in m, how far each came down (k,) m) from its start x0 and end
    x (n, 3) and the mask of its remaining particles at the end."""
    from scipy.spatial import cKDTree

    dx = case.numerics.dx
    top0 = x0[:, 2].max()
    columns = x0[x0[:, 2] > top0 - 0.5 * dx][:, :2]
    near = cKDTree(x[keep, :2]).query_ball_point(columns, SAMPLE * dx)
    z = x[keep, 2]
    top = np.array([z[i].max() if len(i) else -np.inf for i in near])
    return columns, np.maximum(top0 - top, 0.0)


def workpiece_quantities(case, first: dict, last: dict, frames) -> dict[str, float]:
    """Plastic strain, heating, failure and removal, the edge's drop and the lowered volume."""
    dx = case.numerics.dx
    mine = workpiece_mask(case, first)
    if not mine.any():
        return {}
    x0 = np.asarray(first["positions"], dtype=float)
    x = np.asarray(last["positions"], dtype=float)
    damage = np.asarray(last.get("damage", np.zeros(len(x))), dtype=float)
    attached = mine | (np.asarray(last["kind"]) == 1)  # the workpiece and the walls, not the medium or the grain
    gone = removed(x, np.where(mine, damage, 0.0), attached, dx) & mine
    columns, drop = surface_columns(case, x0[mine], x[mine], ~gone[mine])
    front = columns[:, 0] < case.workpiece.front + 2.0 * dx
    out = {"failed_count": float(np.sum((damage >= 1.0) & mine)), "removed_count": float(gone.sum()),
           "removed_volume": float(gone.sum()) * dx**3, "edge_drop": float(drop[front].max()),
           "lowered_volume": float(np.sum(drop[np.isfinite(drop)])) * dx**2}
    if "plastic_strain" in last:
        eps = np.asarray(last["plastic_strain"], dtype=float)[mine]
        out["max_plastic_strain"] = float(eps.max())
        out["plastic_volume"] = float(np.sum(eps > PLASTIC)) * dx**3
    temperatures = [float(np.asarray(f["temperature"], dtype=float)[mine].max()) for _, f in frames
                    if "temperature" in f and len(f["temperature"]) == len(mine)]
    if temperatures:
        out["max_temperature"] = max(temperatures)
    return out


def lubrication_rate(case) -> float:
    """The medium's flow rate by lubrication theory, m^3/s: the cell as two plane channels in series, the gap H
    over the free length and H - h over the workpiece and its support (l), each of resistance 12 eta l / (W H^3),
    driven by the pressure difference rho f L the body force makes over the cell; without the grain, the step's
    entrance and exit losses or the flow's turning (they lower the rate). A PTT medium: the same two channels with
    its steady shear law (medium.cell_flow)."""
    m, c, w = case.medium, case.channel, case.workpiece
    if m.modes:
        return case.cell().flow_rate * c.width
    blocked = case.support_end() - w.front
    resistance = (c.length - blocked) / c.gap**3 + blocked / (c.gap - w.height)**3
    return m.density * m.body_force * c.length * c.width / (12.0 * m.viscosity * resistance)


def flow_quantities(case, result) -> dict[str, float]:
    """The medium's mean flow rate over the run's second half, the empty channel's and the lubrication estimate."""
    m, c = case.medium, case.channel
    empty = m.body_force * m.density * c.gap**3 * c.width / (12.0 * m.viscosity)
    if m.modes:
        empty = flow_rate(m.law(), c.gap, m.density * m.body_force) * c.width
    out = {"flow_rate_empty": empty, "flow_rate_lubrication": lubrication_rate(case)}
    q = _series(result, f"flow_rate_{SECTION}")
    if q is not None and len(q) >= 4:
        out["flow_rate"] = float(np.mean(q[len(q) // 2:]))
    return out


def measure_channel(case, result) -> dict[str, float]:
    """Measured quantities of a channel run (QUANTITIES); empty without its series."""
    if f"grain_{GRAIN}_position" not in result.series or len(result.time) < 2:
        return {}
    measured = grain_quantities(case, result) | contact_quantities(result) | flow_quantities(case, result)
    if len(result.frames) >= 2:
        measured |= workpiece_quantities(case, result.frames[0][1], result.frames[-1][1], result.frames)
    return {k: v for k, v in measured.items() if math.isfinite(v)}


def analyze_channel_run(run_dir: Path, run: dict, case, render: bool = True) -> dict:
    """Print the measured quantities (QUANTITIES) and write channel.png (Fig. 5's three panels) and
    channel_series.png (the grain, the contact and the flow over time). Returns {name: path}."""
    print_run_measures(run_dir, run, QUANTITIES)
    if not render:
        return {}
    paths = {"panels": plot_panels(run, case, Path(run_dir) / "channel.png"),
             "series": plot_series(run, case, Path(run_dir) / "channel_series.png")}
    for name, path in paths.items():
        print(f"{'picture ' + name:<24} {path}")
    return paths
