"""The settling sphere's closed forms (orchestrator/reference/settling.py): Stokes' drag, Hasimoto's (1959)
periodic-array factor against Zick & Homsy's (1982) exact values for the simple cubic array, the terminal speed's
balance."""

import math

import pytest

from orchestrator.reference.settling import (
    hasimoto_factor,
    periodic_terminal_speed,
    solid_fraction,
    stokes_drag,
)


def test_stokes_drag_is_six_pi_mu_a_u():
    assert stokes_drag(2.0, 0.5, 3.0) == pytest.approx(6.0 * math.pi * 3.0, rel=1e-15)


def test_hasimoto_factor_tends_to_one_and_matches_the_tabulated_values():
    assert hasimoto_factor(0.0) == 1.0
    assert hasimoto_factor(1e-9) == pytest.approx(1.0 + 1.7601e-3, rel=1e-5)  # the c^(1/3) term leads
    # Zick & Homsy (1982), Table 2, simple cubic array (K against c): the truncated series within 0.1 % at
    # c = 0.027 and 0.7 % at c = 0.064; 5.6 % high at c = 0.125, beyond the range the checks use.
    assert hasimoto_factor(0.027) == pytest.approx(2.008, rel=1e-3)
    assert hasimoto_factor(0.064) == pytest.approx(2.810, rel=7e-3)
    assert hasimoto_factor(0.125) == pytest.approx(4.292 * 1.056, rel=5e-3)


def test_solid_fraction_and_terminal_speed_balance():
    c = solid_fraction(1.0, 4.0)
    assert c == pytest.approx(math.pi / 48.0, rel=1e-15)
    u = periodic_terminal_speed(2000.0, 1000.0, 0.1, 9.81, 1e-3, 8e-3)
    weight = 1000.0 * 9.81 * 4.0 / 3.0 * math.pi * 1e-9  # (rho_s - rho_f) V g: Hasimoto's F includes the buoyancy
    assert stokes_drag(0.1, 1e-3, u) * hasimoto_factor(solid_fraction(1e-3, 8e-3)) == pytest.approx(weight, rel=1e-14)
    # hindered settling: U / U_Stokes = 1 / K
    assert u == pytest.approx(2.0 / 9.0 * 1000.0 * 9.81 * 1e-6 / 0.1 / hasimoto_factor(solid_fraction(1e-3, 8e-3)), rel=1e-14)


def test_hasimoto_factor_refuses_fractions_outside_the_series():
    with pytest.raises(ValueError, match="outside"):
        hasimoto_factor(0.3)
