"""The numpy Johnson-Cook solid (orchestrator.reference.johnson_cook, solid_eos) against Nutto et al.'s Tables I and
II, closed forms of homogeneous deformation (uniaxial strain, Dienes' simple shear, adiabatic heating), the
Mie-Grueneisen EOS's reference slope and Hugoniot, Hutchings' eq. 20 for the paper's crater; and the expected values
written into the C++ test engines/sph/tests/test_johnson_cook.cpp recomputed here, so the two cannot drift."""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from orchestrator.errors import OrchestratorError
from orchestrator.reference import johnson_cook as jc
from orchestrator.reference import solid_eos as eos
from paths import REPO

CPP_TEST = REPO / "engines/sph/tests/test_johnson_cook.cpp"
STRENGTH, FAILURE = jc.AL6061_T6_STRENGTH, jc.AL6061_T6_FAILURE
SHEAR, BULK = 68.9e9 / (2 * 1.33), 68.9e9 / (3 * 0.34)  # Pa, E = 68.9 GPa, nu = 0.33
RHO, HEAT_CAPACITY, T0 = 2700.0, 896.0, 293.0  # kg/m^3, J/(kg K), K
AL_SHOCK = eos.MieGruneisen(rho0=2703.0, c0=5240.0, s=1.4, gamma0=1.97)  # Steinberg (1996), 6061-T6
GLASS_DENSITY, STEEL_DENSITY = 2500.0, 7810.0  # kg/m^3, soda-lime glass and 100Cr6


def _solid(strength=STRENGTH, failure=None) -> jc.Solid:
    return jc.Solid(SHEAR, eos.LinearEos(RHO, BULK), strength, failure, HEAT_CAPACITY, 0.95)


@pytest.mark.parametrize("plastic_strain, paper", [(0.1, 367.3e6), (0.2, 382.0e6), (0.5, 409.2e6)])
def test_table_one_yield_stress(plastic_strain, paper):
    assert jc.yield_stress(STRENGTH, plastic_strain, 0.0, T0) == pytest.approx(paper, rel=0.01)


@pytest.mark.parametrize("triaxiality, paper", [(1 / 3, 0.470), (0.0, 0.680), (-1 / 3, 0.926)])
def test_table_two_failure_strain_and_its_damage_count(triaxiality, paper):
    assert jc.failure_strain(FAILURE, triaxiality, 1e3, 0.0) == pytest.approx(paper, rel=0.02)
    damage, eps_p, increment = 0.0, 0.0, 1e-3
    while damage < 1.0:
        damage += jc.damage_increment(increment, jc.failure_strain(FAILURE, triaxiality, increment / 1e-6, 0.0))
        eps_p += increment
    assert eps_p == pytest.approx(paper, rel=0.02)


def test_rate_forms_temperatures_and_failure_limits():
    assert jc.rate_factor(0.0, 0.002, "power") == 1.0 and jc.rate_factor(0.5, 0.002, "log") == 1.0
    assert jc.rate_factor(1e3, 0.002, "power") == pytest.approx(1001.0 ** 0.002, rel=1e-15)
    assert jc.rate_factor(1e3, 0.002, "log") == pytest.approx(1.0 + 0.002 * math.log(1e3), rel=1e-15)
    assert jc.homologous_temperature(250.0, T0, 925.0) == 0.0 and jc.homologous_temperature(1e4, T0, 925.0) == 1.0
    assert jc.yield_stress(STRENGTH, 0.1, 0.0, 925.0) == 0.0
    assert jc.damage_increment(1e-3, -0.1) == math.inf and jc.damage_increment(0.0, 0.5) == 0.0


def test_bad_parameters_are_refused():
    with pytest.raises(OrchestratorError, match="rate_form"):
        dataclasses.replace(STRENGTH, rate_form="cowper")
    with pytest.raises(OrchestratorError, match="melting_temperature"):
        dataclasses.replace(STRENGTH, melting_temperature=200.0)
    with pytest.raises(OrchestratorError, match="bulk_modulus"):
        eos.LinearEos(RHO, -1.0)


