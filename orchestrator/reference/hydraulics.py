"""One-dimensional hydraulic elements for the ejector deep-hole drill network. SI units throughout
(m, m^2, m^3/s, Pa, kg/m^3, Pa s); every flow rate is a volume flow, every pressure drop a static
pressure difference upstream minus downstream.

Where the `fluids` package (Caleb Bell, fluids.readthedocs.io) has the element it is used:

- turbulent Darcy friction factor: ``fluids.friction.friction_factor`` (Clamond's exact solution of
  Colebrook-White), applied with the hydraulic diameter for annuli;
- sudden expansion (Borda-Carnot) and sharp contraction loss coefficients:
  ``fluids.fittings.diffuser_sharp`` and ``fluids.fittings.contraction_sharp`` (Rennels);
  sharp entrance and free exit: ``fluids.fittings.entrance_sharp`` and ``fluids.fittings.exit_normal``;
- the primary-nozzle energy balance of a liquid jet pump: ``fluids.jet_pump.liquid_jet_pump_ancillary``
  (Karassik et al., Pump Handbook, 4th ed., 2007, ch. on jet pumps).

Written here, with the reference named at each function:

- laminar flow in a concentric annulus, exact (annular Poiseuille; e.g. White, Viscous Fluid Flow,
  3rd ed., eq. 3-49), and the laminar-turbulent bridge;
- orifices and holes discharging into a large space, Q = Cd A sqrt(2 dp / rho) (ISO 5167-1 with
  beta -> 0); fluids' flow-meter functions need an approach pipe and are used only to check it;
- the jet pump's mixing-chamber momentum balance and diffuser (Karassik's / ESDU 85032's constant-area
  mixing form, nozzle inside the mixing entry). fluids has it only inside ``liquid_jet_pump`` (a
  solve-for-two-unknowns routine) and an unexported helper, so it is derived here and checked against
  ``fluids.jet_pump.liquid_jet_pump`` in the tests.

All pressure drops are odd functions of the flow (sign follows the flow), so that a leak path may
reverse without a special case.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from fluids.fittings import contraction_sharp, diffuser_sharp, entrance_sharp, exit_normal
from fluids.friction import friction_factor
from fluids.jet_pump import liquid_jet_pump_ancillary
from scipy.optimize import brentq

#: Below this Reynolds number (hydraulic diameter) the laminar exact solution holds.
RE_LAMINAR = 2000.0
#: Above this the turbulent Colebrook factor holds; in between f is interpolated linearly in Re
#: (a continuous bridge so that root finders see no jump; the transition itself is not modelled).
RE_TURBULENT = 4000.0


def dynamic_pressure(rho, speed):
    """1/2 rho v^2, Pa, for density rho in kg/m^3 and speed in m/s."""
    return 0.5 * rho * speed * speed


def _signed_square(x):
    return x * abs(x)


def annulus_laminar_flow(dp, length, r_outer, r_inner, mu):
    """Exact laminar (annular Poiseuille) volume flow, m^3/s, through a concentric annulus.

    dp: pressure drop over the length, Pa; length, r_outer, r_inner: m (r_inner = 0 gives
    Hagen-Poiseuille); mu: dynamic viscosity, Pa s.
    Q = pi dp / (8 mu L) [r_o^4 - r_i^4 - (r_o^2 - r_i^2)^2 / ln(r_o / r_i)] (White, Viscous Fluid
    Flow, eq. 3-49).
    """
    bracket = r_outer**4 - r_inner**4
    if r_inner > 0.0:
        bracket -= (r_outer**2 - r_inner**2) ** 2 / math.log(r_outer / r_inner)
    return math.pi * dp / (8.0 * mu * length) * bracket


def annulus_laminar_fre(r_outer, r_inner):
    """Laminar Darcy friction constant f Re of a concentric annulus (dimensionless), with Re and f
    based on the hydraulic diameter D_h = 2 (r_o - r_i); 64 for a pipe, 96 for a narrow gap.

    Follows from annulus_laminar_flow with dp = f (L / D_h) rho u^2 / 2.
    """
    d_h = 2.0 * (r_outer - r_inner)
    area = math.pi * (r_outer**2 - r_inner**2)
    # Q / dp per unit (L/mu): f Re = 2 D_h^2 A / (Q mu L / dp)
    q_per = annulus_laminar_flow(1.0, 1.0, r_outer, r_inner, 1.0)
    return 2.0 * d_h * d_h * area / q_per


def darcy_friction(reynolds, relative_roughness=0.0, laminar_fre=64.0):
    """Darcy friction factor (dimensionless) at Reynolds number `reynolds` (>= 0, based on the
    hydraulic diameter), relative roughness eps/D_h and the duct's laminar constant f Re.

    Laminar (Re <= 2000): laminar_fre / Re (exact for the duct shape). Turbulent (Re >= 4000):
    fluids.friction.friction_factor (Clamond solution of Colebrook) with the hydraulic diameter.
    In between: linear interpolation in Re between the two (continuous; not a transition model).
    """
    if reynolds <= 0.0:
        raise ValueError("darcy_friction needs Re > 0 (use the laminar limit for zero flow)")
    if reynolds <= RE_LAMINAR:
        return laminar_fre / reynolds
    if reynolds >= RE_TURBULENT:
        return friction_factor(Re=reynolds, eD=relative_roughness)
    w = (reynolds - RE_LAMINAR) / (RE_TURBULENT - RE_LAMINAR)
    return (1.0 - w) * laminar_fre / reynolds + w * friction_factor(Re=reynolds, eD=relative_roughness)


@dataclass(frozen=True)
class Duct:
    """A straight circular pipe (d_inner = 0) or concentric annulus: length, d_outer (inner diameter of
    the outer wall), d_inner (outer diameter of the core) and wall roughness, all in m."""

    length: float
    d_outer: float
    d_inner: float = 0.0
    roughness: float = 0.0

    def __post_init__(self):
        if not (self.length > 0.0 and self.d_outer > self.d_inner >= 0.0 and self.roughness >= 0.0):
            raise ValueError(f"invalid duct {self}: need length > 0, d_outer > d_inner >= 0, roughness >= 0")

    @property
    def area(self):
        """Flow cross-section, m^2."""
        return 0.25 * math.pi * (self.d_outer**2 - self.d_inner**2)

    @property
    def hydraulic_diameter(self):
        """4 A / wetted perimeter, m (d_outer - d_inner for an annulus)."""
        return self.d_outer - self.d_inner

    @property
    def laminar_fre(self):
        """Laminar Darcy f Re of the section (64 pipe, -> 96 narrow annulus)."""
        return annulus_laminar_fre(0.5 * self.d_outer, 0.5 * self.d_inner)

    def speed(self, flow):
        """Mean speed, m/s, for a volume flow in m^3/s (signed)."""
        return flow / self.area

    def reynolds(self, flow, rho, mu):
        """Reynolds number |u| D_h rho / mu for flow in m^3/s, rho in kg/m^3, mu in Pa s."""
        return abs(self.speed(flow)) * self.hydraulic_diameter * rho / mu

    def friction(self, flow, rho, mu):
        """Darcy friction factor at this flow (m^3/s); the laminar limit's f Re/Re at zero flow is
        never needed because pressure_drop treats zero flow separately."""
        return darcy_friction(self.reynolds(flow, rho, mu), self.roughness / self.hydraulic_diameter,
                              self.laminar_fre)

    def pressure_drop(self, flow, rho, mu):
        """Frictional pressure drop over the length, Pa, signed with the flow (m^3/s).

        dp = f (L / D_h) rho u |u| / 2; in the laminar range this equals the exact annular Poiseuille
        drop (annulus_laminar_flow inverted).
        """
        if flow == 0.0:
            return 0.0
        u = self.speed(flow)
        return self.friction(flow, rho, mu) * self.length / self.hydraulic_diameter * 0.5 * rho * _signed_square(u)

    def friction_loss_coefficient(self, flow, rho, mu):
        """K = f L / D_h (dimensionless), the section's friction as a loss coefficient (Karassik's K_m
        for a mixing tube)."""
        if flow == 0.0:
            return self.laminar_fre / RE_LAMINAR * self.length / self.hydraulic_diameter
        return self.friction(flow, rho, mu) * self.length / self.hydraulic_diameter


def loss_pressure_drop(flow, area, k_loss, rho):
    """Minor loss K rho u |u| / 2, Pa, with u = flow / area (m^3/s, m^2) and K referred to that area."""
    return k_loss * 0.5 * rho * _signed_square(flow / area)


def orifice_pressure_drop(flow, area, cd, rho):
    """Pressure drop, Pa, across holes of total area `area` (m^2) with discharge coefficient cd that
    discharge into a large space (jet kinetic energy lost): dp = rho/2 (Q / (cd A))^2, signed.

    This is Q = cd A sqrt(2 dp / rho) (ISO 5167-1, beta -> 0; e.g. White, Fluid Mechanics, sect. 6.12).
    """
    return 0.5 * rho * _signed_square(flow / (cd * area))


def orifice_flow(dp, area, cd, rho):
    """Volume flow, m^3/s, through holes (area m^2, discharge coefficient cd) under a pressure drop
    dp (Pa, signed): the inverse of orifice_pressure_drop."""
    return math.copysign(cd * area * math.sqrt(2.0 * abs(dp) / rho), dp)


def slot_contraction_coefficient(beta):
    """Contraction coefficient Cc (jet width at the vena contracta over the slot's width b) of the plane jet that
    leaves a sharp-edged slot centred across a plane channel of width B, beta = b / B in [0, 1): the root of
    Cc [1 + 2/pi (1/(Cc beta) - Cc beta) arctan(Cc beta)] = 1 (inviscid free-streamline theory, von Mises 1917;
    beta -> 0 gives Kirchhoff's pi / (pi + 2) = 0.611). Dimensionless."""
    if not 0.0 <= beta < 1.0:
        raise ValueError(f"beta = b / B must lie in [0, 1), got {beta}")
    if beta == 0.0:
        return math.pi / (math.pi + 2.0)

    def residual(cc):
        k = cc * beta
        return cc * (1.0 + 2.0 / math.pi * (1.0 / k - k) * math.atan(k)) - 1.0

    return brentq(residual, 0.5, 1.0, xtol=1e-14)


def slot_discharge_coefficient(beta):
    """Q / (b sqrt(2 dp / rho)) of that slot (per unit depth), dp the pressure upstream minus the pressure in the
    still water beside the jet behind the plate (the vena contracta's, as corner taps read it): Bernoulli from the
    approach flow Q / B to the jet's Q / (Cc b) gives Cc / sqrt(1 - (Cc beta)^2). Dimensionless."""
    cc = slot_contraction_coefficient(beta)
    return cc / math.sqrt(1.0 - (cc * beta) ** 2)


def sudden_expansion_k(d_small, d_large):
    """Loss coefficient of a sudden expansion from d_small to d_large (m), referred to the velocity in
    the small section: (1 - (d_small/d_large)^2)^2 (Borda-Carnot; fluids.fittings.diffuser_sharp)."""
    return diffuser_sharp(Di1=d_small, Di2=d_large)


def sudden_contraction_k(d_large, d_small):
    """Loss coefficient of a sharp-edged contraction from d_large to d_small (m), referred to the
    velocity in the small section (Rennels; fluids.fittings.contraction_sharp)."""
    return contraction_sharp(Di1=d_large, Di2=d_small)


def sharp_entrance_k():
    """Loss coefficient of a sharp-edged entrance from a large space (0.57, Rennels;
    fluids.fittings.entrance_sharp), dimensionless."""
    return entrance_sharp()


def free_exit_k():
    """Loss coefficient of a free exit into a large space (1.0; fluids.fittings.exit_normal)."""
    return exit_normal()


def equivalent_diameter(area):
    """Diameter, m, of a circle of the given area (m^2)."""
    return math.sqrt(4.0 * area / math.pi)


@dataclass(frozen=True)
class JetPump:
    """A liquid jet pump (ejector) with constant-area mixing chamber (Karassik's model; ESDU 85032).

    area_nozzle: total primary nozzle exit area, m^2; area_mixing: mixing-chamber cross-section, m^2
    (the secondary flow enters through area_mixing - area_nozzle); area_exit: diffuser exit area, m^2
    (= area_mixing for no diffuser); k_primary, k_secondary, k_mixing, k_diffuser: the loss
    coefficients K_p, K_s, K_m, K_d (dimensionless; K_p and K_m referred to nozzle and mixing-exit
    velocity, K_s to the secondary entry velocity, K_d to the mixing-exit velocity).
    The nozzle sits at the mixing entry (fluids' nozzle_retracted=False).
    """

    area_nozzle: float
    area_mixing: float
    area_exit: float
    k_primary: float = 0.05
    k_secondary: float = 0.1
    k_mixing: float = 0.15
    k_diffuser: float = 0.0

    def __post_init__(self):
        if not (0.0 < self.area_nozzle < self.area_mixing <= self.area_exit):
            raise ValueError(f"invalid jet pump {self}: need 0 < area_nozzle < area_mixing <= area_exit")

    @property
    def area_ratio(self):
        """R = A_nozzle / A_mixing (dimensionless)."""
        return self.area_nozzle / self.area_mixing

    def nozzle_pressure_difference(self, flow_primary, flow_secondary, rho_primary, rho_secondary=None):
        """P1 - P2, Pa: primary supply pressure minus secondary (suction) pressure needed to drive the
        primary flow (m^3/s, > 0) through the nozzle against the mixing-entry pressure, given the
        secondary flow (m^3/s). Energy balances of nozzle and secondary inlet, via
        fluids.jet_pump.liquid_jet_pump_ancillary (Karassik):
        P1 - P2 = rho_p/2 (Qp/An)^2 [(1 + Kp) - C (1 + Ks) (M R / (1 - R))^2], M = Qs/Qp, C = rho_s/rho_p.
        """
        if flow_primary <= 0.0:
            raise ValueError("the jet pump's primary flow must be positive")
        rho_s = rho_primary if rho_secondary is None else rho_secondary
        return liquid_jet_pump_ancillary(rhop=rho_primary, rhos=rho_s, Kp=self.k_primary, Ks=self.k_secondary,
                                         d_nozzle=equivalent_diameter(self.area_nozzle),
                                         d_mixing=equivalent_diameter(self.area_mixing),
                                         Qp=flow_primary, Qs=flow_secondary, P2=0.0)

    def pressure_rise(self, flow_primary, flow_secondary, rho_primary, rho_secondary=None):
        """P5 - P2, Pa: diffuser-exit pressure minus suction pressure, from the momentum balance of the
        constant-area mixing chamber (flows in m^3/s, densities kg/m^3):

        P2 - P3 = (1 + Ks) rho_s V3^2 / 2                        (secondary inlet, V3 = Qs / (Am - An))
        (P4 - P3) Am = rho_p Qp Vn + rho_s Qs V3 - rho_d Qd V4 - Km rho_d V4^2 Am / 2    (mixing)
        P5 - P4 = rho_d (V4^2 - V5^2) / 2 - Kd rho_d V4^2 / 2    (diffuser)
        with Vn = Qp/An, V4 = Qd/Am, V5 = Qd/A_exit, Qd = Qp + Qs, rho_d the mixed density.
        (Karassik et al., Pump Handbook, 4th ed., jet pumps; the same model as ESDU 85032.)
        """
        rho_s = rho_primary if rho_secondary is None else rho_secondary
        q_d = flow_primary + flow_secondary
        rho_d = (rho_primary * flow_primary + rho_s * flow_secondary) / q_d if q_d != 0.0 else rho_primary
        v_n = flow_primary / self.area_nozzle
        v_3 = flow_secondary / (self.area_mixing - self.area_nozzle)
        v_4 = q_d / self.area_mixing
        v_5 = q_d / self.area_exit
        suction = (1.0 + self.k_secondary) * 0.5 * rho_s * _signed_square(v_3)
        mixing = ((rho_primary * flow_primary * v_n + rho_s * flow_secondary * v_3 - rho_d * q_d * v_4)
                  / self.area_mixing - self.k_mixing * 0.5 * rho_d * _signed_square(v_4))
        diffuser = 0.5 * rho_d * (v_4 * v_4 - v_5 * v_5) - self.k_diffuser * 0.5 * rho_d * _signed_square(v_4)
        return mixing + diffuser - suction

    def mixing_entry_pressure_drop(self, flow_secondary, rho_secondary):
        """P2 - P3, Pa: suction pressure minus the pressure at the mixing entry (the lowest pressure
        in the pump), for the secondary flow in m^3/s."""
        v_3 = flow_secondary / (self.area_mixing - self.area_nozzle)
        return (1.0 + self.k_secondary) * 0.5 * rho_secondary * _signed_square(v_3)
