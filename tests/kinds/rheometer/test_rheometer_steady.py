"""The rheometer's steady mode: the shear-rate sweep's inputs and run lengths, the steady sample's numerics (the
mean-stress subtraction and the Morris damping), and (with the executable) one linear PTT mode at Wi = 5,
epsilon = 0.01 — unstable within one relaxation time before the cure — following the ODE start-up through its
overshoot."""

import math

import numpy as np
import pytest

from orchestrator.case import load_case
from orchestrator.cli import main
from orchestrator.errors import OrchestratorError
from orchestrator.kinds.rheometer.commands.rheometry_steady import rates_of, steady_duration
from orchestrator.kinds.rheometer.physics import sample_numerics
from orchestrator.reference.viscoelastic_flows import ptt_f_in_shear, ptt_startup_shear
from orchestrator.run import run_case
from paths import REPO

ROOT = REPO
UCM = ROOT / "cases" / "rheometry" / "ucm_one_mode.toml"
STEADY = ["shear={shear_rate=5.0, duration=4.0}", "material.epsilon=0.01"]


def test_rates_are_sorted_and_zero_is_refused(capsys):
    assert rates_of(UCM, [10.0, 0.1, 10.0]) == [0.1, 10.0]
    with pytest.raises(OrchestratorError, match="--shear-rates 0: allowed: shear rates above 0"):
        rates_of(UCM, [1.0, 0.0])
    assert main(["rheometry", str(UCM), "--shear-rates", "0"]) == 2
    err = capsys.readouterr().err
    assert err.count("error:") == 1 and "--shear-rates 0" in err and "Traceback" not in err


def test_a_run_lasts_the_slowest_approach_to_steady_state():
    material = load_case(UCM, overrides=["material.epsilon=0.1"]).model.material  # lambda = 1 s
    f = float(ptt_f_in_shear(100.0, 0.1))
    assert steady_duration(material, 100.0, 10.0) == pytest.approx(10.0 / f, rel=1e-12)
    assert steady_duration(material, 1000.0, 1.0) == pytest.approx(1.0 / float(ptt_f_in_shear(1000.0, 0.1)),
                                                                   rel=1e-12)
    assert steady_duration(material, 0.01, 10.0) == pytest.approx(10.0 / float(ptt_f_in_shear(0.01, 0.1)), rel=1e-12)


def test_a_steady_sample_subtracts_its_mean_stress_and_is_damped():
    case = load_case(UCM, overrides=[*STEADY, "material.solvent_viscosity=2.0"]).model
    sn = sample_numerics(case)
    expected = 1000.0 / float(ptt_f_in_shear(5.0, 0.01))
    assert sn.subtract_mean_stress and sn.morris_viscosity == pytest.approx(2.0 + 0.1 * expected, rel=1e-12)
    h = case.sample.h_over_dx * case.sample.dx  # the mode stresses diffuse with kappa = 0.1 h^2 gamma_dot (eq. SD1)
    assert sn.stress_diffusion == pytest.approx(0.1 * h * h * 5.0, rel=1e-12)
    assert sn.dt <= 0.125 * h * h / sn.stress_diffusion
    off = sample_numerics(load_case(UCM, overrides=[*STEADY, "numerics.damping_viscosity_ratio=0.0",
                                                    "numerics.subtract_mean_stress=false",
                                                    "numerics.stress_diffusion_ratio=0.0"]).model)
    assert off.morris_viscosity == 0.0 and not off.subtract_mean_stress and off.stress_diffusion == 0.0
    oscillating = sample_numerics(load_case(UCM).model)  # the SAOS sample is unchanged
    assert oscillating.morris_viscosity == 0.0 and not oscillating.subtract_mean_stress
    assert oscillating.stress_diffusion == 0.0


@pytest.mark.parametrize("override,key", [("material.modes=[{relaxation_time=0.0, viscosity=1.0}]",
                                           "relaxation_time"),
                                          ("material.epsilon=-0.1", "material.epsilon")])
def test_bad_material_keys_are_named(override, key, capsys):
    assert main(["rheometry", str(UCM), "--shear-rates", "1", "--set", override]) == 2
    err = capsys.readouterr().err
    assert err.count("error:") == 1 and key in err


@pytest.mark.sph
def test_wi5_follows_the_startup_ode_through_its_overshoot(tmp_path):
    summary = run_case(load_case(UCM, overrides=STEADY), engine="sph", out_dir=tmp_path / "run", progress=False)
    assert summary.status == "ok"
    m = summary.measured
    assert m["velocity_profile"] < 1e-6  # the sample moves with the imposed shear
    assert m["startup_peak_shear_stress"] == pytest.approx(m["startup_peak_shear_stress_expected"], rel=1e-3)
    import h5py

    with h5py.File(tmp_path / "run" / "run.h5", "r") as h5:
        t = h5["series/time"][()]
        tau = h5["series/shear_stress"][()]
    exact = ptt_startup_shear(t, 5.0, load_case(UCM, overrides=STEADY).model.material.modes, 0.01)
    assert np.abs(tau - exact.shear_stress).max() < 1e-3 * exact.peak_shear_stress
    assert m["startup_deviation"] == pytest.approx(np.abs(tau - exact.shear_stress).max()
                                                   / np.abs(exact.shear_stress).max(), rel=1e-6)
    assert math.isclose(m["mode1_first_normal_stress_difference"], 29715.65, rel_tol=0.02)  # near steady at 4 s


@pytest.mark.sph
def test_mf20_at_its_lowest_rate_gives_the_closed_form_n1(tmp_path):
    """The paper's five modes at 0.01 1/s (Wi of the 5 s mode 0.05): N1 = 17.7 Pa is 1e-4 of the sample's pressure
    scale and was 10-20 % off while the run went on past the lattice's first rearrangement (strain 0.58); the run
    now lasts 10 of the slowest mode's times (50 s, strain 0.5)."""
    from orchestrator.kinds.rheometer.commands.rheometry_steady import run_rate

    point = run_rate(ROOT / "cases" / "rheometry" / "mf20_table3.toml", 0.01, tmp_path / "run", 10.0)
    assert point.status == "ok" and point.duration == pytest.approx(50.0, rel=1e-3)
    assert point.viscosity_error < 0.01 and point.n1_error < 0.02
    assert point.n1_expected == pytest.approx(17.674, rel=1e-3)
    assert point.startup_deviation < 0.01  # the whole start-up against the ODE (no overshoot at this Wi)


def test_the_flow_curve_marks_a_stopped_run(tmp_path, monkeypatch):
    """A point whose run stopped (unstable) is drawn apart, as a grey cross labelled as such, not as a measured SPH
    point: both panels hold one 'SPH' and one 'run stopped' series with the right rates."""
    from orchestrator.kinds.rheometer.commands import rheometry_steady as steady
    from paths import CASES

    drawn = {}

    def keep(fig, path):
        drawn["axes"] = fig.axes
        return path

    monkeypatch.setattr(steady, "save_pyplot_figure", keep)
    points = [steady.FlowCurvePoint(shear_rate=1.0, viscosity=9482.0, n1=41040.0),
              steady.FlowCurvePoint(shear_rate=100.0, viscosity=636.0, n1=1.44e6, status="failed")]
    steady.plot_flow_curve(CASES / "rheometry" / "mf20_table3.toml", points, tmp_path / "flow_curve.png")
    for ax in drawn["axes"]:
        series = {line.get_label(): line.get_xdata().tolist() for line in ax.get_lines()}
        assert series["SPH"] == [1.0] and series["SPH, run stopped (its last values)"] == [100.0]
