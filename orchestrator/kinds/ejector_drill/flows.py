"""What an ejector-drill SPH run measures (paper eqs. 1-2, Fig. 5): the flows V_AG, V_IB, V_loss and the holes'
flow from the flow planes, the volume stored in the scene, the balance of eq. 2, the sensor pressures in bar, the
filling times and the ejector onset. Flows in m^3/s, pressures in Pa (gauge: the outlets hold gauge pressures),
times in s."""

from __future__ import annotations

import math

import numpy as np

from orchestrator.drill.series import STEADY_FRACTION


def less_back_pressure(series: dict, frames: dict, back: float) -> tuple[dict, dict]:
    """The series and frames with the scene's back pressure (Pa, `[scene] back_pressure`) taken off every pressure:
    the probes' (pressure_probe_*), the columns' chambers (column_pressure_*) and the frames' particles, so that
    they read as the gauge pressures of the flow without it. Unchanged when back is 0."""
    if not back:
        return series, frames
    shifted = {k: (np.asarray(v, dtype=float) - back if k.startswith(("pressure_probe_", "column_pressure_")) else v)
               for k, v in series.items()}
    moved = {k: (f if k == "attrs" else {**f, "pressures": np.asarray(f["pressures"], dtype=float) - back})
             for k, f in frames.items()}
    return shifted, moved


#: Beside the jets: at least this angle (rad) from every hole's axis (a Ø4 mm hole spans 8 degrees at the bore).
BESIDE_JETS = math.radians(30.0)


def pressure_beside_jets(layout, frame: dict) -> tuple[float, int]:
    """(mean gauge pressure Pa, particles) of the head clearance's fluid at the holes' height (within one hole
    radius of sensor A's z) and at least BESIDE_JETS from every hole's axis: the clearance's static pressure, the
    network's node A, which sensor A on a hole's axis (where its jet meets the bore) does not read. (NaN, 0) where
    the scene has no holes or no fluid there."""
    clearance = next((r for r in layout.regions if getattr(r, "name", "") == "head_clearance"), None)
    holes = [p for name, p in layout.planes.items() if name.startswith("hole")]
    if clearance is None or not holes:
        return math.nan, 0
    x = np.asarray(frame["positions"], dtype=float).reshape(-1, 3)
    fluid = np.asarray(frame["kind"]) == 0
    half = max(p.radius for p in holes)
    near = fluid & clearance.contains(x) & (np.abs(x[:, 2] - layout.sensors["A"][2]) <= half)
    angle = np.arctan2(x[:, 1], x[:, 0])
    for p in holes:
        off = np.abs(np.angle(np.exp(1j * (angle - math.atan2(p.normal[1], p.normal[0])))))
        near &= off >= BESIDE_JETS
    if not near.any():
        return math.nan, 0
    return float(np.mean(np.asarray(frame["pressures"], dtype=float)[near])), int(near.sum())


def flow_series(series: dict, time: np.ndarray) -> dict[str, np.ndarray]:
    """V_AG, V_IB, V_loss, V_holes, V_front, V_in, V_mouth_out, V_leak_out (m^3/s) against time from the run's
    series (flow_rate_<plane>, inflow_<inlet>, outflow_<outlet>); V_loss = rear + AG (the rear disc covers the gap,
    whose flow it counts negative). Missing series are absent."""
    def get(name):
        return np.asarray(series[name], dtype=float) if name in series else None

    out = {}
    ag, rear, ib = get("flow_rate_AG"), get("flow_rate_rear"), get("flow_rate_IB")
    if ag is not None:
        out["V_AG"] = ag
    if ib is not None:
        out["V_IB"] = ib
    if ag is not None and rear is not None:
        out["V_loss"] = rear + ag
    holes = [get(n) for n in sorted(series) if n.startswith("flow_rate_hole")]
    if holes:
        out["V_holes"] = np.sum(holes, axis=0)
    for key, name in (("V_front", "flow_rate_front"), ("V_in", "inflow_gap_inlet"), ("V_in", "inflow_clearance_inlet"),
                      ("V_mouth_out", "outflow_mouth"), ("V_leak_out", "outflow_leak")):
        if get(name) is not None:
            out[key] = get(name)
    if "V_AG" not in out and "V_in" in out:  # the drill-head scene: the inlet is the gap's flow
        out["V_AG"] = out["V_in"]
    return out


