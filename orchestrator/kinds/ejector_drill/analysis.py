"""`orchestrator analyze` of an ejector-drill run: the flows and the balance of eq. 2 (with the volume still filling
the control volume), the sensor pressures, the filling times and the ejector onset, the SPH beside the 1D network
and the paper (table and comparison.png), the flow and pressure series (series.png) and, with render, the sectional
pictures at the case's picture times (pictures.py)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.drill.series import STEADY_FRACTION, run_series, sensor_pressures, steady_window
from orchestrator.kinds.ejector_drill.flows import (STILL_SHARE, balance, ejector_onset, filling_times, flow_series,
                                                       less_back_pressure, pressure_beside_jets, spaced_frames,
                                                       stored_volume_rate, window_balance, zones)
from orchestrator.kinds.ejector_drill.comparison import (comparison_rows, element_flows, elements_at_flow,
                                                         network_at_gap_flow, stored_volume)
from orchestrator.kinds.ejector_drill.head_flow import edge_flow, head_finding, pad_flow
from orchestrator.kinds.ejector_drill.layout import drill_layout
from orchestrator.kinds.ejector_drill.pictures import draw_run_pictures
from orchestrator.reference.drill_network import LITRE_PER_MIN, solve


#: The paper's mean time steps (sect. 4): flow-exit area over 1 ms, drill-head area over 10 ms, s.
PAPER_MEAN_DT = {"flow_exit": 1.403e-8, "drill_head": 5.46e-8}


def _fmt(value) -> str:
    return f"{value:10.3g}" if isinstance(value, float) and math.isfinite(value) else f"{'-':>10}"


def balance_verdict(residual_share: float, filling_share: float) -> str:
    """One line on eq. 2 over the steady window: closed within 1 % of V_AG, or where the missing volume is (the
    fluid still filling the control volume, when the storage accounts for the residual to within 1 %; else what the
    planes and frames do not account for). Shares of V_AG, -."""
    if abs(residual_share) <= 0.01:
        return "the balance closes within 1 %"
    if math.isfinite(filling_share) and abs(residual_share - filling_share) <= 0.01:
        where = "still filling the scene" if filling_share > 0 else "draining from the scene"
        return (f"the balance does not close within 1 %: the missing volume is the fluid {where} (the control "
                "volume's storage above), not yet a steady state")
    return (f"the balance does not close within 1 %: {residual_share * 100:.3g} % of V_AG, of which the control "
            f"volume's storage accounts for {filling_share * 100:.3g} %")


def print_window_balance(bal: dict, win: dict) -> None:
    """Print eq. 2 as volumes between the steady window's first and last frames (analysis.window_balance) and the
    verdict; without two frames in the window, the means of `bal` (analysis.balance) and its storage rate."""
    if not win:
        print(f"residual V_AG - V_IB - V_loss = {bal['residual_share'] * 100:.3g} % of V_AG; the control volume "
              f"stores {bal.get('filling_share', math.nan) * 100:.3g} % of V_AG (d volume / dt from the frames)")
        print(balance_verdict(bal["residual_share"], bal.get("filling_share", math.nan)))
        return
    ag = win["V_AG"]
    residual = (ag - win["V_IB"] - win["V_loss"]) / ag if ag else math.nan
    print(f"as volumes from frame to frame, {win['t_a'] * 1e3:.4g}..{win['t_b'] * 1e3:.4g} ms (ml): V_AG "
          f"{ag * 1e6:.4g}, V_IB {win['V_IB'] * 1e6:.4g}, V_loss {win['V_loss'] * 1e6:.4g}, stored in the control "
          f"volume {win['stored'] * 1e6:+.4g}")
    print(f"residual V_AG - V_IB - V_loss = {residual * 100:.3g} % of V_AG; the storage {win['stored_share'] * 100:.3g} "
          f"%; what neither accounts for: {win['closure_share'] * 100:.2g} %")
    print(balance_verdict(residual, win["stored_share"]))


def print_zones(layout, frames: dict, v_in: float) -> None:
    """Print the still zones and the zone of maximum pressure (analysis.zones) of the last frame; v_in m/s."""
    last = frames[max((k for k in frames if k != "attrs"), key=int)]
    found = zones(layout, last, v_in)
    print(f"\nzones at t = {float(last['attrs']['time']) * 1e3:.3g} ms (paper: 'areas with little to zero fluid velocity "
          "and maximum pressure'):")
    still = "; ".join(f"{name} {count} ({share * 100:.2g} % of it) at r {r * 1e3:.3g} mm, z {z * 1e3:.3g} mm"
                      for name, count, share, r, z in found["still"][:4]) or "none"
    print(f"  still (|v| < {STILL_SHARE * 100:g} % of v_in): {still}")
    if "peak" in found:
        n, mean, top, name, r, z = found["peak"]
        print(f"  highest pressure (top {n} particles): mean {mean / 1e5:.3g} bar, max {top / 1e5:.3g} bar, mostly "
              f"in {name}, at r {r * 1e3:.3g} mm, z {z * 1e3:.3g} mm")


def _cells(values, scale: float, fmt: str) -> str:
    return "/".join(format(v * scale, fmt) if math.isfinite(v) else "-" for v in values) or "-"


def print_head_flow(case, frames: dict) -> None:
    """Print the flow at the guide pads and the cutting edges (head_flow.py) in every frame, and the paper's
    finding for Figs. 3-4 measured on the last; nothing for a head without them."""
    keys = sorted((k for k in frames if k != "attrs"), key=int)
    if not keys or not (case.head.pad_angles or case.head.edge_angles):
        return
    print("\nguide pads and cutting edges (paper Figs. 3-4; pads in the order of head.pad_angles; dead: the share of "
          f"a window without moving fluid, empty or slower than {STILL_SHARE * 100:g} % of v_in):")
    print(f"{'t ms':>6}{'v m/s':>7}{'q bar':>7}  {'pad rise bar':<14}{'past m/s':<12}{'lee dead %':<12}{'open %':>7}  "
          f"{'edge dp bar':<12}{'faces %':>8}{'gap %':>7}{'mouth m/s':>10}")
    for k in keys:
        f = frames[k]
        pads, edges = pad_flow(case, f), edge_flow(case, f)
        print(f"{float(f['attrs']['time']) * 1e3:6.3g}{pads['approach']:7.3g}{pads['dynamic'] / 1e5:7.3g}  "
              f"{_cells(pads['rise'], 1e-5, '.3g'):<14}{_cells(pads['past'], 1, '.3g'):<12}"
              f"{_cells(pads['wake_dead'], 100, '.3g'):<12}{_cells([pads['open_dead']], 100, '.3g'):>7}  "
              f"{_cells(edges['jump'], 1e-5, '+.2g'):<12}{_cells(edges['face_dead'], 100, '.3g'):>8}"
              f"{_cells([edges['gap_dead']], 100, '.3g'):>7}{_cells(edges['mouth_speed'], 1, '.3g'):>10}")
    print("finding: " + head_finding(case, frames[keys[-1]]))


def print_element_flows(net, sph: dict, scene, layout, p_a: float, where: str) -> None:
    """Print the flows the network's elements give at the SPH's pressure p_a (Pa gauge, read `where`) and the
    outlets' held pressures (comparison.element_flows) beside the SPH's V_IB and V_loss (flow_exit; drill_head:
    V_IB only)."""
    if not math.isfinite(p_a):
        return
    els = element_flows(net, p_a, scene.mouth_pressure, scene.leak_pressure, scene.columns)
    parts = [f"the cutting zone and the chip mouth's entrance {els['V_IB'] / LITRE_PER_MIN:.3g} l/min (SPH "
             f"{sph.get('V_IB', math.nan) / LITRE_PER_MIN:.3g})"]
    if "leak" in layout.outlets:
        parts.append(f"the leak path {els['V_loss'] / LITRE_PER_MIN:.3g} l/min (SPH "
                     f"{sph.get('V_loss', math.nan) / LITRE_PER_MIN:.3g})")
    ends = "the columns' ends" if scene.columns else "the outlets"
    print(f"the network's elements alone at the SPH's p_A {where} = {p_a / 1e5:.3g} bar and {ends}' pressures: "
          + ", ".join(parts))


def print_elements_at_flow(net, sph: dict, scene, layout) -> None:
    """Print the network's elements carrying the SPH's V_AG between the scene's ends (comparison.elements_at_flow):
    their p_A and split beside the SPH's (flow_exit with a leak outlet)."""
    v_ag = sph.get("V_AG", math.nan)
    if "leak" not in layout.outlets or not (math.isfinite(v_ag) and v_ag > 0):
        return
    p_a, els = elements_at_flow(net, v_ag, scene.mouth_pressure, scene.leak_pressure, scene.columns)
    print(f"the network's elements carrying the SPH's V_AG = {v_ag / LITRE_PER_MIN:.3g} l/min between the scene's "
          f"ends (the SPH's boundary conditions): p_A {p_a / 1e5:.3g} bar, V_IB {els['V_IB'] / LITRE_PER_MIN:.3g} "
          f"l/min (SPH {sph.get('V_IB', math.nan) / LITRE_PER_MIN:.3g}), V_loss {els['V_loss'] / LITRE_PER_MIN:.3g} "
          f"l/min (SPH {sph.get('V_loss', math.nan) / LITRE_PER_MIN:.3g})")