def _fixed_return_inputs() -> tuple[np.ndarray, np.ndarray]:
    """The deviatoric stress (Pa) and strain increment (-) of the C++ test's fixed_deviator / fixed_strain_increment."""
    s = np.array([[50, 20, -10], [20, -30, 5], [-10, 5, -20]]) * 1e6
    d_eps = np.array([[12e-3, 4e-3, 0.0], [4e-3, -4e-3, 2e-3], [0.0, 2e-3, 8e-4]])
    return s, d_eps


@pytest.mark.parametrize("form", jc.RATE_FORMS)
def test_radial_return_lands_on_the_yield_surface_and_is_the_identity_inside(form):
    strength = dataclasses.replace(STRENGTH, rate_form=form)
    s, d_eps = _fixed_return_inputs()
    plastic_steps = 0
    for scale in (0.3, 1.0, 5.0, 40.0):
        for eps_p in (0.0, 0.05, 0.8):
            step = jc.radial_return(_solid(strength), s, scale * d_eps, eps_p, 350.0, 1e-6)
            dep = step.plastic_strain_increment
            surface = jc.yield_stress(strength, eps_p + dep, dep / 1e-6, 350.0)
            if dep > 0.0:
                plastic_steps += 1
                assert jc.von_mises(step.deviatoric_stress) == pytest.approx(surface, rel=1e-12)
                assert step.temperature_rise == pytest.approx(0.95 * surface * dep / (RHO * HEAT_CAPACITY), rel=1e-12)
            else:
                trial = s + 2.0 * SHEAR * jc.deviator(scale * d_eps)
                assert np.array_equal(step.deviatoric_stress, trial) and jc.von_mises(trial) <= surface
    assert 0 < plastic_steps < 12


def _richardson_slope(pressure, side: float) -> float:
    """dp/dmu at mu = 0 from one side, third-order Richardson extrapolation over h, h/2, h/4."""
    slope = [pressure(side * h) / (side * h) for h in (1e-4, 5e-5, 2.5e-5)]
    first = [2 * slope[1] - slope[0], 2 * slope[2] - slope[1]]
    return (4 * first[1] - first[0]) / 3


@pytest.mark.parametrize("equation", [AL_SHOCK, eos.LinearEos(RHO, BULK)], ids=["mie_gruneisen", "linear"])
def test_eos_is_continuous_at_the_reference_with_the_bulk_modulus_as_slope(equation):
    def pressure(mu):
        return equation.pressure(equation.rho0 * (1.0 + mu), 0.0)
    assert pressure(0.0) == 0.0
    assert abs(pressure(1e-14) - pressure(-1e-14)) <= 3e-14 * equation.reference_bulk_modulus
    for side in (1.0, -1.0):
        assert _richardson_slope(pressure, side) == pytest.approx(equation.reference_bulk_modulus, rel=1e-9)


@pytest.mark.parametrize("particle_velocity", [100.0, 500.0, 1500.0])
def test_mie_gruneisen_holds_the_hugoniot(particle_velocity):
    rho, p_shock, e_shock = AL_SHOCK.hugoniot(particle_velocity)
    assert AL_SHOCK.pressure(rho, e_shock) == pytest.approx(p_shock, rel=1e-12)
    with pytest.raises(OrchestratorError, match="Hugoniot"):
        AL_SHOCK.pressure(AL_SHOCK.rho0 * 3.6)


def _uniaxial_plastic_strain(strain: float, temperature_of=lambda eps_p: T0) -> float:
    """eps_p on the uniaxial-strain plastic branch: 2 G eps - 3 G eps_p = sigma_y(eps_p, T(eps_p)), rate-free."""
    def residual(eps_p):
        return 2 * SHEAR * strain - 3 * SHEAR * eps_p - jc.yield_stress(STRENGTH, eps_p, 0.0, temperature_of(eps_p))
    return brentq(residual, 0.0, 2 * strain / 3, xtol=1e-15, rtol=1e-14) if residual(0.0) > 0 else 0.0


