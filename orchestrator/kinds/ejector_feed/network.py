"""What the 1D network (reference/drill_network.py) says at the feed scene's boundaries and sensors: its state at
the case's network_flow, and its pressure in the annular gap a distance downstream of the feed (the nozzle ring).
SI units (m^3/s, m/s, Pa gauge)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from orchestrator.reference.drill_network import LITRE_PER_MIN, NetworkState, solve
from orchestrator.reference.hydraulics import loss_pressure_drop, sharp_entrance_k


def gap_pressure_below_feed(net, state: NetworkState, distance: float) -> float:
    """Gauge pressure (Pa) the network has in the annular gap `distance` m downstream (toward the head) of the feed
    node F, where the nozzles draw: p_feed less the gap's sharp entrance and its friction over that length (the
    network's own elements, drill_network._pressures)."""
    gap = net.annular_gap(distance)
    p = (state.p_feed - loss_pressure_drop(state.V_AG, gap.area, sharp_entrance_k(), net.rho)
         - gap.pressure_drop(state.V_AG, net.rho, net.mu))
    return p - net.p_ambient


@dataclass(frozen=True)
class FeedBoundary:
    """The network's numbers the feed scene's open boundaries carry: the feed inlet's mean speed (V_total over the
    gap's area) and the inner tube inlet's (V_IB over the tube's bore), m/s; the gauge pressures the gap outlet and
    the tube outlet hold, Pa; the state they come from."""

    state: NetworkState
    gap_speed: float
    tube_speed: float
    gap_outlet_pressure: float
    tube_outlet_pressure: float


def feed_boundary(case, gap_outlet_distance: float) -> FeedBoundary:
    """The network at case.scene.network_flow (l/min): the inlets carry its V_total (gap) and V_IB (tube); the gap
    outlet, `gap_outlet_distance` m below the nozzle ring, holds its gap pressure there; the tube outlet holds its
    p_C2. The network has no pressure inside its mixing length (the jet pump is one control volume from the nozzles
    to C2, 0.12 m): the scene's tube outlet, a few tube diameters behind the nozzles, stands for the mixing length's
    end, so the SPH's p_C1 - p_C2 is the suction its short mixing zone builds against the network's whole rise."""
    net = case.network()
    state = solve(net, case.scene.network_flow * LITRE_PER_MIN)
    gap_area = net.annular_gap().area
    tube_area = 0.25 * math.pi * net.d_inner_tube_id ** 2
    return FeedBoundary(state=state, gap_speed=state.V_total / gap_area, tube_speed=state.V_IB / tube_area,
                        gap_outlet_pressure=gap_pressure_below_feed(net, state, gap_outlet_distance),
                        tube_outlet_pressure=state.p_C2 - net.p_ambient)
