"""What a feed-scene run measures (layout.py): V_total (the feed inlet's inflow), V_EN (the discs across the
nozzles), V_AG (the discs at C1: AG_all over the gap and the tube, -z, plus IB over the tube, +z), V_IB (IB, and
the tube inlet's inflow), the mixed flow behind the nozzles; eq. 1 (V_total = V_AG + V_EN) and the tube's balance
(V_IB + V_EN = V_mixed) as residuals; the sensor pressures B, C1, C2. SI units (m^3/s, Pa gauge, s).

The tube's discs count particles crossing them, and at 3.7-5.5 m/s a whole lattice layer of the bore (201 mm^2 x dx,
1,800 particles at dx = 1/3 mm) crosses every 60-90 us, together while the lattice is still ordered: over a window
of 50 us their mean is quantised by +-80 l/min. The tube's flows are therefore also taken from the frames, as the
volume flux sum (m / rho) v_z / (2 w) of the fluid in a slab of half-width w around C1 and C2 (tube_slab_flows)."""

from __future__ import annotations

import math

import numpy as np

from orchestrator.drill.series import STEADY_FRACTION, steady_window


def feed_flows(series: dict) -> dict[str, np.ndarray]:
    """V_total, V_AG, V_EN, V_IB, V_IB_in, V_mixed, V_gap_out, V_tube_out (m^3/s) from the run's series (the ones
    present)."""
    def get(name):
        return np.asarray(series[name], dtype=float) if name in series else None

    out = {}
    for key, name in (("V_total", "inflow_feed_inlet"), ("V_IB_in", "inflow_tube_inlet"), ("V_IB", "flow_rate_IB"),
                      ("V_mixed", "flow_rate_mixed"), ("V_gap_out", "outflow_gap_outlet"),
                      ("V_tube_out", "outflow_tube_outlet")):
        if get(name) is not None:
            out[key] = get(name)
    if get("flow_rate_AG_all") is not None and "V_IB" in out:  # AG_all counts the tube's +z flow negative
        out["V_AG"] = get("flow_rate_AG_all") + out["V_IB"]
    nozzles = [get(n) for n in sorted(series) if n.startswith("flow_rate_nozzle")]
    if nozzles:
        out["V_EN"] = np.sum(nozzles, axis=0)
    return out


def steady_means(time: np.ndarray, flows: dict) -> dict[str, float]:
    """Each flow's mean over the last STEADY_FRACTION of the run (m^3/s), the nozzles' share V_EN / V_total (-),
    eq. 1's residual V_total - V_AG - V_EN and the tube's V_IB + V_EN - V_mixed (m^3/s) with their shares of
    V_total (-)."""
    window = steady_window(time)
    out = {k: float(np.nanmean(v[window])) for k, v in flows.items()}
    total = out.get("V_total", math.nan)
    out["EN_share"] = out.get("V_EN", math.nan) / total if total else math.nan
    out["residual_eq1"] = total - out.get("V_AG", math.nan) - out.get("V_EN", math.nan)
    out["residual_tube"] = out.get("V_IB", math.nan) + out.get("V_EN", math.nan) - out.get("V_mixed", math.nan)
    for key in ("residual_eq1", "residual_tube"):
        out[key + "_share"] = out[key] / total if total else math.nan
    return out


def slab_flow(arrays: dict, mass: float, z: float, half_width: float, radius: float) -> float:
    """Volume flow (m^3/s) along +z through the bore at height z from one frame's arrays (positions, velocities,
    densities, kind): sum (m / rho) v_z over the fluid with r < radius and |z_i - z| < half_width, / (2 half_width)."""
    x = np.asarray(arrays["positions"], dtype=float)
    fluid = np.asarray(arrays["kind"]) == 0
    inside = fluid & (np.hypot(x[:, 0], x[:, 1]) < radius) & (np.abs(x[:, 2] - z) < half_width)
    v = np.asarray(arrays["velocities"], dtype=float)[inside, 2]
    return float(np.sum(mass / np.asarray(arrays["densities"], dtype=float)[inside] * v) / (2.0 * half_width))


def tube_slab_flows(frames, case, layout) -> dict[str, float]:
    """V_IB_slab and V_mixed_slab (m^3/s): slab_flow at C1 and C2 (half-width: 3/8 of c1_distance, clear of the
    nozzles' mouths, 0.6 mm from the ring) averaged over the frames (time s, arrays) in the last STEADY_FRACTION of
    the run; {} without such frames."""
    if not frames:
        return {}
    t_end = frames[-1][0]
    chosen = [a for t, a in frames if t >= t_end - STEADY_FRACTION * t_end and t > 0.0]
    if not chosen:
        return {}
    mass = case.fluid.density * case.numerics.dx ** 3
    half = 0.375 * case.scene.c1_distance
    out = {}
    for key, sensor in (("V_IB_slab", "C1"), ("V_mixed_slab", "C2")):
        z = layout.sensors[sensor][2]
        out[key] = float(np.mean([slab_flow(a, mass, z, half, layout.tube.r_out) for a in chosen]))
    return out


def gap_storage(frames, case, layout) -> float:
    """d/dt (m^3/s) of the fluid volume sum m / rho above C1 outside the bore (the gap with the nozzles, eq. 1's
    control volume, and whatever fluid sits in the walls' layer between their surface and their particles), between
    the first and the last frame of the last STEADY_FRACTION of the run (NaN with fewer than two)."""
    t_end = frames[-1][0] if frames else 0.0
    chosen = [(t, a) for t, a in frames if t >= t_end - STEADY_FRACTION * t_end]
    if len(chosen) < 2:
        return math.nan
    mass, z = case.fluid.density * case.numerics.dx ** 3, layout.sensors["C1"][2]

    def volume(arrays):
        x = np.asarray(arrays["positions"], dtype=float)
        inside = (np.asarray(arrays["kind"]) == 0) & (x[:, 2] > z) & (np.hypot(x[:, 0], x[:, 1]) > layout.tube.r_out)
        return float(np.sum(mass / np.asarray(arrays["densities"], dtype=float)[inside]))

    (t0, a0), (t1, a1) = chosen[0], chosen[-1]
    return (volume(a1) - volume(a0)) / (t1 - t0)
