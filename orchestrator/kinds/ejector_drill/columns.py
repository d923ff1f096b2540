"""The passages beyond a drill scene's outlets as liquid columns (engine eq. OB5, `[scene] columns`).

A scene keeps a few millimetres of each outlet path: the leak outlet sits in the tube/bore clearance about 30 mm
behind the head face, while that clearance runs on to the bore mouth (`bore_depth`, 0.3 m); the chip-mouth outlet
sits 5 mm behind the face, while the chip mouth and the inner tube run on to the feed (`tube_length`, 0.4 m). With
plain outlets held at a pressure that missing liquid has no mass: a scene started at rest drains its clearance in
a fraction of a millisecond (docs/ejector_drill.md). A column outlet gives it back its inertia and friction: the
engine integrates rho0 L du/dt = p_chamber - p_held - K rho0 u|u|/2 for each.

- leak: L = bore_depth - z_leak (the clearance from the outlet to the bore mouth), A the clearance's section,
  K = f L / D_h (its friction, Duct) + 1 (the free exit into the flooded work area).
- mouth: the chip mouth from the outlet to the head's rear (z_head), then the inner tube over tube_length to the
  feed, as one column of the mouth's section A_m: L = (z_head - z_mouth) + tube_length A_m / A_t (the same
  inertia rho0 sum(L_i / A_i) A_m), K on the mouth's speed = f_m (z_head - z_mouth) / d_m + the sudden expansion
  into the tube + f_t tube_length / d_t (A_m / A_t)^2. It ends at the held mouth pressure (the network puts C1,
  where it ends, at -0.9 bar gauge at 60 l/min; the case holds 0 unless told).

The friction factors are taken at `flow` (m^3/s; the scene's inflow: f changes little with it in turbulent flow).

`inertia` (0 < inertia <= 1, `[scene] column_inertia`) keeps that fraction of each column's length for its inertia
(and its chamber, so that it rings at its own quarter-wave period), while K stays the whole passage's. A steady state
(du/dt = 0, the chamber's mass constant) does not depend on L: p_chamber = p_held + K rho0 u|u|/2 either way. It
only shortens the transient: the full columns ring at 4 L / c0 and settle over about L / (K u), tens of
milliseconds, beyond the quick scenes' reach.
"""
from __future__ import annotations

import math

from orchestrator.reference.hydraulics import Duct, free_exit_k, sudden_expansion_k


def outlet_columns(net, head_length: float, outlets: dict, flow: float, inertia: float = 1.0) -> dict[str, dict]:
    """role -> the column keys of the engine's outlet (column_length m, column_loss -, column_area m^2) for the
    outlets 'leak' and 'mouth' among `outlets` (role -> Plane, z along the drill axis from the head face, m), with
    net a DrillNetwork and head_length the head's length (m, where the inner tube begins); column_length is the
    fraction `inertia` of the passage's (its loss is the whole passage's)."""
    rho, mu = net.rho, net.mu
    columns = {}
    if "leak" in outlets:
        length = net.bore_depth - outlets["leak"].center[2]
        clearance = Duct(length, net.d_bore, net.d_outer_tube_od, net.roughness)
        loss = clearance.friction_loss_coefficient(flow, rho, mu) + free_exit_k()
        columns["leak"] = dict(column_length=length * inertia, column_loss=loss, column_area=clearance.area)
    if "mouth" in outlets:
        in_head = head_length - outlets["mouth"].center[2]
        mouth, tube = Duct(in_head, net.d_chip_mouth, 0.0, net.roughness), net.inner_tube(net.tube_length)
        ratio = mouth.area / tube.area
        loss = (mouth.friction_loss_coefficient(flow, rho, mu) + sudden_expansion_k(net.d_chip_mouth, net.d_inner_tube_id)
                + tube.friction_loss_coefficient(flow, rho, mu) * ratio**2)
        columns["mouth"] = dict(column_length=(in_head + net.tube_length * ratio) * inertia, column_loss=loss,
                                column_area=0.25 * math.pi * net.d_chip_mouth**2)
    return columns
