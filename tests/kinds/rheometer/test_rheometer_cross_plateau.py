"""The rheometer's plateau modulus G_p and Cross-law solvent: a `calibrate maxwell --plateau --cross` fragment
pastes in whole, bad values are named, the expected moduli (G_p in G', the solvent's first harmonic in G'') and
their quadrature, and (with the executable) the sample's G' and G'' against them within 1 %."""

import math

import numpy as np
import pytest

from orchestrator.case import load_case
from orchestrator.errors import CaseError
from orchestrator.kinds import build_scene
from orchestrator.kinds.rheometer.analysis import maxwell_moduli
from orchestrator.kinds.rheometer.calibration import write_fragment
from orchestrator.kinds.rheometer.checks import evaluate
from orchestrator.kinds.rheometer.physics import sample_numerics
from orchestrator.kinds.rheometer.solvent import cox_merz_loss_modulus, first_harmonic_loss_modulus
from orchestrator.reference.maxwell import TABLE_III, CrossLaw, MaxwellFit
from orchestrator.run import run_case
from paths import REPO

CASES = REPO / "cases" / "rheometry"
UCM = CASES / "ucm_one_mode.toml"
CROSS_PLATEAU = CASES / "cross_plateau_one_mode.toml"


def _pasted(tmp_path, fit) -> object:
    fragment = write_fragment(fit, tmp_path / "fragment.toml", "synthetic")
    head = UCM.read_text().split("[material]")[0]
    case_file = tmp_path / "pasted.toml"
    case_file.write_text(head + fragment.read_text() + "\n[shear]\namplitude = 5.0e-4\nomega = 1.0\n")
    return load_case(case_file).model


def test_a_plateau_and_cross_fragment_pastes_in_whole(tmp_path):
    law = CrossLaw(2.0e4, 12.0, 0.3, 0.8)
    case = _pasted(tmp_path, MaxwellFit(TABLE_III[:4], 150.0, law, "both", {"storage": 0.0, "loss": 0.0}))
    material = case.material
    assert material.storage_plateau == 150.0 and material.cross_loss.law == (2.0e4, 12.0, 0.3, 0.8)
    deck = build_scene(case).materials[0].deck()
    assert deck["storage_plateau"] == 150.0
    assert deck["cross_viscosity"] == {"eta_0": 2.0e4, "eta_inf": 12.0, "time_constant": 0.3, "exponent": 0.8}
    g = material.complex_modulus(1.0)  # the linear limit: G_p in G', (eta_s + eta_0) omega in G''
    modes = sum(m.modulus * (x := m.relaxation_time) ** 2 / (1 + x**2) for m in TABLE_III[:4])
    assert g.real == pytest.approx(150.0 + modes, rel=1e-12)
    assert material.solvent_shear_viscosity(1.0) == pytest.approx(law.viscosity(1.0), rel=1e-12)


BAD = [
    ("infinite_shear_viscosity = 3.0e4", "cross_loss.infinite_shear_viscosity"),
    ("exponent = 1.5", "cross_loss.exponent"),
    ("exponent = 0.0", "cross_loss.exponent"),
    ("time_constant = 0.0", "time_constant"),
]


@pytest.mark.parametrize("line,words", BAD, ids=[w for _, w in BAD])
def test_bad_cross_values_are_named(tmp_path, line, words):
    good = {"zero_shear_viscosity": "2.0e4", "infinite_shear_viscosity": "12.0", "time_constant": "0.3",
            "exponent": "0.8"}
    key, value = (part.strip() for part in line.split("="))
    table = "\n".join(f"{k} = {value if k == key else v}" for k, v in good.items())
    case_file = tmp_path / "bad.toml"
    case_file.write_text(UCM.read_text().replace("[shear]", f"[material.cross_loss]\n{table}\n\n[shear]"))
    with pytest.raises((CaseError, ValueError)) as error:
        build_scene(load_case(case_file).model)
    assert words in str(error.value)


@pytest.mark.parametrize("overrides,words", [
    (["material.storage_plateau=-1.0"], "material.storage_plateau"),
    (["material.storage_plateau=10.0", "shear={shear_rate=1.0, duration=2.0}"], "no steady state"),
])
def test_bad_plateau_values_are_named(overrides, words):
    with pytest.raises((CaseError, ValueError)) as error:
        build_scene(load_case(UCM, overrides=overrides).model)
    assert words in str(error.value)