def beside_jets(layout, frames: dict) -> tuple[np.ndarray, np.ndarray]:
    """(frame times s, gauge pressures Pa) beside the holes' jets (analysis.pressure_beside_jets), in time order,
    for the frames that have fluid there (empty without holes)."""
    side = sorted((float(f["attrs"]["time"]), pressure_beside_jets(layout, f)[0]) for k, f in frames.items()
                  if k != "attrs")
    side = [v for v in side if math.isfinite(v[1])]
    return (np.array([t for t, _ in side]), np.array([p for _, p in side])) if side else (np.zeros(0), np.zeros(0))


def print_columns(series: dict, time: np.ndarray, layout) -> None:
    """Print each column outlet's chamber pressure (bar gauge), speed (m/s) and flow (l/min) over the steady window
    (engine eq. OB5; nothing for plain outlets)."""
    window = steady_window(time)
    parts = []
    for role in layout.outlets:
        p, u = series.get(f"column_pressure_{role}"), series.get(f"column_speed_{role}")
        if p is None or u is None:
            continue
        parts.append(f"{role} {np.mean(np.asarray(p)[window]) / 1e5:.3g} bar, {np.mean(np.asarray(u)[window]):.3g} m/s")
    if parts:
        print(f"columns (eq. OB5) over the last {STEADY_FRACTION:.0%}: chamber pressure and speed: " + "; ".join(parts))


