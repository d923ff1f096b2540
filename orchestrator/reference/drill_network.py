"""1D hydraulic network of the ejector deep-hole drill of Canini, Gerken, Biermann & Eberhard.
SI units: m, m^2, m^3/s, Pa (pressures absolute unless a name says gauge), kg/m^3, Pa s.

Paths (the paper's names, eqs. 1-2: V_total = V_AG + V_EN, V_AG = V_IB + V_loss):

    feed F --(ejector nozzles, V_EN)--------------------------------> jet pump in the inner tube
       \\--(sharp entrance, annular gap between the tubes, V_AG)--> adduction holes --> A (cutting zone)
    A --(head flats, cutting edges, chip mouth, inner tube, V_IB)--> C1 (inner tube before the nozzles)
    A --(clearance head/bore, outer tube/bore, V_loss)--> bore mouth (ambient; V_loss < 0: drawn in)
    C1 + nozzles --(jet pump: mixing length of the inner tube)--> C2 --(rest of inner tube, exit)--> ambient

Sensors (Fig. 5): A at the drill-head outlets (cutting-zone pressure), B in the annular gap near the feed
(the telemetry sits on the clamping chuck, Fig. 6), C1/C2 in the inner tube before (suction side) and
behind (end of the mixing length) the ejector nozzles.

The paper gives only the bore (30 mm), d_Diff = 1 mm, the flow range 50-80 l/min, n ~ 950 1/min and
the expected 10-20 bar; it shows the geometry only in figures. Every other number below is a
reconstruction, with its reasoning beside it. Single-phase liquid, no chips, tool rotation not modelled
(centrifugal head in the gap, rho omega^2 r^2 / 2 ~ 0.5 kPa at n = 950 1/min, is negligible).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, root

from orchestrator.errors import OrchestratorError
from orchestrator.reference.hydraulics import (
    Duct, JetPump, dynamic_pressure, equivalent_diameter, free_exit_k, loss_pressure_drop, orifice_pressure_drop,
    sharp_entrance_k, sudden_expansion_k)

LITRE_PER_MIN = 1.0e-3 / 60.0  # m^3/s


@dataclass(frozen=True)
class DrillNetwork:
    """Every dimension (m), area (m^2), coefficient (dimensionless) and fluid property (SI) of the
    network, with its source. A case file fills this; the defaults are the reconstruction.

    d_Diff is read literally as a diametral difference (0.5 mm radial gap). With it the gap alone takes
    ~20 bar at 60 l/min and the feed needs ~30 bar, above the paper's expected 10-20 bar; read as a radial
    gap (d_diff = 2 mm here) the feed needs 10.6 bar at 60 l/min but the ejector no longer holds the leak
    (V_loss ~ +20 %). The jet pump cavitates (mixing-entry pressure below p_vapour) from ~60 l/min with
    the defaults: NetworkState.cavitating says when the liquid-only model is outside its validity.
    """

    # --- fluid: water-based emulsion (not stated in the paper; ejector drilling usually runs on
    # emulsion); rho = 1000 gives the dynamic head 1/2 rho (60 m/s)^2 = 18 bar of the paper's inflow.
    rho: float = 1000.0  # kg/m^3
    mu: float = 1.0e-3  # Pa s, water at 20 C; a 5 % emulsion is 1-1.5 mPa s (reconstruction)
    p_ambient: float = 101325.0  # Pa; the work area is flooded at atmospheric pressure (paper, sect. 4)
    p_vapour: float = 2340.0  # Pa, water at 20 C: absolute pressures below it mean cavitation

    # --- bore and tubes
    d_bore: float = 30.0e-3  # paper: drilling diameter d = 30 mm (phi_ext = 30 mm)
    d_outer_tube_od: float = 24.0e-3  # reconstruction: ~0.8 d leaves a 3 mm radial clearance to the bore
    d_outer_tube_id: float = 20.0e-3  # reconstruction: 2 mm wall for 8-10 kN feed force (paper: F_f)
    d_diff: float = 1.0e-3  # paper: "difference in diameter of the annular gap" d_Diff = 1 mm (diametral)
    d_inner_tube_id: float = 16.0e-3  # reconstruction: 1.5 mm wall on the inner tube OD = 20 - d_Diff mm
    tube_length: float = 0.40  # m, feed to drill head; reconstruction: bore depth l/D = 10 (300 mm) + chuck,
    # connector and head shank (the paper names no depth)
    roughness: float = 1.5e-6  # m, drawn steel tube (Moody: 1.5 um)

    # --- ejector nozzles at the feed end of the inner tube, angled rearward
    n_ejector_nozzles: int = 6  # reconstruction (a ring of small nozzles or slots, Fig. 1C)
    d_ejector_nozzle: float = 1.0e-3  # reconstruction: sized so that about a third of V_total takes the
    # nozzles (the split ejector-tool makers state) -> 35 % at 60 l/min; R = A_n / A_m = 0.023
    k_primary: float = 0.10  # K_p of a short drilled nozzle (Karassik: 0.05-0.15)
    k_secondary: float = 0.10  # K_s, secondary entry (Karassik; fluids' example 0.11)
    mixing_length: float = 0.12  # m, inner tube behind the nozzles that acts as mixing throat (~7.5 d_i,
    # Karassik's recommended throat length 6-8 D); K_m = f L_mix / d_i is computed from it
    discharge_length: float = 0.10  # m, rest of the inner tube from the end of mixing to the chip outlet

    # --- drill head
    n_holes: int = 3  # adduction holes from the annular gap to the outside of the head (reconstruction)
    d_hole: float = 4.0e-3  # reconstruction, Fig. 2 (holes much wider than the 0.5 mm radial gap)
    cd_hole: float = 0.65  # short drilled hole fed by a crossflow, l/d ~ 1-2 (Lichtarowicz et al. 1965: 0.6-0.8)
    front_area: float = 80.0e-6  # m^2, free passage from the outlets to the cutting edges (flats and chip
    # space on the head's periphery; reconstruction)
    k_cutting_zone: float = 1.5  # turns around the cutting edges into the chip mouth, on front_area (Idelchik
    # order of two 90-degree turns; reconstruction)
    d_chip_mouth: float = 12.0e-3  # equivalent diameter of the chip mouth (reconstruction, < d_inner_tube_id)
    k_chip_mouth_entry: float = 0.57  # sharp entrance into the mouth (Rennels, fluids.fittings.entrance_sharp)

    # --- leak path from the outlets back to the bore mouth
    d_head_body: float = 29.2e-3  # head body behind the guide pads (pads at 30 mm; reconstruction)
    head_rear_length: float = 25.0e-3  # m, head length from the outlets to the tube joint (reconstruction)
    pad_blockage: float = 0.3  # fraction of the head clearance's circumference taken by guide pads (recon.)
    bore_depth: float = 0.30  # m, current drilled depth = length of the tube/bore clearance (l/D = 10)

    # --- sensor B position
    sensor_b_from_feed: float = 0.05  # m into the annular gap from the feed (chuck, Fig. 5B/6; reconstruction)

    # derived elements
    @property
    def d_inner_tube_od(self):
        """Inner tube outside diameter, m: outer tube ID minus d_Diff."""
        return self.d_outer_tube_id - self.d_diff

    def annular_gap(self, length=None):
        """The annular gap between outer and inner tube (Duct) over `length` m (default: all of it)."""
        return Duct(self.tube_length if length is None else length, self.d_outer_tube_id, self.d_inner_tube_od,
                    self.roughness)

    def inner_tube(self, length):
        """A stretch of the inner tube (Duct) of `length` m."""
        return Duct(length, self.d_inner_tube_id, 0.0, self.roughness)

    @property
    def hole_area(self):
        """Total adduction-hole area, m^2."""
        return self.n_holes * 0.25 * math.pi * self.d_hole**2

    @property
    def nozzle_area(self):
        """Total ejector-nozzle area, m^2."""
        return self.n_ejector_nozzles * 0.25 * math.pi * self.d_ejector_nozzle**2

    def head_clearance(self):
        """Clearance between head body and bore behind the outlets (Duct, full circumference; the guide
        pads' blockage is applied by the network as a flow scaled by 1 / (1 - pad_blockage), i.e. the same
        narrow gap over a shorter circumference)."""
        return Duct(self.head_rear_length, self.d_bore, self.d_head_body, self.roughness)

    def tube_clearance(self):
        """Clearance between the outer tube and the bore wall over the drilled depth (Duct)."""
        return Duct(self.bore_depth, self.d_bore, self.d_outer_tube_od, self.roughness)

    def jet_pump(self, mixing_flow):
        """The ejector as a JetPump: mixing chamber = inner tube, no diffuser, K_m = f L_mix / d_i at the
        mixing-exit flow `mixing_flow` (m^3/s)."""
        k_m = self.inner_tube(self.mixing_length).friction_loss_coefficient(mixing_flow, self.rho, self.mu)
        area = self.inner_tube(1.0).area
        return JetPump(self.nozzle_area, area, area, self.k_primary, self.k_secondary, k_m, 0.0)


@dataclass(frozen=True)
class NetworkState:
    """The solved network at one feed flow: flows in m^3/s, pressures absolute in Pa, speeds in m/s."""

    V_total: float
    V_AG: float
    V_EN: float
    V_IB: float
    V_loss: float
    p_feed: float
    p_A: float
    p_B: float
    p_C1: float
    p_C2: float
    p_mixing_entry: float  # lowest pressure, at the nozzle exits (P3 of the jet pump)
    cavitating: bool  # p_mixing_entry below the vapour pressure: the liquid-only model is outside its validity
    speeds: dict
    residuals: tuple  # Pa: feed-pressure mismatch of the two paths, leak-path mismatch
    p_ambient: float = 101325.0

    def gauge_bar(self, name):
        """Pressure `name` (e.g. 'p_A') as gauge pressure in bar."""
        return (getattr(self, name) - self.p_ambient) / 1.0e5

    def litres_per_min(self, name):
        """Flow `name` (e.g. 'V_EN') in l/min."""
        return getattr(self, name) / LITRE_PER_MIN


def leak_pressure_drop(net, v_loss):
    """Pressure drop (Pa) of the leak path at the flow v_loss (m^3/s, negative: drawn in): A -> head clearance (the
    guide pads block part of its circumference: the same gap speed over a full circumference carries
    v_loss / (1 - pad_blockage)) -> sudden expansion into the tube clearance (Borda-Carnot on the area ratio) ->
    tube clearance over the drilled depth -> bore mouth (free exit into the flooded work area)."""
    rho, mu = net.rho, net.mu
    head, tube_c = net.head_clearance(), net.tube_clearance()
    q_head = v_loss / (1.0 - net.pad_blockage)  # flow of the full-circumference duct with the same gap speed
    return (head.pressure_drop(q_head, rho, mu)
            + loss_pressure_drop(q_head, head.area, sudden_expansion_k(
                equivalent_diameter((1.0 - net.pad_blockage) * head.area), equivalent_diameter(tube_c.area)), rho)
            + tube_c.pressure_drop(v_loss, rho, mu) + loss_pressure_drop(v_loss, tube_c.area, free_exit_k(), rho))


def front_pressure_drop(net, v_ib):
    """Pressure drop (Pa) from A into the chip mouth at the flow v_ib (m^3/s): the turns round the cutting edges
    (k_cutting_zone on front_area) and the mouth's sharp entrance (k_chip_mouth_entry on its area); the inner tube
    beyond is not in it."""
    mouth = 0.25 * math.pi * net.d_chip_mouth**2
    return (loss_pressure_drop(v_ib, net.front_area, net.k_cutting_zone, net.rho)
            + loss_pressure_drop(v_ib, mouth, net.k_chip_mouth_entry, net.rho))


def mouth_path_pressure_drop(net, v_ib):
    """Pressure drop (Pa) from A to C1 at the flow v_ib (m^3/s): front_pressure_drop, the sudden expansion from the
    chip mouth into the inner tube and the inner tube's friction over tube_length."""
    mouth = 0.25 * math.pi * net.d_chip_mouth**2
    return (net.inner_tube(net.tube_length).pressure_drop(v_ib, net.rho, net.mu)
            + loss_pressure_drop(v_ib, mouth, sudden_expansion_k(net.d_chip_mouth, net.d_inner_tube_id), net.rho)
            + front_pressure_drop(net, v_ib))


