"""Drag-finishing reductions: block-averaged standard error and peak contact forces."""

import math

import numpy as np
import pytest

from orchestrator.kinds.drag_finishing.forces import contact_force_peaks, standard_error


def ar1(rng, n: int, rho: float) -> np.ndarray:
    """An AR(1) series of unit variance and lag-one correlation rho."""
    noise = rng.normal(size=n) * math.sqrt(1 - rho**2)
    x = np.empty(n)
    x[0] = rng.normal()
    for i in range(1, n):
        x[i] = rho * x[i - 1] + noise[i]
    return x


def test_standard_error_of_a_correlated_series():
    """For AR(1) with rho = 0.8 the standard error of the mean is sqrt((1 + rho)/(1 - rho)) = 3 times the naive
    sigma/sqrt(n); block averaging recovers it (mean of 200 estimates within 10 %), the naive formula does not."""
    rng = np.random.default_rng(1)
    n, rho = 5000, 0.8
    expected = math.sqrt((1 + rho) / (1 - rho)) / math.sqrt(n)
    estimates = [standard_error(ar1(rng, n, rho)) for _ in range(200)]
    assert np.mean(estimates) == pytest.approx(expected, rel=0.10)
    assert 1 / math.sqrt(n) < 0.4 * expected  # what ignoring the correlation would report


def test_standard_error_needs_two_samples_per_block():
    assert math.isnan(standard_error(np.arange(19.0)))
    assert standard_error(np.ones(40)) == 0.0


def test_contact_force_peaks_use_the_last_snapshot():
    first = (0.5, {"normal_force": np.array([9.0, 9.0])})
    last = (1.5, {"normal_force": np.arange(101, dtype=float)})
    peaks = contact_force_peaks([first, last])
    assert peaks == {"contact_fn_max": 100.0, "contact_fn_p99": pytest.approx(99.0)}
    assert contact_force_peaks([]) == {}