def print_balance(case, layout, time: np.ndarray, flows: dict, frames: dict) -> tuple[dict, np.ndarray | None]:
    """Print eq. 2 over the steady window with the control volume's storage (from the frames) and the filling
    times (a start 'empty'); returns the balance (analysis.balance) and the storage rate at the series' times
    (m^3/s; None with fewer than two frames on the frame grid)."""
    t_frames, volumes = stored_volume(layout, frames, case.fluid.density * case.numerics.dx ** 3,
                                      case.scene_fluid().floor_density)
    grid = spaced_frames(t_frames, case.output.frame_interval)
    stored = (np.interp(time, t_frames[grid], stored_volume_rate(t_frames[grid], volumes[grid]))
              if grid.sum() >= 2 else None)
    bal = balance(time, flows, stored)
    print(f"\neq. 2 over the last 20 % of the run (l/min): V_AG {bal.get('V_AG', math.nan) / LITRE_PER_MIN:.4g}, "
          f"V_IB {bal.get('V_IB', math.nan) / LITRE_PER_MIN:.4g}, V_loss {bal.get('V_loss', 0.0) / LITRE_PER_MIN:.4g}")
    print_window_balance(bal, window_balance(time, flows, t_frames, volumes))
    if case.scene.start == "filled":
        print(f"\nstarted filled at rest, the inlet ramped over {case.scene.ramp_time * 1e3:g} ms: no filling times")
    else:
        times = filling_times(time, flows)
        print("\nfilling times (s): " + ", ".join(f"{k} {v:.3g}" if math.isfinite(v) else f"{k} not reached"
                                                 for k, v in times.items()))
    return bal, stored


def print_comparison(case, layout, series: dict, time: np.ndarray, bal: dict) -> tuple[dict, list]:
    """Print the SPH beside the network at the SPH's V_AG, at the standard flow and the paper (comparison_rows);
    returns the SPH's flows and pressures (SI) and the rows."""
    net = case.network()
    sph = {k: v for k, v in bal.items() if k.startswith("V_")}
    sph.update({f"p_{k}": v for k, v in sensor_pressures(series, time).items()})
    at_gap = network_at_gap_flow(net, sph["V_AG"]) if sph.get("V_AG", 0) > 0 else None
    standard = solve(net, case.scene.network_flow * LITRE_PER_MIN)
    b_distance = layout.sensors["B"][2] - case.geometry().head_length if layout.area == "flow_exit" else None
    rows = comparison_rows(sph, net, at_gap, standard, b_distance, case.scene.network_flow)
    feed = at_gap.litres_per_min("V_total") if at_gap else math.nan
    print(f"\n{'quantity':<20}{'unit':>6}{'SPH':>10}{'net@V_AG':>10}{'net@' + format(case.scene.network_flow, 'g'):>10}"
          f"  paper          (net@V_AG: the network at the feed {feed:.4g} l/min whose V_AG is the SPH's)")
    for name, unit, a, b, c, paper in rows:
        print(f"{name:<20}{unit:>6}{_fmt(a)}{_fmt(b)}{_fmt(c)}  {paper}")
    return sph, rows