def _pressures(net, v_total, v_en, v_ib):
    """Walk the network for given V_EN, V_IB (m^3/s); return (residuals in Pa, state fields)."""
    rho, mu = net.rho, net.mu
    v_ag = v_total - v_en
    v_loss = v_ag - v_ib
    q_d = v_en + v_ib
    # downstream of the ejector: rest of the inner tube and the free exit to ambient
    tube_d = net.inner_tube(net.discharge_length)
    p_c2 = net.p_ambient + tube_d.pressure_drop(q_d, rho, mu) + loss_pressure_drop(q_d, tube_d.area, free_exit_k(), rho)
    pump = net.jet_pump(q_d)
    p_c1 = p_c2 - pump.pressure_rise(v_en, v_ib, rho)
    p_feed = p_c1 + pump.nozzle_pressure_difference(v_en, v_ib, rho)
    # return path: cutting zone -> chip mouth -> inner tube (whole tube length) -> C1
    mouth = 0.25 * math.pi * net.d_chip_mouth**2
    tube_i = net.inner_tube(net.tube_length)
    p_a = p_c1 + mouth_path_pressure_drop(net, v_ib)
    # supply path: feed -> sharp entrance -> annular gap -> holes -> A
    gap = net.annular_gap()
    entrance = loss_pressure_drop(v_ag, gap.area, sharp_entrance_k(), rho)
    p_feed_ag = (p_a + orifice_pressure_drop(v_ag, net.hole_area, net.cd_hole, rho) + gap.pressure_drop(v_ag, rho, mu)
                 + entrance)
    p_b = p_feed - entrance - net.annular_gap(net.sensor_b_from_feed).pressure_drop(v_ag, rho, mu)
    head, tube_c = net.head_clearance(), net.tube_clearance()
    q_head = v_loss / (1.0 - net.pad_blockage)
    residuals = (p_feed_ag - p_feed, p_a - net.p_ambient - leak_pressure_drop(net, v_loss))
    speeds = dict(ejector_jet=v_en / net.nozzle_area, annular_gap=gap.speed(v_ag), holes=v_ag / net.hole_area,
                  chip_mouth=v_ib / mouth, inner_tube=tube_i.speed(v_ib), discharge=tube_d.speed(q_d),
                  head_clearance=head.speed(q_head), front=v_ib / net.front_area)
    p_3 = p_c1 - pump.mixing_entry_pressure_drop(v_ib, rho)
    fields = dict(V_total=v_total, V_AG=v_ag, V_EN=v_en, V_IB=v_ib, V_loss=v_loss, p_feed=p_feed, p_A=p_a, p_B=p_b,
                  p_C1=p_c1, p_C2=p_c2, p_mixing_entry=p_3, cavitating=bool(p_3 < net.p_vapour),
                  speeds=speeds, residuals=residuals, p_ambient=net.p_ambient)
    return residuals, fields