def test_uniaxial_strain_follows_the_elastic_slope_then_the_hardening_curve():
    path = jc.homogeneous_deformation(_solid(), "uniaxial_strain", 1e-3, 0.3, 2000, adiabatic=False)
    eps = path.strain[1:]
    slope = path.stress[1, 0, 0] / eps[0]
    print(f"elastic slope {slope / 1e9:.5g} GPa, K + 4G/3 = {(BULK + 4 * SHEAR / 3) / 1e9:.5g} GPa")
    assert slope == pytest.approx(BULK + 4 * SHEAR / 3, rel=1e-3)
    eps_p = np.array([_uniaxial_plastic_strain(e) for e in eps])
    q = np.minimum(2 * SHEAR * eps, [jc.yield_stress(STRENGTH, e, 0.0, T0) for e in eps_p])
    closed = BULK * (1 - np.exp(-eps)) + 2 / 3 * q
    assert eps_p[-1] > 0.15 and np.all(path.plastic_strain[1:][eps_p == 0] == 0)
    assert np.max(np.abs(path.stress[1:, 0, 0] / closed - 1)) < 1e-5
    assert np.max(np.abs(path.equivalent_stress[1:] / q - 1)) < 1e-5
    assert np.max(np.abs(path.plastic_strain[1:] - eps_p)) < 1e-5


@pytest.mark.parametrize("form", jc.RATE_FORMS)
def test_perfect_plasticity_at_a_high_rate_holds_the_rate_factor(form):
    strength = dataclasses.replace(STRENGTH, B=0.0, rate_form=form)
    path = jc.homogeneous_deformation(_solid(strength), "uniaxial_strain", 1e4, 0.5, 2000, adiabatic=False)
    # steady plastic flow in uniaxial strain: d eps_p = 2/3 d eps, so epsdot_p = 2/3 of the applied rate
    expected = strength.A * jc.rate_factor(2 / 3 * 1e4, strength.C, form)
    assert path.equivalent_stress[-1] == pytest.approx(expected, rel=1e-6)
    assert expected / strength.A - 1 > 0.015


def test_adiabatic_heating_is_the_plastic_work_and_follows_the_closed_form():
    path = jc.homogeneous_deformation(_solid(), "uniaxial_strain", 1e-3, 0.5, 4000, adiabatic=True)
    rise = path.temperature[-1] - T0
    work = np.trapezoid(path.equivalent_stress, path.plastic_strain)
    # closed form: dT/d eps_p = chi sigma_y(eps_p, T) / (rho C_p), then eps_p from 2 G eps - 3 G eps_p = sigma_y
    heating = solve_ivp(lambda e, t: [0.95 * jc.yield_stress(STRENGTH, e, 0.0, t[0]) / (RHO * HEAT_CAPACITY)],
                        (0.0, 0.4), [T0], rtol=1e-11, atol=1e-9, dense_output=True)
    eps_p = _uniaxial_plastic_strain(0.5, lambda e: float(heating.sol(e)[0]))
    closed_rise = float(heating.sol(eps_p)[0]) - T0
    print(f"eps_p {path.plastic_strain[-1]:.5f} (closed {eps_p:.5f}); dT {rise:.4f} K, "
          f"chi W_p / (rho C_p) {0.95 * work / (RHO * HEAT_CAPACITY):.4f} K, closed form {closed_rise:.4f} K")
    assert rise == pytest.approx(0.95 * work / (RHO * HEAT_CAPACITY), rel=0.01)
    assert rise == pytest.approx(closed_rise, rel=0.01)
    assert path.plastic_strain[-1] == pytest.approx(eps_p, rel=1e-4)
    assert rise > 40.0  # large enough that the softening shapes the path


def test_elastic_simple_shear_is_dienes_closed_form():
    path = jc.homogeneous_deformation(_solid(dataclasses.replace(STRENGTH, A=1e15)), "simple_shear", 1.0, 2.0, 1000)
    gamma = path.strain[-1]
    assert path.stress[-1, 0, 1] == pytest.approx(SHEAR * math.sin(gamma), rel=1e-5)
    assert path.stress[-1, 0, 0] == pytest.approx(SHEAR * (1 - math.cos(gamma)), rel=1e-5)
    assert path.stress[-1, 1, 1] == pytest.approx(-SHEAR * (1 - math.cos(gamma)), rel=1e-5)


