"""1D hydraulic elements (orchestrator.reference.hydraulics) against textbook values, and the ejector
deep-hole drill network (orchestrator.reference.drill_network): balances, pressure ordering, anchors and
the direction in which the flow split moves."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest
from fluids.flow_meter import flow_meter_discharge
from fluids.jet_pump import liquid_jet_pump
from scipy.integrate import quad

from orchestrator.reference import drill_network as dn
from orchestrator.reference import hydraulics as hy

RHO, MU = 1000.0, 1.0e-3
PAPER_RANGE = (50, 60, 70, 80)  # l/min, the paper's V_feed range


# ---------------------------------------------------------------- laminar annulus
def test_laminar_annulus_equals_the_integrated_exact_profile():
    # u(r) = G/(4 mu) [r_o^2 - r^2 + (r_o^2 - r_i^2) ln(r / r_o) / ln(r_o / r_i)], G = dp/L (White eq. 3-48)
    r_o, r_i, dp, length = 10e-3, 6e-3, 2.0e3, 0.5
    g = dp / length

    def u(r):
        return g / (4 * MU) * (r_o**2 - r**2 + (r_o**2 - r_i**2) * math.log(r / r_o) / math.log(r_o / r_i))

    assert u(r_i) == pytest.approx(0.0, abs=1e-12) and u(r_o) == pytest.approx(0.0, abs=1e-12)
    q_profile = quad(lambda r: 2 * math.pi * r * u(r), r_i, r_o, epsabs=0, epsrel=1e-13)[0]
    assert hy.annulus_laminar_flow(dp, length, r_o, r_i, MU) == pytest.approx(q_profile, rel=1e-10)


def test_laminar_annulus_limits_pipe_and_narrow_gap():
    dp, length = 1.0e3, 1.0
    # r_i = 0: Hagen-Poiseuille Q = pi r^4 dp / (8 mu L)
    assert hy.annulus_laminar_flow(dp, length, 5e-3, 0.0, MU) == pytest.approx(math.pi * 5e-3**4 * dp / (8 * MU),
                                                                             rel=1e-14)
    # narrow gap h << r: plane Poiseuille Q = W h^3 dp / (12 mu L), W = pi (r_o + r_i); error O((h/r)^2) ~ 4e-5 here
    r_o, r_i = 10.5e-3, 10.0e-3
    plane = math.pi * (r_o + r_i) * (r_o - r_i) ** 3 * dp / (12 * MU * length)
    assert hy.annulus_laminar_flow(dp, length, r_o, r_i, MU) == pytest.approx(plane, rel=2e-4)
    assert hy.annulus_laminar_flow(dp, length, r_o, r_i, MU) != pytest.approx(plane, rel=1e-6)


def test_laminar_f_re_matches_shah_and_london():
    # Shah & London (1978), concentric annuli: Fanning f Re = 16 (pipe), 23.813 (r_i/r_o = 0.5), -> 24 (plates)
    assert hy.annulus_laminar_fre(1.0, 0.0) == pytest.approx(64.0, rel=1e-14)
    assert hy.annulus_laminar_fre(1.0, 0.5) / 4 == pytest.approx(23.813, rel=2e-4)
    assert hy.annulus_laminar_fre(10.0, 9.5) / 4 == pytest.approx(24.0, rel=1e-3)


def test_duct_laminar_drop_inverts_the_exact_annulus_formula():
    gap = hy.Duct(0.4, 20e-3, 19e-3)
    flow = 1.0e-6  # m^3/s -> u = 0.033 m/s, Re = 33: laminar
    assert gap.reynolds(flow, RHO, MU) < hy.RE_LAMINAR
    dp = gap.pressure_drop(flow, RHO, MU)
    assert hy.annulus_laminar_flow(dp, 0.4, 10e-3, 9.5e-3, MU) == pytest.approx(flow, rel=1e-10)
    assert gap.pressure_drop(-flow, RHO, MU) == pytest.approx(-dp, rel=1e-15)


# ---------------------------------------------------------------- friction factors
def test_turbulent_friction_against_moody_and_blasius():
    # Colebrook / Moody chart: smooth pipe Re = 1e5 -> 0.0180; eps/D = 1e-3, Re = 1e5 -> 0.0222
    assert hy.darcy_friction(1e5) == pytest.approx(0.0180, rel=5e-3)
    assert hy.darcy_friction(1e5, 1e-3) == pytest.approx(0.0222, rel=5e-3)
    # Blasius f = 0.3164 Re^-1/4 is within ~1-3 % of smooth Colebrook for 4e3 < Re < 1e5
    for re in (1e4, 2e4, 5e4):
        assert hy.darcy_friction(re) == pytest.approx(0.3164 * re**-0.25, rel=0.03)
    assert hy.darcy_friction(1000.0) == pytest.approx(0.064, rel=1e-14)


def test_friction_bridge_is_continuous():
    for edge in (hy.RE_LAMINAR, hy.RE_TURBULENT):
        below, above = hy.darcy_friction(edge * (1 - 1e-9)), hy.darcy_friction(edge * (1 + 1e-9))
        assert above == pytest.approx(below, rel=1e-6)


def test_turbulent_annulus_uses_the_hydraulic_diameter():
    gap = hy.Duct(1.0, 20e-3, 19e-3)
    assert gap.hydraulic_diameter == pytest.approx(1e-3, rel=1e-12)
    flow = 6.0e-4  # 36 l/min, u = 19.6 m/s, Re = 19,600
    u = flow / gap.area
    f = hy.darcy_friction(u * 1e-3 * RHO / MU)
    assert gap.pressure_drop(flow, RHO, MU) == pytest.approx(f / 1e-3 * 0.5 * RHO * u * u, rel=1e-12)


# ---------------------------------------------------------------- orifices and fittings
def test_orifice_discharge_textbook_value_and_fluids_meter():
    # Cd = 0.61, d = 10 mm, 1 bar of water: Q = 0.61 * 7.854e-5 m^2 * sqrt(2e5 / 1000) = 6.7755e-4 m^3/s
    area = math.pi / 4 * 0.01**2
    q = hy.orifice_flow(1.0e5, area, 0.61, RHO)
    assert q == pytest.approx(6.7755e-4, rel=1e-4)
    # fluids' flow-meter equation with a negligible approach velocity (beta = 0.01)
    m = flow_meter_discharge(D=1.0, Do=0.01, P1=2.0e5, P2=1.0e5, rho=RHO, C=0.61)
    assert q == pytest.approx(m / RHO, rel=1e-7)
    assert hy.orifice_pressure_drop(q, area, 0.61, RHO) == pytest.approx(1.0e5, rel=1e-12)
    assert hy.orifice_pressure_drop(-q, area, 0.61, RHO) == pytest.approx(-1.0e5, rel=1e-12)


def test_expansion_contraction_limits():
    # Borda-Carnot: (1 - (d1/d2)^2)^2 = 0.5625 for d2 = 2 d1; -> 1 (free exit) for an infinite space
    assert hy.sudden_expansion_k(1.0, 2.0) == pytest.approx(0.5625, rel=1e-14)
    assert hy.sudden_expansion_k(1.0, 1e4) == pytest.approx(hy.free_exit_k(), rel=1e-7)
    # Rennels' sharp contraction from a very large pipe tends to his sharp entrance (0.57)
    assert hy.sudden_contraction_k(1.0, 1e-3) == pytest.approx(hy.sharp_entrance_k(), rel=5e-3)
    assert hy.sudden_contraction_k(1.0, 0.999) < 0.01


# ---------------------------------------------------------------- jet pump
def test_jet_pump_against_fluids_liquid_jet_pump_example():
    # fluids.jet_pump.liquid_jet_pump docstring example (Karassik's model), solved there for P1 and d_nozzle
    ans = liquid_jet_pump(rhop=998.0, rhos=1098.0, Km=0.186, Kd=0.12, Ks=0.11, Kp=0.04, d_mixing=0.045, Qs=0.01,
                          Qp=0.01, P2=133600.0, P5=200e3, nozzle_retracted=False, max_variations=10000)
    assert ans["P1"] == pytest.approx(426256.0, rel=1e-5)
    area = lambda d: math.pi / 4 * d * d  # noqa: E731
    pump = hy.JetPump(area(ans["d_nozzle"]), area(0.045), area(ans["d_diffuser"]), 0.04, 0.11, 0.186, 0.12)
    assert 133600.0 + pump.pressure_rise(0.01, 0.01, 998.0, 1098.0) == pytest.approx(200e3, rel=1e-6)
    assert 133600.0 + pump.nozzle_pressure_difference(0.01, 0.01, 998.0, 1098.0) == pytest.approx(ans["P1"], rel=1e-6)


def test_jet_pump_zero_secondary_flow_limit():
    # Qs = 0: P1 - P2 = q (1 + Kp) and P5 - P2 = q [2R - R^2 (1 + Km + Kd + (Am/A5)^2)], q = rho Vn^2 / 2
    a_n, a_m, a_5 = 5e-6, 2e-4, 4e-4
    pump = hy.JetPump(a_n, a_m, a_5, k_primary=0.1, k_secondary=0.1, k_mixing=0.2, k_diffuser=0.15)
    qp = 3e-4
    q = 0.5 * RHO * (qp / a_n) ** 2
    r = a_n / a_m
    assert pump.nozzle_pressure_difference(qp, 0.0, RHO) == pytest.approx(q * 1.1, rel=1e-12)
    expected = q * (2 * r - r * r * (1 + 0.2 + 0.15 + (a_m / a_5) ** 2))
    assert pump.pressure_rise(qp, 0.0, RHO) == pytest.approx(expected, rel=1e-12)
    # the lift falls as the pump draws secondary flow (the pump's characteristic)
    assert pump.pressure_rise(qp, 0.5 * qp, RHO) < pump.pressure_rise(qp, 0.0, RHO)


# ---------------------------------------------------------------- the drill network
@pytest.fixture(scope="module")
def states():
    return {q: dn.solve(dn.DrillNetwork(), q * dn.LITRE_PER_MIN) for q in PAPER_RANGE}


def test_network_balances_close(states):
    for s in states.values():
        assert abs(s.V_total - s.V_AG - s.V_EN) <= 1e-9 * s.V_total  # eq. 1
        assert abs(s.V_AG - s.V_IB - s.V_loss) <= 1e-9 * s.V_total  # eq. 2
        assert max(abs(r) for r in s.residuals) <= 1e-6 * (s.p_feed - s.p_ambient)
        assert s.V_EN > 0 and s.V_AG > 0 and s.V_IB > 0


def test_network_leak_path_is_consistent_with_p_a():
    # the leak flows out of the bore (V_loss > 0) exactly when the cutting zone is above ambient
    net = dn.DrillNetwork()
    for d_nozzle in (0.6e-3, 1.0e-3):
        s = dn.solve(replace(net, d_ejector_nozzle=d_nozzle), 60 * dn.LITRE_PER_MIN)
        assert (s.V_loss > 0) == (s.p_A > s.p_ambient)


def test_network_pressures_fall_along_the_main_paths(states):
    for s in states.values():
        # supply: feed -> B (annular gap at the chuck) -> A (head outlets) -> C1 (inner tube before the nozzles)
        assert s.p_feed > s.p_B > s.p_A > s.p_C1 > s.p_mixing_entry
        # discharge: the jet pump lifts C1 to C2, which drives the rest of the inner tube to ambient
        assert s.p_feed > s.p_C2 > s.p_ambient and s.p_C2 > s.p_C1


def test_network_velocity_anchor(states):
    assert hy.dynamic_pressure(1000.0, 60.0) / 1e5 == pytest.approx(18.0, rel=1e-12)  # the anchor
    s = states[60]
    head = s.p_feed - s.p_mixing_entry  # all the pressure the network can turn into speed
    fastest = max(abs(v) for v in s.speeds.values())
    # energy: no stream is faster than the available head allows ...
    assert hy.dynamic_pressure(RHO, fastest) <= head
    # ... and the ejector jets, the fastest stream, take most of it (1/(1+K_p) of it, K_p = 0.1)
    assert fastest == s.speeds["ejector_jet"]
    assert hy.dynamic_pressure(RHO, fastest) / head == pytest.approx(1 / 1.1, rel=1e-9)
    # the SPH scene's 60 m/s is the jet speed class of this network at 50-60 l/min (within 30 %)
    assert 0.7 < states[50].speeds["ejector_jet"] / 60.0 < 1.3


def test_network_pressures_scale_between_q_175_and_q_2(states):
    # turbulent friction (Blasius-like, ~Q^1.75) and inertial losses (Q^2): doubling 40 -> 80 l/min
    low = dn.solve(dn.DrillNetwork(), 40 * dn.LITRE_PER_MIN)
    ratio = (states[80].p_feed - states[80].p_ambient) / (low.p_feed - low.p_ambient)
    assert 2**1.75 < ratio < 4.0


def test_flow_split_moves_toward_the_annular_gap_with_flow(states):
    # the annular gap is friction-dominated (f falls with Re) while the nozzles are inertial (fixed K):
    # with more flow the gap gets relatively cheaper, so V_AG / V_total must rise, slowly
    shares = [states[q].V_AG / states[q].V_total for q in PAPER_RANGE]
    assert all(b > a for a, b in zip(shares, shares[1:]))
    assert shares[-1] - shares[0] < 0.05
    # and a thicker coolant (more friction in the gap) pushes flow to the nozzles
    thick = dn.solve(replace(dn.DrillNetwork(), mu=5e-3), 60 * dn.LITRE_PER_MIN)
    assert thick.V_AG / thick.V_total < shares[1] - 0.02


def test_larger_ejector_nozzles_draw_more_from_the_cutting_zone():
    losses = [dn.solve(replace(dn.DrillNetwork(), d_ejector_nozzle=d), 60 * dn.LITRE_PER_MIN).V_loss
              for d in (0.6e-3, 0.8e-3, 1.0e-3, 1.2e-3)]
    assert all(b < a for a, b in zip(losses, losses[1:]))
    assert losses[0] > 0 > losses[-1]  # from leaking out of the bore to drawing fluid in


def test_ejector_onset_is_where_v_loss_changes_sign():
    # the default geometry draws fluid in at every flow of the search range: no onset
    assert dn.ejector_onset(dn.DrillNetwork(), 5.0, 150.0) is None
    # nozzles of 0.84 mm put the onset inside the paper's range
    net = replace(dn.DrillNetwork(), d_ejector_nozzle=0.84e-3)
    q = dn.ejector_onset(net, 5.0, 150.0)
    assert q is not None and 40.0 < q < 90.0
    s = dn.solve(net, q * dn.LITRE_PER_MIN)
    assert abs(s.V_loss) < 1e-6 * s.V_total


def test_cavitation_is_flagged():
    s = dn.solve(dn.DrillNetwork(), 80 * dn.LITRE_PER_MIN)
    assert s.cavitating == (s.p_mixing_entry < dn.DrillNetwork().p_vapour)
    assert dn.solve(dn.DrillNetwork(), 20 * dn.LITRE_PER_MIN).cavitating is False


def test_bad_flow_is_refused():
    with pytest.raises(dn.OrchestratorError):
        dn.solve(dn.DrillNetwork(), 0.0)


def test_slot_contraction_follows_von_mises_table():
    """Cc of a slot in a channel (von Mises 1917) at the b/B of his table (0.611, 0.612, 0.616, 0.622, 0.644, 0.662,
    0.687, 0.722, 0.781, rounded to 3 digits); Kirchhoff's pi / (pi + 2) at b/B = 0; C_d adds the approach speed."""
    from orchestrator.reference.hydraulics import slot_contraction_coefficient, slot_discharge_coefficient

    table = {0.0: 0.611, 0.1: 0.612, 0.2: 0.616, 0.3: 0.622, 0.5: 0.644, 0.6: 0.662, 0.7: 0.687, 0.8: 0.722,
             0.9: 0.781}
    for beta, cc in table.items():
        assert slot_contraction_coefficient(beta) == pytest.approx(cc, abs=6e-4)
    assert slot_contraction_coefficient(0.0) == pytest.approx(math.pi / (math.pi + 2.0), rel=1e-15)
    assert slot_contraction_coefficient(1e-9) == pytest.approx(math.pi / (math.pi + 2.0), rel=1e-8)
    cc = slot_contraction_coefficient(0.25)
    assert slot_discharge_coefficient(0.25) == pytest.approx(cc / math.sqrt(1.0 - (0.25 * cc) ** 2), rel=1e-15)
    assert slot_discharge_coefficient(0.25) == pytest.approx(0.62615, abs=1e-5)
    with pytest.raises(ValueError, match="beta"):
        slot_contraction_coefficient(1.0)