def solve(net, v_total):
    """Solve the network for a feed flow v_total (m^3/s, > 0); returns a NetworkState.

    Unknowns: the nozzle share s = V_EN / V_total (kept in (0, 1) through a logistic) and V_IB. Equations:
    both paths from the feed give the same feed pressure; the leak path's drop equals p_A - p_ambient.
    Solved with scipy.optimize.root (hybr) from several starts; raises OrchestratorError if none converges.
    """
    if not v_total > 0.0:
        raise OrchestratorError(f"the drill network needs a positive feed flow, got {v_total} m^3/s")
    scale = dynamic_pressure(net.rho, v_total / net.annular_gap().area)

    def unpack(y):
        return v_total / (1.0 + math.exp(-float(y[0]))), float(y[1]) * v_total

    def fun(y):
        v_en, v_ib = unpack(y)
        return np.array(_pressures(net, v_total, v_en, v_ib)[0]) / scale

    best = None
    for share, ib in ((1 / 3, 0.6), (0.5, 0.4), (0.2, 0.8), (0.7, 0.3), (0.1, 0.9)):
        sol = root(fun, [math.log(share / (1.0 - share)), ib], method="hybr", options=dict(xtol=1e-13))
        err = float(np.max(np.abs(fun(sol.x))))
        if best is None or err < best[0]:
            best = (err, sol.x)
        if err < 1e-10:
            break
    if best[0] > 1e-8:
        raise OrchestratorError(f"the drill network did not converge at {v_total / LITRE_PER_MIN:.3g} l/min "
                                f"(scaled residual {best[0]:.2e})")
    v_en, v_ib = unpack(best[1])
    return NetworkState(**_pressures(net, v_total, v_en, v_ib)[1])


def sweep(net, litres_per_min):
    """Solved states at each feed flow given in l/min (the paper's range is 50-80)."""
    return [solve(net, q * LITRE_PER_MIN) for q in litres_per_min]


def ejector_onset(net, low=1.0, high=200.0):
    """Feed flow, l/min, at which V_loss crosses zero (the ejector onset: on the side where V_loss <= 0 the
    ejector draws fluid in from the bore mouth instead of leaking coolant out), searched in [low, high] l/min
    with brentq; None when V_loss has the same sign at both ends (no onset in the range). Which side draws
    in depends on the geometry: check with solve()."""

    def loss(q):
        return solve(net, q * LITRE_PER_MIN).V_loss

    a, b = loss(low), loss(high)
    if a == 0.0:
        return low
    if a * b > 0.0:
        return None
    return brentq(loss, low, high, xtol=1e-6)