def test_the_first_harmonic_of_a_generalized_newtonian_solvent():
    """Constant eta: G'' = eta omega. A Cross law: the quadrature against the Fourier coefficient of the sampled stress
    eta(|gamma_dot|) gamma_dot over one period, and below the linear limit eta_0 omega."""
    assert first_harmonic_loss_modulus(lambda rate: 7.0, 3.0, 0.1) == pytest.approx(21.0, rel=1e-12)
    law = CrossLaw(1000.0, 50.0, 20.0, 0.7)
    omega, amplitude = 2.0, 0.05
    s = np.linspace(0.0, 2 * np.pi, 200_001)[:-1]
    rate = amplitude * omega * np.cos(s)
    stress = law.viscosity(np.abs(rate)) * rate
    fourier = 2.0 * np.mean(stress * np.cos(s)) / amplitude
    exact = first_harmonic_loss_modulus(law.viscosity, omega, amplitude)
    assert exact == pytest.approx(fourier, rel=1e-8)
    assert 50.0 * omega < exact < 1000.0 * omega
    assert np.allclose(first_harmonic_loss_modulus(law.viscosity, [omega, omega], amplitude), exact, rtol=1e-14)
    assert cox_merz_loss_modulus(law.viscosity, omega) == pytest.approx(omega * law.viscosity(omega), rel=1e-14)


def test_the_expected_moduli_add_the_plateau_and_the_cross_solvent():
    case = load_case(CROSS_PLATEAU).model
    material, shear = case.material, case.shear
    g1, g2 = maxwell_moduli(material, shear.omega, shear.amplitude)
    mode = material.modes[0]
    x = mode.relaxation_time * shear.omega
    g = mode.viscosity / mode.relaxation_time
    assert g1 == pytest.approx(material.storage_plateau + g * x * x / (1 + x * x), rel=1e-12)
    solvent = first_harmonic_loss_modulus(material.cross_loss.viscosity, shear.omega, shear.amplitude)
    assert g2 == pytest.approx(g * x / (1 + x * x) + solvent, rel=1e-12)
    # the solvent thins over the cycle: its G'' is well below the linear limit and the check is not Newtonian
    assert solvent < 0.8 * material.cross_loss.zero_shear_viscosity * shear.omega
    sn = sample_numerics(case)
    assert sn.dt <= 0.125 * (1.3 * case.sample.dx) ** 2 * sn.density / material.cross_loss.zero_shear_viscosity


@pytest.mark.sph
def test_the_plateau_adds_to_g_storage_and_the_cross_solvent_gives_its_first_harmonic(tmp_path):
    """One UCM mode with G_p and a Cross solvent that thins over the cycle: G' and G'' within 1 % of
    G_p + Maxwell and Maxwell + the solvent's first harmonic (measured in docs/rheometry.md)."""
    case = load_case(CROSS_PLATEAU)
    summary = run_case(case, out_dir=tmp_path / "run", progress=False)
    m = summary.measured
    assert m["storage_modulus"] == pytest.approx(m["maxwell_storage_modulus"], rel=0.01)
    assert m["loss_modulus"] == pytest.approx(m["maxwell_loss_modulus"], rel=0.01)
    assert abs(m["cox_merz_loss_modulus"] / m["maxwell_loss_modulus"] - 1.0) > 0.05  # the two readings differ
    # the thinning solvent's stress is not sinusoidal: eq. 17's residual is its higher harmonics (2.39 % here)
    material, amplitude = case.model.material, case.model.shear.amplitude
    s = np.linspace(0.0, 2 * np.pi, 100_001)[:-1]
    rate = amplitude * case.model.shear.omega * np.cos(s)
    solvent = material.cross_loss.viscosity(np.abs(rate)) * rate
    higher = solvent - 2.0 * np.mean(solvent * np.cos(s)) * np.cos(s)
    harmonics = np.sqrt(np.mean(higher**2)) / (amplitude * math.hypot(m["maxwell_storage_modulus"],
                                                                      m["maxwell_loss_modulus"]))
    assert m["fit_residual"] == pytest.approx(harmonics, rel=0.05)


@pytest.mark.sph
def test_the_cross_solvent_gives_the_steady_shear_viscosity(tmp_path):
    """One PTT mode and a Cross solvent at gamma_dot = K^-1: tau_xy / gamma_dot = eta / f + eta_C within 1 % (measured
    1393.83 against 1393.83 Pa s), and the steady_viscosity check passes on it."""
    loaded = load_case(CASES / "cross_solvent_steady.toml")
    summary = run_case(loaded, out_dir=tmp_path / "run", progress=False)
    m = summary.measured
    material = loaded.model.material
    assert m["shear_viscosity_expected"] == pytest.approx(868.83 + float(material.cross_loss.viscosity(1.0)), rel=1e-5)
    assert m["shear_viscosity"] == pytest.approx(m["shear_viscosity_expected"], rel=0.01)
    rows, _ = evaluate(loaded.model, {"measured": {"attrs": m}})
    assert [row["passed"] for row in rows] == [True]
