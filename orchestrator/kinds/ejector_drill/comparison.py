"""The ejector-drill SPH beside the 1D hydraulic network (reference/drill_network.py) and the paper: the control
volume's stored fluid (eq. 2's missing volume while the scene fills), the network solved at the SPH's annular-gap
flow and at the paper's standard rate, and the comparison table. Flows in l/min and pressures in bar (gauge) in
the table; SI elsewhere."""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from orchestrator.reference.drill_network import (LITRE_PER_MIN, front_pressure_drop, leak_pressure_drop,
                                                  mouth_path_pressure_drop, solve)
from orchestrator.reference.hydraulics import orifice_pressure_drop

#: The paper's expectation (sect. 4): "Pressures in the range of p = 10 - 20 bar are expected in the overall system";
#: flow rates 50-80 l/min.
PAPER_BAR = (10.0, 20.0)
PAPER_FLOW = (50.0, 80.0)
FLOWS = ("V_total", "V_AG", "V_EN", "V_IB", "V_loss")
SENSORS = ("A", "B", "C1", "C2")


def control_volume_mask(layout, positions: np.ndarray) -> np.ndarray:
    """Fluid between the inflow planes (AG and rear, or the inlet) and the chip mouth's plane IB (mask)."""
    z_top = layout.planes["AG"].center[2] if "AG" in layout.planes else layout.inlet.center[2]
    ib = layout.planes["IB"]
    r = np.hypot(positions[:, 0], positions[:, 1])
    return (positions[:, 2] < z_top) & ~((r < ib.radius) & (positions[:, 2] > ib.center[2]))


def stored_volume(layout, frames, mass: float, floor_density: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(frame times s, liquid volume m / max(rho, floor_density) in the control volume m^3) from run.h5 frames;
    mass: of one particle, rho0 dx^3 (kg); floor_density: the cavitation floor's density (kg/m^3, 0: none), at
    which a cavitating particle holds its liquid (the rest of m/rho is vapour), as the engine's flow planes count."""
    times, volumes = [], []
    for key in sorted((k for k in frames if k != "attrs"), key=int):
        frame = frames[key]
        fluid = np.asarray(frame["kind"]) == 0
        x = np.asarray(frame["positions"], dtype=float)[fluid]
        rho = np.asarray(frame["densities"], dtype=float)[fluid]
        times.append(float(frame["attrs"]["time"]))
        inside = control_volume_mask(layout, x)
        volumes.append(float(np.sum(mass / np.maximum(rho[inside], floor_density))))
    return np.asarray(times), np.asarray(volumes)


def network_at_gap_flow(net, v_ag: float):
    """The network solved at the feed flow whose V_AG equals v_ag (m^3/s, > 0), by brentq over 1-2000 l/min; None
    when no feed in that range gives it."""
    def miss(q):
        return solve(net, q * LITRE_PER_MIN).V_AG - v_ag

    try:
        return solve(net, brentq(miss, 1.0, 2000.0, xtol=1e-6) * LITRE_PER_MIN)
    except ValueError:
        return None


def element_flows(net, p_a: float, p_mouth: float, p_leak: float, columns: bool = False) -> dict:
    """The network's two ways out of the cutting zone, each alone, driven by the SPH's pressures (Pa gauge): 'V_IB'
    through the turns round the cutting edges and the chip mouth's entrance (front_pressure_drop) from p_a to the
    mouth outlet's p_mouth (with columns, whose mouth column runs on through the inner tube to C1: the whole way,
    mouth_path_pressure_drop), 'V_loss' along the leak path (leak_pressure_drop) from p_a to p_leak (m^3/s,
    negative: drawn in). They say how the network's elements would split the flow at the SPH's p_A: where they disagree
    with the SPH's flows, the scene's passages differ from the network's elements."""
    out = {}
    front = mouth_path_pressure_drop if columns else front_pressure_drop
    for name, drop, dp in (("V_IB", front, p_a - p_mouth), ("V_loss", leak_pressure_drop, p_a - p_leak)):
        hi = 1.0  # m^3/s: far beyond any drop here
        out[name] = brentq(lambda q, d=drop, target=dp: d(net, q) - target, -hi, hi, xtol=1e-12) if dp else 0.0
    return out


def elements_at_flow(net, flow: float, p_mouth: float, p_leak: float, columns: bool = False) -> tuple[float, dict]:
    """(p_A Pa gauge, element_flows) of the network's two ways out carrying `flow` (m^3/s, the SPH's V_AG) between
    the scene's own ends (p_mouth, p_leak Pa gauge): the network with the SPH's boundary conditions, which the
    whole network (its mouth at the ejector's suction) does not have."""
    def miss(p_a):
        return sum(element_flows(net, p_a, p_mouth, p_leak, columns).values()) - flow

    p_a = brentq(miss, min(p_mouth, p_leak) - 1e7, max(p_mouth, p_leak) + 1e7, xtol=1e-3)
    return p_a, element_flows(net, p_a, p_mouth, p_leak, columns)


def network_gap_pressure(net, state, distance: float) -> float:
    """Gauge pressure (bar) the network has in the annular gap `distance` m up from the head (the SPH's sensor B):
    p_A plus the holes' orifice drop plus the gap's friction over that length."""
    p = (state.p_A + orifice_pressure_drop(state.V_AG, net.hole_area, net.cd_hole, net.rho)
         + net.annular_gap(distance).pressure_drop(state.V_AG, net.rho, net.mu))
    return (p - net.p_ambient) / 1e5


def comparison_rows(sph: dict, net, at_gap, at_standard, b_distance: float | None, standard_flow: float) -> list:
    """Rows (quantity, unit, SPH, network at the SPH's V_AG, network at the standard flow, paper) with flows in
    l/min and gauge pressures in bar; NaN where a value does not exist (outside the scene, or no network state)."""
    rows = []
    for name in FLOWS:
        value = sph.get(name, math.nan)
        rows.append((name, "l/min", value / LITRE_PER_MIN if math.isfinite(value) else math.nan,
                     at_gap.litres_per_min(name) if at_gap else math.nan, at_standard.litres_per_min(name),
                     f"{PAPER_FLOW[0]:g}-{PAPER_FLOW[1]:g}" if name == "V_total" else ""))
    for s in SENSORS:
        value = sph.get(f"p_{s}", math.nan)
        rows.append((f"p_{s}", "bar", value / 1e5 if math.isfinite(value) else math.nan,
                     at_gap.gauge_bar(f"p_{s}") if at_gap else math.nan, at_standard.gauge_bar(f"p_{s}"),
                     f"{PAPER_BAR[0]:g}-{PAPER_BAR[1]:g} (system)"))
    if b_distance is not None:
        rows.append(("p_B at the SPH's B", "bar", sph.get("p_B", math.nan) / 1e5,
                     network_gap_pressure(net, at_gap, b_distance) if at_gap else math.nan,
                     network_gap_pressure(net, at_standard, b_distance), ""))
    rows.append(("p_feed", "bar", math.nan, at_gap.gauge_bar("p_feed") if at_gap else math.nan,
                 at_standard.gauge_bar("p_feed"), f"{PAPER_BAR[0]:g}-{PAPER_BAR[1]:g} (system)"))
    return rows
