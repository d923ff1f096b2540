"""The rheometer kind: the case format and its errors, the mass-scaling criterion, the fit of eq. 17 on synthetic
stresses, the sample's lattice, and (with the executable) one UCM mode against Maxwell's G', G''."""

import math

import numpy as np
import pytest

from orchestrator.case import load_case
from orchestrator.errors import CaseError
from orchestrator.kinds import build_scene
from orchestrator.kinds.rheometer.analysis import fit_moduli, maxwell_moduli
from orchestrator.kinds.rheometer.physics import sample_numerics
from orchestrator.kinds.rheometer.scene import hexagonal_lattice
from orchestrator.run import run_case
from paths import REPO

CASES = REPO / "cases" / "rheometry"
UCM = CASES / "ucm_one_mode.toml"


def test_the_mass_scaling_meets_its_criterion():
    """The shear wave crosses the sample in T / N: L sqrt(rho / |G*|) = (2 pi / omega) / N."""
    for omega, n in ((0.1, 20.0), (10.0, 20.0), (10.0, 80.0)):
        case = load_case(UCM, overrides=[f"shear.omega={omega}", f"numerics.quasi_static={n}"]).model
        sn = sample_numerics(case)
        modulus = abs(case.material.complex_modulus(omega))  # G = 1000 Pa, lambda = 1 s
        assert modulus == pytest.approx(1000.0 * omega / math.sqrt(1 + omega**2), rel=1e-12)
        assert 0.01 * math.sqrt(sn.density / modulus) == pytest.approx(2 * math.pi / omega / n, rel=1e-12)
        assert sn.sound_speed == pytest.approx(10 * math.sqrt(1000.0 / sn.density), rel=1e-12)
        record = 2 * math.pi / omega / 64
        assert record / sn.dt == pytest.approx(round(record / sn.dt), abs=1e-9)  # whole steps per record
        assert sn.dt <= 0.1 * 1.3e-3 / sn.sound_speed * (1 + 1e-12)
        assert sn.rest_pressure == pytest.approx(10 * 1000.0, rel=1e-12)


def test_eq17_fit_returns_the_moduli_of_a_synthetic_stress_with_a_transient():
    omega, amplitude, g1, g2 = 3.0, 5e-4, 1234.0, 567.0
    t = np.linspace(0.0, 4 * 2 * np.pi / omega, 257)
    tau = amplitude * (g1 * np.sin(omega * t) + g2 * np.cos(omega * t)) - 0.1 * np.exp(-t / 20.0)
    fit = fit_moduli(t, tau, omega, amplitude, 2 * 2 * np.pi / omega, t[-1])
    assert fit["storage_modulus"] == pytest.approx(g1, rel=5e-4) and fit["loss_modulus"] == pytest.approx(g2, rel=5e-4)
    plain = np.linalg.lstsq(np.column_stack([np.sin(omega * t), np.cos(omega * t)]) * amplitude, tau, rcond=None)[0]
    assert abs(plain[1] / g2 - 1) > 10 * abs(fit["loss_modulus"] / g2 - 1)  # the offset terms matter


def test_maxwell_moduli_with_a_solvent():
    case = load_case(UCM, overrides=["material.solvent_viscosity=2.0"]).model
    g1, g2 = maxwell_moduli(case.material, 1.0)
    assert (g1, g2) == (pytest.approx(500.0), pytest.approx(502.0))  # G = 1000 Pa at lambda omega = 1, + eta_s omega


def test_the_sample_is_a_hexagonal_lattice_moving_with_the_shear():
    case = load_case(UCM).model
    scene = build_scene(case)
    positions, area = hexagonal_lattice(0.01, 10, 2)
    assert len(positions) == 120 and area == pytest.approx(1e-6 / 1.2)  # 10 x 12 rows
    assert np.allclose(scene.positions, positions) and scene.n_fluid == 120
    assert scene.masses.sum() == pytest.approx(sample_numerics(case).density * 1e-4, rel=1e-12)
    assert np.allclose(scene.velocities[:, 0], 5e-4 * 1.0 * (positions[:, 1] - 0.005))
    square = build_scene(load_case(UCM, overrides=["sample.lattice='square'"]).model)
    assert square.n_particles == 100


BAD = [
    (["shear.omega=-1.0"], "shear.omega"),
    (["shear={amplitude=5e-4}"], "shear.omega is missing"),
    (["shear={amplitude=5e-4, omega=1.0, shear_rate=1.0}"], "not both and not neither"),
    (["material.storage_plateau=-500.0"], "material.storage_plateau"),
    (["material.modes=[]"], "material.modes"),
    (["material.eos='ideal'"], "material.eos = 'ideal'"),
    (["sample.particles=2"], "sample.particles"),
    (["sample.dimension=3", "sample.lattice='hexagonal'"], "sample.lattice = 'hexagonal' is 2D only"),
    (["shear={shear_rate=1.0, duration=2.0, cycles=3}"], "shear.cycles counts oscillation cycles"),
    (["expected=[{check='steady_ptt', quantity='shear_viscosity', tolerance=0.02}]"], "steady_ptt rows need"),
    (["expected=[{check='saos_maxwell', quantity='viscosity', tolerance=0.02}]"], "is not measured by check"),
]


@pytest.mark.parametrize("overrides,words", BAD, ids=[w.split(" ")[0] for _, w in BAD])
def test_bad_rheometer_keys_are_named(overrides, words):
    with pytest.raises((CaseError, ValueError)) as error:
        build_scene(load_case(UCM, overrides=overrides).model)
    assert words in str(error.value)


@pytest.mark.sph
def test_one_ucm_mode_gives_maxwell_moduli(tmp_path):
    """lambda omega = 1: G' = G'' = G / 2 = 500 Pa (measured 0.01 %, 0.004 %)."""
    summary = run_case(load_case(UCM), out_dir=tmp_path / "run", progress=False)
    m = summary.measured
    assert m["storage_modulus"] == pytest.approx(500.0, rel=0.005)
    assert m["loss_modulus"] == pytest.approx(500.0, rel=0.005)
    assert m["velocity_profile"] < 0.01 and m["fit_residual"] < 0.01


def test_a_calibrate_maxwell_fragment_pastes_into_a_rheometer_case(tmp_path):
    """The fragment `calibrate maxwell --out` writes ([material], storage_plateau, [[material.modes]]) is the
    rheometer's [material]: Table III fitted from noise-free moduli comes back as the case's modes."""
    from orchestrator.reference.maxwell import TABLE_III, MaxwellFit
    from orchestrator.kinds.rheometer.calibration import write_fragment

    fit = MaxwellFit(TABLE_III, 0.0, None, "both", {"storage": 0.0, "loss": 0.0})
    fragment = write_fragment(fit, tmp_path / "fragment.toml", "synthetic")
    head = UCM.read_text().split("[material]")[0]
    tail = "\n[shear]\namplitude = 5.0e-4\nomega = 1.0\n"
    case_file = tmp_path / "pasted.toml"
    case_file.write_text(head + fragment.read_text() + tail)
    case = load_case(case_file).model
    assert [(m.relaxation_time, m.viscosity) for m in case.material.modes] == [
        (m.relaxation_time, m.viscosity) for m in TABLE_III]
    g = case.material.complex_modulus(1.0)
    assert (g.real, g.imag) == (pytest.approx(3928.24, rel=1e-5), pytest.approx(1462.55, rel=1e-5))