def print_beside_jets(case, layout, sph: dict, frames: dict, time: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Print the network's elements at the SPH's p_A (sensor A), the pressure beside the jets over the steady
    window with the elements at it, and the elements carrying the SPH's V_AG; returns beside_jets' series."""
    net = case.network()
    print_element_flows(net, sph, case.scene, layout, sph.get("p_A", math.nan), "(sensor A)")
    t_side, p_sides = beside_jets(layout, frames)
    steady = t_side >= time[-1] - STEADY_FRACTION * (time[-1] - time[0])
    p_side = float(np.mean(p_sides[steady])) if steady.any() else math.nan
    if math.isfinite(p_side):
        print(f"p_A beside the jets (the head clearance at the holes' height, >= 30 degrees from each hole's axis; "
              f"frames of the last {STEADY_FRACTION:.0%}): {p_side / 1e5:.3g} bar, where sensor A on a hole's axis "
              f"reads the jet meeting the bore; the network's p_A is this static pressure")
        print_element_flows(net, sph, case.scene, layout, p_side, "beside the jets")
    print_elements_at_flow(net, sph, case.scene, layout)
    return t_side, p_sides


def analyze_drill_run(run_dir, run: dict, case, render: bool = True) -> dict:
    """Print the run's flows, balance, pressures, filling times and the comparison with the network and the paper;
    write series.png, comparison.png and (render) section_<t>.png. Returns {name: path}."""
    run_dir = Path(run_dir)
    layout = drill_layout(case)
    paper_dt = PAPER_MEAN_DT[layout.area]
    series, time = run_series(run_dir, run, case, f" (paper: {paper_dt:.4g} s)")
    if time.size < 2:
        return {}
    series, frames = less_back_pressure(series, run.get("frames", {}), case.scene.back_pressure)
    flows = flow_series(series, time)
    bal, stored = print_balance(case, layout, time, flows, frames)
    if frames:
        print_zones(layout, frames, case.scene.inlet_velocity)
        print_head_flow(case, frames)
    sph, rows = print_comparison(case, layout, series, time, bal)
    beside = print_beside_jets(case, layout, sph, frames, time)
    print_columns(series, time, layout)
    v_in = case.scene.inlet_velocity
    if case.scene.back_pressure:
        print(f"pressures are gauge less the scene's back pressure, {case.scene.back_pressure / 1e5:g} bar (held at "
              "both outlets and the fluid's rest pressure: the same flow, above the vapour floor)")
    print(f"anchor: 1/2 rho v_in^2 = {0.5 * case.fluid.density * v_in ** 2 / 1e5:.3g} bar at v_in = {v_in:g} m/s; "
          "sensors outside the scene (C1, C2 at the feed) are '-'")
    outputs = draw_run_pictures(run_dir, case, layout, time, flows, series, stored, beside, rows, frames, render)
    for name, path in outputs.items():
        print(f"{name:<14} {path}")
    return outputs


def measure_drill(case, result) -> dict[str, float]:
    """Measured quantities of an ejector-drill run (SI units): V_in (the inlet's), V_AG, V_IB, V_loss (means over
    the last STEADY_FRACTION, m^3/s), balance_residual (V_AG - V_IB - V_loss, m^3/s) and balance_share (of V_AG, -),
    p_A, p_B (gauge, Pa), t_gap, t_holes, t_front, t_mouth, t_leak (a start 'empty' only), t_ejector_onset (s,
    after t_leak, or after the ramp with a start 'filled'; NaN: did not happen),
    max_density_deviation (-). Empty when the run recorded fewer than two series records."""
    time = np.asarray(result.time if result.time is not None else [], dtype=float)
    if time.size < 2:
        return {}
    series = {k: v.values for k, v in result.series.items()}
    flows = flow_series(series, time)
    out = {}
    bal = balance(time, flows)
    for key in ("V_in", "V_AG", "V_IB", "V_loss"):
        if key in bal:
            out[key] = bal[key]
    out["balance_residual"], out["balance_share"] = bal["residual"], bal["residual_share"]
    out.update({f"p_{k}": v for k, v in sensor_pressures(series, time).items()})
    if case.scene.start == "filled":  # nothing fills; the onset counts once the inlet has ramped up
        out["t_ejector_onset"] = ejector_onset(time, flows, case.scene.ramp_time)
    else:
        times = filling_times(time, flows)
        out.update(times)
        out["t_ejector_onset"] = ejector_onset(time, flows, times.get("t_leak", math.nan))
    if "max_density_deviation" in series:
        out["max_density_deviation"] = float(np.nanmax(series["max_density_deviation"]))
    return out
