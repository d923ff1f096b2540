"""`orchestrator analyze` of a feed-scene run: the flows through the nozzle ring and the tube with their balances,
the sensor pressures B, C1, C2 beside the 1D network at the state the scene's boundaries carry (network.py),
the series (series.png), the comparison (comparison.png) and, with render, sections at the picture times. Flows in
l/min, pressures in bar (gauge) in the table."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.drill.series import run_series, sensor_pressures
from orchestrator.kinds.ejector_feed.flows import feed_flows, gap_storage, steady_means, tube_slab_flows
from orchestrator.kinds.ejector_feed.layout import feed_layout
from orchestrator.kinds.ejector_feed.network import feed_boundary, gap_pressure_below_feed
from orchestrator.kinds.ejector_feed.pictures import draw_run_pictures
from orchestrator.reference.drill_network import LITRE_PER_MIN

def _fmt(value) -> str:
    return f"{value:10.4g}" if isinstance(value, float) and math.isfinite(value) else f"{'-':>10}"


def feed_rows(case, means: dict, pressures: dict) -> list:
    """Rows (quantity, unit, SPH, network at scene.network_flow, note): flows in l/min, the nozzles' share in %,
    gauge pressures in bar; the held outlet pressures for reference."""
    layout = feed_layout(case)
    boundary = feed_boundary(case, layout.z_nozzles - layout.outlets["gap"].center[2])
    net, state = case.network(), boundary.state
    rows = []
    for name, key, note in (("V_total", "V_total", "the feed inlet's inflow (held)"),
                            ("V_AG", "V_AG", "gap, at C1 (discs AG_all + IB)"),
                            ("V_EN", "V_EN", "the nozzles' discs"),
                            ("V_IB", "V_IB_slab", "tube, at C1 (frames' slab; the inlet holds it)"),
                            ("V_mixed", "V_mixed_slab", "tube, at C2 (frames' slab)")):
        value = means.get(key, math.nan)
        network = state.V_IB + state.V_EN if name == "V_mixed" else getattr(state, name)
        rows.append((name, "l/min", value / LITRE_PER_MIN, network / LITRE_PER_MIN, note))
    rows.append(("V_EN / V_total", "%", 100 * means.get("EN_share", math.nan), 100 * state.V_EN / state.V_total, ""))
    b_bar = gap_pressure_below_feed(net, state, case.scene.c1_distance) / 1e5
    rows.append(("p_B", "bar", pressures.get("B", math.nan) / 1e5, b_bar,
                 f"gap, {case.scene.c1_distance * 1e3:g} mm below the nozzles (network: there)"))
    rows.append(("p_C1", "bar", pressures.get("C1", math.nan) / 1e5, state.gauge_bar("p_C1"),
                 f"tube axis, {case.scene.c1_distance * 1e3:g} mm before the nozzles"))
    rows.append(("p_C2", "bar", pressures.get("C2", math.nan) / 1e5, state.gauge_bar("p_C2"),
                 f"SPH: {case.scene.c2_distance * 1e3:g} mm behind; network: end of mixing "
                 f"({net.mixing_length * 1e3:g} mm)"))
    rows.append(("p_C2 - p_C1", "bar", (pressures.get("C2", math.nan) - pressures.get("C1", math.nan)) / 1e5,
                 state.gauge_bar("p_C2") - state.gauge_bar("p_C1"), "the jets' pressure rise"))
    rows.append(("p gap outlet", "bar", math.nan, boundary.gap_outlet_pressure / 1e5, "held by the SPH's gap outlet"))
    rows.append(("p tube outlet", "bar", math.nan, boundary.tube_outlet_pressure / 1e5, "held: the network's p_C2"))
    return rows


def analyze_feed_run(run_dir, run: dict, case, render: bool = True) -> dict:
    """Print the feed run's flows, balances and pressures beside the network; write series.png, comparison.png and
    (render) section_<t>.png. Returns {name: path}."""
    run_dir = Path(run_dir)
    series, time = run_series(run_dir, run, case)
    if time.size < 2:
        return {}
    flows = feed_flows(series)
    means = steady_means(time, flows)
    frames = run.get("frames", {})
    listed = [(float(frames[k]["attrs"]["time"]), frames[k]) for k in sorted((k for k in frames if k != "attrs"),
                                                                              key=int)]
    means.update(tube_slab_flows(listed, case, feed_layout(case)))
    pressures = sensor_pressures(series, time)
    total = means.get("V_total", math.nan)
    slab_residual = (means.get("V_IB_slab", math.nan) + means.get("V_EN", math.nan)
                     - means.get("V_mixed_slab", math.nan)) / total
    print(f"\nover the last 20 % of the run ({time[-1] * 0.8e3 + time[0] * 0.2e3:.3g}-{time[-1] * 1e3:.3g} ms): "
          f"eq. 1 V_total - V_AG - V_EN = {means['residual_eq1_share'] * 100:.3g} % of V_total; the tube's "
          f"V_IB + V_EN - V_mixed = {means['residual_tube_share'] * 100:.3g} % of V_total by the discs (quantised by "
          f"whole layers: kinds/ejector_feed/flows.py), {slab_residual * 100:.3g} % by the frames' slabs")
    stored = gap_storage(listed, case, feed_layout(case))
    if math.isfinite(stored):
        print(f"eq. 1's control volume (the gap above C1 with the nozzles) stores {stored / total * 100:.3g} % of "
              f"V_total (frames {case.output.frame_interval * 1e3:g} ms apart): the residual less the storage is "
              f"{(means['residual_eq1_share'] - stored / total) * 100:.3g} %")
    rows = feed_rows(case, means, pressures)
    print(f"\n{'quantity':<16}{'unit':>6}{'SPH':>10}{'network':>10}  (network at {case.scene.network_flow:g} l/min: "
          "the state the inlets and outlets carry)")
    for name, unit, a, b, note in rows:
        print(f"{name:<16}{unit:>6}{_fmt(a)}{_fmt(b)}  {note}")
    outputs = draw_run_pictures(run_dir, case, time, flows, series, rows, run.get("frames", {}), render)
    for name, path in outputs.items():
        print(f"{name:<14} {path}")
    return outputs


def measure_feed(case, result) -> dict[str, float]:
    """Measured quantities of a feed-scene run (SI units): the steady means of steady_means, p_B, p_C1, p_C2 (gauge,
    Pa), the tube's flows from the frames (tube_slab_flows), max_density_deviation (-). Empty when the run recorded fewer than two series records."""
    time = np.asarray(result.time if result.time is not None else [], dtype=float)
    if time.size < 2:
        return {}
    series = {k: v.values for k, v in result.series.items()}
    out = steady_means(time, feed_flows(series))
    out.update({f"p_{k}": v for k, v in sensor_pressures(series, time).items()})
    out.update(tube_slab_flows(result.frames, case, feed_layout(case)))
    if "max_density_deviation" in series:
        out["max_density_deviation"] = float(np.nanmax(series["max_density_deviation"]))
    return out
