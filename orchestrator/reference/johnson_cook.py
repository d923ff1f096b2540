"""The Johnson-Cook solid of Nutto et al. (eqs. 10-14) and Hutchings' crater (eq. 20), as plain numpy functions.

Units are SI: stresses and moduli in Pa, strains dimensionless, rates in 1/s, temperatures in K, densities in
kg/m^3, specific heat in J/(kg K). Tensors are 3 x 3 numpy arrays; tension is positive.

    sigma_y = [A + B eps_p^n] R(epsdot*; C) [1 - T*^m]                               (eq. 10)
    T*      = (T - T0) / (Tm - T0), clipped to [0, 1]                               (eq. 11)
    dT      = chi dW_p / (rho0 C_p),  dW_p = sigma_y d eps_p                        (eq. 12)
    D       = sum d eps_p / eps_f                                                   (eq. 13)
    eps_f   = [D1 + D2 exp(D3 sigma*)] R(epsdot*; D4) [1 + D5 T*]                   (eq. 14)

epsdot* = epsdot_p / epsdot_0 is the plastic strain rate over a reference rate. The rate factor R has two forms:
'power', R = (1 + epsdot*)^C as the paper writes eq. 10, and 'log', R = 1 + C ln(max(epsdot*, 1)), Johnson and Cook's
own form (clipped so that rates below the reference do not soften). sigma* = sigma_m / sigma_eq is the triaxiality,
mean stress sigma_m = tr(sigma) / 3 = -p over the von Mises stress, positive in tension.

The plastic step is a radial return: the trial deviator s + 2 G dev(d eps) is scaled back onto the yield surface,
with the plastic strain increment solved implicitly (backward Euler in eps_p and in the plastic rate) and the
temperature of the step's start in the softening term (explicit, as the heat is the step's own product).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from orchestrator.errors import OrchestratorError

RATE_FORMS = ("power", "log")
_RETURN_ITERATIONS = 200


@dataclass(frozen=True)
class Strength:
    """Eq. 10-11: A (Pa), B (Pa), n (-), C (-), m (-), reference rate epsdot_0 (1/s), T0 and Tm (K), rate form."""

    A: float
    B: float
    n: float
    C: float
    m: float
    reference_rate: float = 1.0
    room_temperature: float = 293.0
    melting_temperature: float = 925.0
    rate_form: str = "power"

    def __post_init__(self):
        if self.rate_form not in RATE_FORMS:
            raise OrchestratorError(f"rate_form = {self.rate_form!r}: allowed: {', '.join(RATE_FORMS)}")
        if not (self.A > 0.0 and self.B >= 0.0 and self.n > 0.0 and self.C >= 0.0 and self.m > 0.0):
            raise OrchestratorError("Johnson-Cook strength: A > 0, B >= 0, n > 0, C >= 0, m > 0 required")
        if not self.reference_rate > 0.0:
            raise OrchestratorError(f"reference_rate = {self.reference_rate}: must be above 0 (1/s)")
        if not self.melting_temperature > self.room_temperature:
            raise OrchestratorError(f"melting_temperature = {self.melting_temperature} K is not above "
                                    f"room_temperature = {self.room_temperature} K")


@dataclass(frozen=True)
class Failure:
    """Eq. 14: D1..D5 (-), reference rate epsdot_0 (1/s) and rate form of the D4 term."""

    D1: float
    D2: float
    D3: float
    D4: float
    D5: float
    reference_rate: float = 1.0
    rate_form: str = "power"


@dataclass(frozen=True)
class Solid:
    """An elastic-plastic solid: shear modulus G (Pa), an EOS (solid_eos.LinearEos or MieGruneisen, giving rho0),
    Johnson-Cook strength and optional failure, specific heat C_p (J/(kg K)) and heat fraction chi (-) of eq. 12."""

    shear_modulus: float
    eos: object
    strength: Strength
    failure: Failure | None = None
    heat_capacity: float = 896.0
    heat_fraction: float = 0.95

    @property
    def rho0(self) -> float:
        """Reference density, kg/m^3."""
        return self.eos.rho0


#: Nutto et al., Table I (strength) and Table II (failure), Al6061-T6 after Takaffoli & Papini (2012); the melting
#: and room temperatures (925 K, 293 K) are the usual Johnson-Cook values for this alloy.
AL6061_T6_STRENGTH = Strength(A=324e6, B=114e6, n=0.42, C=0.002, m=1.34)
AL6061_T6_FAILURE = Failure(D1=-0.77, D2=1.45, D3=-0.47, D4=0.0, D5=1.60)


def rate_factor(rate_ratio: float, exponent: float, form: str) -> float:
    """R(epsdot*) (-) of eqs. 10 and 14 for a dimensionless rate epsdot* >= 0: (1 + epsdot*)^exponent ('power') or
    1 + exponent ln(max(epsdot*, 1)) ('log')."""
    if form == "power":
        return (1.0 + rate_ratio) ** exponent
    if form == "log":
        return 1.0 + exponent * math.log(max(rate_ratio, 1.0))
    raise OrchestratorError(f"rate form {form!r}: allowed: {', '.join(RATE_FORMS)}")


def homologous_temperature(temperature: float, room_temperature: float, melting_temperature: float) -> float:
    """T* = (T - T0) / (Tm - T0) of eq. 11 (-), clipped to [0, 1] (no hardening below T0, no strength above Tm);
    temperatures in K."""
    t_star = (temperature - room_temperature) / (melting_temperature - room_temperature)
    return min(max(t_star, 0.0), 1.0)


def yield_stress(strength: Strength, plastic_strain: float, plastic_rate: float, temperature: float) -> float:
    """sigma_y of eq. 10 (Pa) at equivalent plastic strain eps_p (-), plastic rate epsdot_p (1/s) and T (K)."""
    t_star = homologous_temperature(temperature, strength.room_temperature, strength.melting_temperature)
    hardening = strength.A + strength.B * max(plastic_strain, 0.0) ** strength.n
    rate = rate_factor(plastic_rate / strength.reference_rate, strength.C, strength.rate_form)
    return hardening * rate * (1.0 - t_star ** strength.m)


def failure_strain(failure: Failure, triaxiality: float, plastic_rate: float, homologous: float) -> float:
    """eps_f of eq. 14 (-) at triaxiality sigma* (-, tension positive), plastic rate (1/s) and T* (-)."""
    rate = rate_factor(plastic_rate / failure.reference_rate, failure.D4, failure.rate_form)
    return (failure.D1 + failure.D2 * math.exp(failure.D3 * triaxiality)) * rate * (1.0 + failure.D5 * homologous)


def damage_increment(plastic_strain_increment: float, fracture_strain: float) -> float:
    """dD = d eps_p / eps_f of eq. 13 (-); a failure strain <= 0 (high triaxiality) fails at the first plastic
    increment (inf)."""
    if plastic_strain_increment <= 0.0:
        return 0.0
    return plastic_strain_increment / fracture_strain if fracture_strain > 0.0 else math.inf


def temperature_rise(plastic_work_density: float, heat_fraction: float, rho0: float, heat_capacity: float) -> float:
    """T - T0 = chi W_p / (rho0 C_p) of eq. 12 (K): plastic work per unit volume W_p (J/m^3), fraction chi (-),
    density rho0 (kg/m^3), specific heat C_p (J/(kg K))."""
    return heat_fraction * plastic_work_density / (rho0 * heat_capacity)


def deviator(tensor: np.ndarray) -> np.ndarray:
    """The deviatoric part t - tr(t) / 3 I of a 3 x 3 tensor (its units)."""
    return tensor - np.trace(tensor) / 3.0 * np.eye(3)


def von_mises(deviatoric_stress: np.ndarray) -> float:
    """sigma_eq = sqrt(3/2 s : s) (Pa) of a deviatoric stress s (Pa)."""
    return math.sqrt(1.5 * float(np.sum(deviatoric_stress * deviatoric_stress)))


def triaxiality(mean_stress: float, equivalent_stress: float) -> float:
    """sigma* = sigma_m / sigma_eq (-), mean stress tr(sigma) / 3 = -p positive in tension; 0 when sigma_eq = 0."""
    return mean_stress / equivalent_stress if equivalent_stress > 0.0 else 0.0


@dataclass(frozen=True)
class ReturnStep:
    """One radial-return step: the new deviatoric stress (Pa, 3 x 3), plastic strain increment (-), the yield stress
    at the end of the step (Pa), plastic work per unit volume (J/m^3) and the adiabatic temperature rise (K)."""

    deviatoric_stress: np.ndarray
    plastic_strain_increment: float
    yield_stress: float
    plastic_work: float
    temperature_rise: float


def _plastic_increment(strength: Strength, trial: float, shear_modulus: float, plastic_strain: float,
                       temperature: float, dt: float) -> float:
    """The root of f(x) = trial - 3 G x - sigma_y(eps_p + x, x / dt, T) on [0, trial / (3 G)] (f falls with x): Newton
    steps kept inside a shrinking bracket, bisection where Newton would leave it."""
    def residual(x: float) -> float:
        return trial - 3.0 * shear_modulus * x - yield_stress(strength, plastic_strain + x, x / dt, temperature)

    def slope(x: float) -> float:
        eps = plastic_strain + x
        t_star = homologous_temperature(temperature, strength.room_temperature, strength.melting_temperature)
        thermal = 1.0 - t_star ** strength.m
        ratio = x / (dt * strength.reference_rate)
        rate = rate_factor(ratio, strength.C, strength.rate_form)
        if strength.rate_form == "power":
            d_rate = strength.C * (1.0 + ratio) ** (strength.C - 1.0) / (dt * strength.reference_rate)
        else:
            d_rate = strength.C / x if ratio > 1.0 else 0.0
        d_hardening = strength.B * strength.n * eps ** (strength.n - 1.0) if eps > 0.0 else math.inf
        hardening = strength.A + strength.B * eps ** strength.n
        return -3.0 * shear_modulus - thermal * (d_hardening * rate + hardening * d_rate)

    lo, hi = 0.0, trial / (3.0 * shear_modulus)
    x = min(hi, (trial - yield_stress(strength, plastic_strain, 0.0, temperature)) / (3.0 * shear_modulus))
    for _ in range(_RETURN_ITERATIONS):
        f = residual(x)
        if f == 0.0:
            return x
        if f > 0.0:
            lo = x
        else:
            hi = x
        df = slope(x)
        step = f / df if math.isfinite(df) and df < 0.0 else math.nan
        guess = x - step
        if not lo < guess < hi:
            guess = 0.5 * (lo + hi)
        if abs(guess - x) <= 1e-15 * hi or hi - lo <= 1e-15 * hi:
            return guess
        x = guess
    return x


def radial_return(solid: Solid, deviatoric_stress: np.ndarray, strain_increment: np.ndarray, plastic_strain: float,
                  temperature: float, dt: float) -> ReturnStep:
    """One J2 step: trial s + 2 G dev(d eps) (strain increment d eps = D dt, -), returned radially to sigma_y of
    eq. 10 at eps_p + d eps_p, plastic rate d eps_p / dt (dt in s) and the step's starting temperature (K); the
    identity (with zero plastic increment) inside the yield surface."""
    trial = deviatoric_stress + 2.0 * solid.shear_modulus * deviator(strain_increment)
    q_trial = von_mises(trial)
    static = yield_stress(solid.strength, plastic_strain, 0.0, temperature)
    if q_trial <= static:
        return ReturnStep(trial, 0.0, static, 0.0, 0.0)
    if static <= 0.0:  # molten: no deviatoric stress
        increment = q_trial / (3.0 * solid.shear_modulus)
        return ReturnStep(np.zeros((3, 3)), increment, 0.0, 0.0, 0.0)
    increment = _plastic_increment(solid.strength, q_trial, solid.shear_modulus, plastic_strain, temperature, dt)
    q_new = q_trial - 3.0 * solid.shear_modulus * increment
    work = q_new * increment
    rise = temperature_rise(work, solid.heat_fraction, solid.rho0, solid.heat_capacity)
    return ReturnStep(trial * (q_new / q_trial), increment, q_new, work, rise)


def corotate(tensor: np.ndarray, spin: np.ndarray, dt: float) -> np.ndarray:
    """R t R^T with R = exp(W dt), the exact solution over dt (s) of the Jaumann rotation dt/dt = W t - t W for a
    constant spin W = (L - L^T) / 2 (1/s)."""
    axis = np.array([spin[2, 1], spin[0, 2], spin[1, 0]]) * dt
    angle = float(np.linalg.norm(axis))
    if angle == 0.0:
        return tensor.copy()
    k = spin * dt / angle
    rotation = np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * (k @ k)
    return rotation @ tensor @ rotation.T


@dataclass(frozen=True)
class StressPath:
    """A homogeneous deformation's history, one row per step (the first row is the start): time (s), strain (-,
    the log strain rate * t in uniaxial strain, the shear gamma = rate * t in simple shear), Cauchy stress (Pa,
    n x 3 x 3), pressure (Pa), von Mises stress (Pa), equivalent plastic strain (-), temperature (K), damage (-),
    density (kg/m^3); failed_step is the first row with D >= 1 (None: no failure)."""

    time: np.ndarray
    strain: np.ndarray
    stress: np.ndarray
    pressure: np.ndarray
    equivalent_stress: np.ndarray
    plastic_strain: np.ndarray
    temperature: np.ndarray
    damage: np.ndarray
    density: np.ndarray
    failed_step: int | None


MODES = ("uniaxial_strain", "simple_shear")


def homogeneous_deformation(solid: Solid, mode: str, rate: float, final_strain: float, steps: int,
                            adiabatic: bool = True, temperature: float | None = None) -> StressPath:
    """A material point under a constant velocity gradient: uniaxial strain (L = rate e_x e_x) or simple shear
    (L = rate e_x e_y), rate in 1/s, up to final_strain (-) in `steps` steps, starting unstressed at `temperature`
    (K; default T0). Each step: half the Jaumann rotation, the radial return, the other half (Strang splitting),
    the density rho0 exp(-tr(L) t), the EOS pressure with the specific energy of the stress power, heating (eq. 12)
    when adiabatic, damage (eq. 13) and, once D >= 1, no deviatoric stress and no tension."""
    if mode not in MODES:
        raise OrchestratorError(f"mode = {mode!r}: allowed: {', '.join(MODES)}")
    if not (rate > 0.0 and final_strain > 0.0 and steps >= 1):
        raise OrchestratorError("rate (1/s) and final_strain must be above 0, steps at least 1")
    gradient = np.zeros((3, 3))
    gradient[0, 0 if mode == "uniaxial_strain" else 1] = rate
    stretching, spin = 0.5 * (gradient + gradient.T), 0.5 * (gradient - gradient.T)
    dt = final_strain / rate / steps
    start_temperature = solid.strength.room_temperature if temperature is None else temperature
    rows = {name: np.zeros(steps + 1) for name in ("pressure", "eq", "eps_p", "T", "D", "rho")}
    stress = np.zeros((steps + 1, 3, 3))
    rows["T"][0], rows["rho"][0] = start_temperature, solid.rho0
    s, energy, failed = np.zeros((3, 3)), 0.0, None
    for k in range(1, steps + 1):
        rho = solid.rho0 * math.exp(-np.trace(gradient) * k * dt)
        eps_p, temp, damage = rows["eps_p"][k - 1], rows["T"][k - 1], rows["D"][k - 1]
        increment = 0.0
        if failed is None:
            step = radial_return(solid, corotate(s, spin, 0.5 * dt), stretching * dt, eps_p, temp, dt)
            s, increment = corotate(step.deviatoric_stress, spin, 0.5 * dt), step.plastic_strain_increment
            temp += step.temperature_rise if adiabatic else 0.0
        pressure = solid.eos.pressure(rho, energy)
        q = von_mises(s)
        if solid.failure is not None and failed is None:
            homologous = homologous_temperature(temp, solid.strength.room_temperature,
                                                solid.strength.melting_temperature)
            eps_f = failure_strain(solid.failure, triaxiality(-pressure, q), increment / dt, homologous)
            damage += damage_increment(increment, eps_f)
            if damage >= 1.0:
                failed, s, q = k, np.zeros((3, 3)), 0.0
        if failed is not None:
            pressure = max(pressure, 0.0)
        sigma = s - pressure * np.eye(3)
        energy += float(np.sum(sigma * stretching)) * dt / rho
        stress[k] = sigma
        for name, value in zip(("pressure", "eq", "eps_p", "T", "D", "rho"),
                               (pressure, q, eps_p + increment, temp, damage, rho)):
            rows[name][k] = value
    time = np.arange(steps + 1) * dt
    return StressPath(time, rate * time, stress, rows["pressure"], rows["eq"], rows["eps_p"], rows["T"], rows["D"],
                      rows["rho"], failed)


def hutchings_crater_diameter(radius: float, speed: float, sphere_density: float, hardness: float) -> float:
    """Eq. 20, d = 2 r sqrt(2 v) (2 rho / (3 H))^(1/4) (m): sphere radius r (m), impact speed v (m/s), the sphere's
    density rho (kg/m^3; its kinetic energy is what the indentation absorbs), target hardness H (Pa)."""
    return 2.0 * radius * math.sqrt(2.0 * speed) * (2.0 * sphere_density / (3.0 * hardness)) ** 0.25


def hutchings_hardness(diameter: float, radius: float, speed: float, sphere_density: float) -> float:
    """Eq. 20 solved for H (Pa): the mean contact pressure that stops a sphere (radius m, speed m/s, density
    kg/m^3) in a crater of the given diameter (m)."""
    return 2.0 * sphere_density / 3.0 * (2.0 * radius * math.sqrt(2.0 * speed) / diameter) ** 4