def spaced_frames(t_frames: np.ndarray, interval: float) -> np.ndarray:
    """Mask of the frames at least interval / 2 (s) after the last kept one: leaves out the extra frame a stopped
    (and resumed) run wrote at its stop, whose short interval would make a storage rate spike."""
    keep = np.zeros(len(t_frames), dtype=bool)
    last = -math.inf
    for i, t in enumerate(t_frames):
        if t - last >= 0.5 * interval:
            keep[i], last = True, t
    return keep


def stored_volume_rate(time: np.ndarray, volume: np.ndarray) -> np.ndarray:
    """d(volume)/dt, m^3/s, by central differences (one-sided at the ends) of a volume series (m^3)."""
    if len(time) < 2:
        return np.zeros_like(volume)
    return np.gradient(volume, time)


def balance(time: np.ndarray, flows: dict, stored: np.ndarray | None = None) -> dict[str, float]:
    """Eq. 2 over the steady window (the last STEADY_FRACTION of the run): V_AG, V_IB, V_loss (means, m^3/s),
    residual = V_AG - V_IB - V_loss (m^3/s), its share of V_AG (-), and with `stored` (d volume/dt of the fluid
    between the planes, m^3/s, at the same times) the share of V_AG still filling the scene (-)."""
    t_end = time[-1]
    window = time >= t_end - STEADY_FRACTION * (t_end - time[0])
    mean = {k: float(np.nanmean(v[window])) for k, v in flows.items() if k in ("V_AG", "V_IB", "V_loss", "V_in")}
    out = dict(mean)
    ag, ib, loss = mean.get("V_AG", math.nan), mean.get("V_IB", math.nan), mean.get("V_loss", 0.0)
    out["residual"] = ag - ib - loss
    out["residual_share"] = out["residual"] / ag if ag else math.nan
    if stored is not None:
        out["filling_share"] = float(np.nanmean(stored[window])) / ag if ag else math.nan
    return out


def window_balance(time: np.ndarray, flows: dict, t_frames: np.ndarray, volumes: np.ndarray) -> dict[str, float]:
    """Eq. 2 as volumes over the steady window's frames: from the first frame at or after the window's start (the
    last STEADY_FRACTION of the run) to the last frame, t_a..t_b (s). V_AG, V_IB, V_loss are the volumes (m^3) the
    planes counted over (t_a, t_b] (each series record is the mean flow since the one before, so the sum of rate x
    interval is exact), stored the change of the control volume's fluid volume between the two frames (m^3), and
    closure_share = (V_AG - V_IB - V_loss - stored) / V_AG (-): what neither the planes nor the storage account for.
    Empty when fewer than two frames lie in the window, or no series record or no inflow between them (a run's
    stop frame a few steps after its last regular one)."""
    if len(time) < 2 or len(t_frames) < 2:
        return {}
    tol = 1e-9 * (time[-1] - time[0])
    start = time[-1] - STEADY_FRACTION * (time[-1] - time[0])
    inside = np.nonzero(t_frames >= start - tol)[0]
    if len(inside) < 2:
        return {}
    t_a, t_b = float(t_frames[inside[0]]), float(t_frames[inside[-1]])
    step = np.diff(time, prepend=time[0])
    counted = (time > t_a + tol) & (time <= t_b + tol)
    if "V_AG" not in flows or not np.any(flows["V_AG"][counted]):
        return {}
    out = {"t_a": t_a, "t_b": t_b, "stored": float(volumes[inside[-1]] - volumes[inside[0]])}
    for key in ("V_AG", "V_IB", "V_loss"):
        out[key] = float(np.sum(flows[key][counted] * step[counted])) if key in flows else 0.0
    out["closure_share"] = (out["V_AG"] - out["V_IB"] - out["V_loss"] - out["stored"]) / out["V_AG"] \
        if out["V_AG"] else math.nan
    out["stored_share"] = out["stored"] / out["V_AG"] if out["V_AG"] else math.nan
    return out