def test_simple_shear_fails_at_the_zero_triaxiality_strain_and_then_holds_no_tension():
    path = jc.homogeneous_deformation(_solid(failure=FAILURE), "simple_shear", 1e3, 2.0, 4000, adiabatic=False)
    assert path.failed_step is not None
    print(f"failed at eps_p {path.plastic_strain[path.failed_step]:.4f} (eps_f at sigma* = 0: 0.680)")
    assert path.plastic_strain[path.failed_step] == pytest.approx(0.680, rel=0.02)
    after = slice(path.failed_step, None)
    assert np.all(path.equivalent_stress[after] == 0) and np.all(path.pressure[after] >= 0)
    tension = jc.homogeneous_deformation(_solid(failure=FAILURE), "uniaxial_strain", 1e3, 0.05, 200)
    assert tension.failed_step is not None and np.all(tension.stress[tension.failed_step:] == 0)


def test_hutchings_crater_of_the_glass_sphere():
    radius, speed, diameter = 300e-6, 100.0, 400e-6  # m, m/s, m: the paper's 600 um sphere and 400 um crater
    hardness = jc.hutchings_hardness(diameter, radius, speed, GLASS_DENSITY)
    print(f"H {hardness / 1e9:.4f} GPa (sphere density), "
          f"{jc.hutchings_hardness(diameter, radius, speed, STEEL_DENSITY) / 1e9:.4f} GPa (target density)")
    assert hardness == pytest.approx(0.34e9, rel=0.05)
    assert jc.hutchings_crater_diameter(radius, speed, GLASS_DENSITY, hardness) == pytest.approx(diameter, rel=1e-14)
    ratio = jc.hutchings_crater_diameter(radius, 4 * speed, GLASS_DENSITY, hardness) / diameter
    assert ratio == pytest.approx(2.0, rel=1e-14)


def _cross_check_values() -> dict[str, float]:
    """The quantities the C++ test compares with constants of the same names (see the calls named there)."""
    log = dataclasses.replace(STRENGTH, rate_form="log")
    failure = dataclasses.replace(FAILURE, D4=0.011)
    values = {
        "kYieldPower": jc.yield_stress(STRENGTH, 0.3, 500.0, 400.0),
        "kYieldLog": jc.yield_stress(log, 0.3, 500.0, 400.0),
        "kFailureStrain": jc.failure_strain(failure, 0.2, 500.0, jc.homologous_temperature(400.0, T0, 925.0)),
        "kMieGruneisenCompressed": AL_SHOCK.pressure(1.1 * 2703.0, 2.0e5),
        "kMieGruneisenExpanded": AL_SHOCK.pressure(0.95 * 2703.0, 2.0e5),
        "kHutchingsDiameter": jc.hutchings_crater_diameter(300e-6, 100.0, 2500.0, 0.34e9),
        "kHutchingsHardness": jc.hutchings_hardness(400e-6, 300e-6, 100.0, 2500.0),
    }
    s, d_eps = _fixed_return_inputs()
    for tag, strength in (("Power", STRENGTH), ("Log", log)):
        solid = jc.Solid(26.0e9, eos.LinearEos(2700.0, 70e9), strength)
        step = jc.radial_return(solid, s, d_eps, 0.05, 350.0, 1e-6)
        values |= {f"kReturn{tag}Increment": step.plastic_strain_increment, f"kReturn{tag}Yield": step.yield_stress,
                   f"kReturn{tag}Sxx": step.deviatoric_stress[0, 0], f"kReturn{tag}Sxy": step.deviatoric_stress[0, 1],
                   f"kReturn{tag}Syz": step.deviatoric_stress[1, 2], f"kReturn{tag}Heating": step.temperature_rise}
    return values


def test_the_cpp_test_holds_the_reference_values():
    constants = {name: float(value) for name, value in
                 re.findall(r"constexpr double (k\w+) = ([-+0-9.eE]+);", CPP_TEST.read_text())}
    values = _cross_check_values()
    assert set(values) <= set(constants), f"missing in {CPP_TEST.name}: {sorted(set(values) - set(constants))}"
    for name, value in values.items():
        assert constants[name] == pytest.approx(value, rel=1e-12), name
