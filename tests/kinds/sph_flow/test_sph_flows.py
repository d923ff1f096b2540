"""Series solutions of Morris et al. (1997) against their limits, and the hydrostatic column."""

import math

import numpy as np
import pytest

from orchestrator.reference.sph_flows import (
    MORRIS1997,
    couette_steady_velocity,
    couette_velocity,
    hydrostatic_pressure,
    poiseuille_steady_velocity,
    poiseuille_velocity,
    tait_density,
)

L, NU, F, V0 = MORRIS1997.gap, MORRIS1997.viscosity, MORRIS1997.body_force, MORRIS1997.plate_speed
Y = np.linspace(0.0, L, 41)


def test_paper_parameters_give_the_papers_peak_speed():
    assert MORRIS1997.poiseuille_peak == pytest.approx(2.5e-5, rel=1e-12)
    assert MORRIS1997.diffusion_time == pytest.approx(1.0, rel=1e-12)


def test_poiseuille_starts_from_rest_and_ends_on_the_parabola():
    assert np.max(np.abs(poiseuille_velocity(Y, 0.0, L, NU, F))) < 1e-6 * MORRIS1997.poiseuille_peak
    late = poiseuille_velocity(Y, 5.0, L, NU, F)
    np.testing.assert_allclose(late, poiseuille_steady_velocity(Y, L, NU, F), atol=1e-12 * 2.5e-5)
    assert poiseuille_steady_velocity(L / 2, L, NU, F) == pytest.approx(F * L**2 / (8 * NU))


def test_poiseuille_obeys_the_diffusion_equation():
    # u_t = nu u_yy + F, by finite differences of the series at an intermediate time
    t, dt, dy = 0.1, 1e-5, 1e-6
    y = np.linspace(0.1 * L, 0.9 * L, 9)
    u_t = (poiseuille_velocity(y, t + dt, L, NU, F) - poiseuille_velocity(y, t - dt, L, NU, F)) / (2 * dt)
    u_yy = (poiseuille_velocity(y + dy, t, L, NU, F) - 2 * poiseuille_velocity(y, t, L, NU, F)
            + poiseuille_velocity(y - dy, t, L, NU, F)) / dy**2
    np.testing.assert_allclose(u_t, NU * u_yy + F, rtol=1e-4)


def test_poiseuille_centre_relaxes_with_the_first_mode():
    # late in the start-up only n = 1 is left: u_peak - u(L/2, t) = 4 F L^2/(nu pi^3) exp(-pi^2 nu t / L^2)
    t = 0.4
    deficit = MORRIS1997.poiseuille_peak - poiseuille_velocity(L / 2, t, L, NU, F)
    first = 4 * F * L**2 / (NU * math.pi**3) * math.exp(-math.pi**2 * NU * t / L**2)
    assert deficit == pytest.approx(first, rel=1e-6)


def test_couette_starts_from_rest_and_ends_linear():
    inner = Y[1:-1]  # at t = 0 the plate jumps: the series converges like 1/n inside
    assert np.max(np.abs(couette_velocity(inner, 0.0, L, NU, V0, n_terms=20000))) < 2e-3 * V0
    np.testing.assert_allclose(couette_velocity(Y, 5.0, L, NU, V0), couette_steady_velocity(Y, L, V0),
                               atol=1e-12 * V0)
    assert couette_velocity(L, 0.05, L, NU, V0) == pytest.approx(V0, abs=1e-12)  # the plate itself
    assert couette_velocity(0.0, 0.05, L, NU, V0) == pytest.approx(0.0, abs=1e-15)


def test_couette_obeys_the_diffusion_equation():
    t, dt, dy = 0.05, 1e-5, 1e-6
    y = np.linspace(0.1 * L, 0.9 * L, 9)
    u_t = (couette_velocity(y, t + dt, L, NU, V0) - couette_velocity(y, t - dt, L, NU, V0)) / (2 * dt)
    u_yy = (couette_velocity(y + dy, t, L, NU, V0) - 2 * couette_velocity(y, t, L, NU, V0)
            + couette_velocity(y - dy, t, L, NU, V0)) / dy**2
    np.testing.assert_allclose(u_t, NU * u_yy, rtol=1e-4, atol=1e-9 * V0)


def test_hydrostatic_pressure_is_linear_and_zero_above_the_surface():
    y = np.array([0.0, 0.25, 0.5, 0.6])
    np.testing.assert_allclose(hydrostatic_pressure(y, 0.5, 1000.0, 9.81), [4905.0, 2452.5, 0.0, 0.0])


def test_tait_density_inverts_the_equation_of_state():
    rho0, c0 = 1000.0, 20.0
    rho = tait_density(4905.0, rho0, c0)
    p = rho0 * c0**2 / 7 * ((rho / rho0) ** 7 - 1)
    assert p == pytest.approx(4905.0, rel=1e-12)
    assert rho > rho0


# --- measured dam-break surge fronts (orchestrator.reference.dam_break_data) ---

from orchestrator.reference.dam_break_data import (  # noqa: E402
    KOSHIZUKA_OKA,
    MARTIN_MOYCE_LARGE,
    MARTIN_MOYCE_LETHE,
    MARTIN_MOYCE_SMALL,
    SURGE_FRONT_DATA,
    dimensionless_front,
    dimensionless_time,
)


def test_surge_front_series_are_monotone_and_start_at_the_column():
    for data in SURGE_FRONT_DATA.values():
        assert len(data.T) == len(data.Z) >= 9, data.name
        assert np.all(np.diff(data.T) > 0) and np.all(np.diff(data.Z) > 0), data.name
        assert 1.0 <= data.Z[0] < 1.3 and data.height_ratio == 2.0, data.name
        assert data.digitised_by.startswith("https://github.com/"), data.name


def test_two_digitisations_of_martin_and_moyce_agree_within_three_percent():
    # PySPH's and Lethe's numbers were read off the paper independently; they measure the digitising error
    T = np.array(MARTIN_MOYCE_LETHE.T)
    for data in (MARTIN_MOYCE_SMALL, MARTIN_MOYCE_LARGE):
        z = data.front_at(T)
        inside = np.isfinite(z)
        assert inside.sum() >= 10
        assert np.max(np.abs(z[inside] / np.array(MARTIN_MOYCE_LETHE.Z)[inside] - 1)) < 0.03, data.name
    assert np.isnan(MARTIN_MOYCE_SMALL.front_at(0.5))  # before the first measurement: no value


def test_dimensionless_variables_use_twice_g():
    a = KOSHIZUKA_OKA.column_width
    assert dimensionless_time(1.0, a, 9.81) == pytest.approx(math.sqrt(2 * 9.81 / 0.146))
    assert dimensionless_front(2 * a, a) == pytest.approx(2.0)