def first_time(time: np.ndarray, values: np.ndarray, threshold: float) -> float:
    """First time (s) the series reaches `threshold` (NaN if never)."""
    hit = np.nonzero(np.asarray(values) >= threshold)[0]
    return float(time[hit[0]]) if hit.size else math.nan


def filling_times(time: np.ndarray, flows: dict) -> dict[str, float]:
    """Times (s): t_gap (fluid first crosses the holes' planes: the gap is full down to the holes), t_holes (the
    holes carry 90 % of V_AG: running full), t_front (fluid first reaches the plane ahead of the holes), t_mouth
    (first flow into the chip mouth), t_leak (first flow into the tube/bore clearance). NaN when it did not happen;
    thresholds are 1 % of the inflow's mean."""
    v_in = flows.get("V_AG")
    ref = float(np.nanmax(np.abs(v_in))) if v_in is not None and np.size(v_in) else 0.0
    small = 0.01 * ref
    out = {}
    if "V_holes" in flows:
        out["t_gap"] = first_time(time, flows["V_holes"], small)
        full = (flows["V_holes"] >= 0.9 * flows["V_AG"]) & (flows["V_holes"] > small) if "V_AG" in flows else None
        out["t_holes"] = first_time(time, full.astype(float), 0.5) if full is not None else math.nan
    for key, name in (("t_front", "V_front"), ("t_mouth", "V_IB"), ("t_leak", "V_loss")):
        if name in flows:
            out[key] = first_time(time, flows[name], small)
    return out


def ejector_onset(time: np.ndarray, flows: dict, after: float) -> float:
    """First time (s) after `after` (s) at which V_loss <= 0 (the ejector draws fluid from the cutting zone; NaN if
    never, or without V_loss)."""
    if "V_loss" not in flows or not math.isfinite(after):
        return math.nan
    hit = np.nonzero((time > after) & (flows["V_loss"] <= 0.0))[0]
    return float(time[hit[0]]) if hit.size else math.nan


#: A fluid particle slower than this share of the inflow speed is "still" (paper sect. 3.2: "areas with little to
#: zero fluid velocity"), -.
STILL_SHARE = 0.05
#: The share of fluid particles with the highest pressure that marks the zone of maximum pressure, -.
PEAK_SHARE = 0.01


def zones(layout, frame: dict, v_in: float) -> dict:
    """The zones the paper describes (sect. 3.2: little to zero velocity, maximum pressure) in one run.h5 frame:
    {'still': [(region, count, share of the region's particles, mean r m, mean z m), ...] for the fluid particles
    slower than STILL_SHARE v_in, largest count first; 'peak': (count, mean p Pa, max p Pa, region holding most,
    mean r m and z m of its particles among them) of the PEAK_SHARE of fluid particles with the highest pressure}. Only particles inside the
    layout's fluid regions count (not the open boundaries' buffers)."""
    fluid = np.asarray(frame["kind"]) == 0
    x = np.asarray(frame["positions"], dtype=float)[fluid]
    speed = np.linalg.norm(np.asarray(frame["velocities"], dtype=float)[fluid], axis=1)
    p = np.asarray(frame["pressures"], dtype=float)[fluid]
    label = np.full(len(x), -1)
    for k, region in enumerate(layout.regions):
        label[(label < 0) & region.contains(x)] = k
    inside = label >= 0
    x, speed, p, label = x[inside], speed[inside], p[inside], label[inside]
    r = np.hypot(x[:, 0], x[:, 1])
    still = []
    slow = speed < STILL_SHARE * v_in
    for k, region in enumerate(layout.regions):
        mine = label == k
        hit = mine & slow
        if hit.any():
            still.append((region.name, int(hit.sum()), float(hit.sum() / mine.sum()), float(r[hit].mean()),
                          float(x[hit, 2].mean())))
    still.sort(key=lambda row: -row[1])
    out = {"still": still}
    if len(p):
        n = max(1, int(round(PEAK_SHARE * len(p))))
        top = np.argsort(p)[-n:]
        most = np.bincount(label[top], minlength=len(layout.regions)).argmax()
        there = top[label[top] == most]
        out["peak"] = (n, float(p[top].mean()), float(p[top].max()), layout.regions[most].name,
                       float(r[there].mean()), float(x[there, 2].mean()))
    return out
