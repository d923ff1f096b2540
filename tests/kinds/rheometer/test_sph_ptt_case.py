"""PTT materials and Lees-Edwards boundaries in an SPH flow case: the case format and its errors, the deck the
sph adapter writes, and (with the executable) the shear-stress, N1 and strain series and mode stresses in run.h5."""

import json

import numpy as np
import pytest

from orchestrator.case import load_case
from orchestrator.errors import CaseError
from orchestrator.kinds import build_scene
from orchestrator.kinds.sph_flow.sph import deck_context
from orchestrator.run import run_case
from orchestrator.runh5 import read_run
from paths import DATA

CELL = DATA / "sph_ptt_shear_cell.toml"


def test_ptt_material_and_lees_edwards_reach_the_deck():
    scene = build_scene(load_case(CELL).model)
    context = deck_context(scene)
    material = json.loads(context["materials"][0])
    assert material == {"name": "melt", "model": "ptt", "rho0": 1.0, "c0": 5.0, "eos": "quadratic",
                        "background_pressure": 0.0, "epsilon": 0.1, "solvent_viscosity": 0.0,
                        "modes": [{"lambda": 1.0, "eta": 1.0}]}
    assert json.loads(context["lees_edwards"]) == {"shear_rate": 1.0}
    oscillating = load_case(CELL, overrides=["lees_edwards={amplitude=5e-4, omega=6.0}"]).model
    assert json.loads(deck_context(build_scene(oscillating))["lees_edwards"]) == {"amplitude": 5e-4, "omega": 6.0}


def test_a_sheared_ptt_cell_takes_a_morris_solvent_and_the_mean_stress_subtraction():
    case = load_case(CELL, overrides=["physics.terms=['morris_viscosity']", "materials.0.solvent_viscosity=0.1",
                                      "lees_edwards={shear_rate=1.0, subtract_mean_stress=true}"]).model
    context = deck_context(build_scene(case))
    assert json.loads(context["physics"]) == ["morris_viscosity"]
    assert json.loads(context["lees_edwards"]) == {"shear_rate": 1.0, "subtract_mean_stress": True}


BAD = [
    (["materials.0.modes=[]"], "materials[0].modes (melt) is missing"),
    (["materials.0.modes=[{relaxation_time=1.0}]"], "materials[0].modes[0].viscosity: required key is missing"),
    (["materials.0.modes=[{relaxation_time=-1.0, viscosity=1.0}]"], "materials[0].modes[0].relaxation_time"),
    (["materials.0.viscosity=1e-3"], "materials[0].viscosity (melt) is not a key of a ptt material"),
    (["materials.0.eos='ideal'"], "unknown equation of state 'ideal'; allowed: tait, quadratic"),
    (["materials.0.gamma=5.0"], "materials[0].gamma (melt) is the Tait exponent"),
    (["numerics.dt=nan"], "numerics.dt"),
    (["materials.0.model='newtonian'"], "materials[0].modes (melt) is a key of a ptt material"),
    (["physics.terms=['morris_viscosity']"], "must be > 0 with 'morris_viscosity'"),
    (["lees_edwards={shear_rate=1.0, subtract_mean_stress=2}"], "lees_edwards.subtract_mean_stress"),
    (["lees_edwards={amplitude=5e-4}"], "lees_edwards.omega is missing"),
    (["lees_edwards={shear_rate=1.0, omega=2.0}"], "either shear_rate"),
    (["domain.periodic=[0]"], "domain.periodic must list axes 0 and 1"),
    (["lees_edwards={shear_rate=10.0}"], "above fluid.max_speed"),
]


@pytest.mark.parametrize("overrides,words", BAD, ids=[w.split(" ")[0] for _, w in BAD])
def test_bad_ptt_and_lees_edwards_keys_are_named(overrides, words):
    with pytest.raises(CaseError) as error:
        load_case(CELL, overrides=overrides)
    assert words in str(error.value)


def test_a_ptt_material_needs_a_fixed_step(tmp_path):
    text = CELL.read_text().replace("dt = 5e-5", "")
    path = tmp_path / "adaptive.toml"
    path.write_text(text)
    with pytest.raises(CaseError, match="numerics.dt is missing: a ptt material"):
        load_case(path)


@pytest.mark.sph
def test_run_h5_has_the_shear_series_and_mode_stresses(tmp_path):
    run_case(load_case(CELL, overrides=["simulation.duration=0.2", "output.frame_interval=0.1"]), out_dir=tmp_path / "run", progress=False)
    run = read_run(tmp_path / "run")
    series = run["series"]
    t = np.asarray(series["time"])
    assert np.allclose(series["shear_strain"], t, rtol=1e-12, atol=1e-15)  # gamma = gamma_dot t, gamma_dot = 1/s
    assert np.allclose(series["shear_rate"], 1.0)
    # start-up of UCM-like shear from rest (Wi small at t << lambda): tau_xy = eta (1 - exp(-t/lambda)) to O(eps)
    assert series["shear_stress"][-1] == pytest.approx(1.0 - np.exp(-0.2), rel=0.03)
    assert 0 < series["first_normal_stress_difference"][-1] < series["shear_stress"][-1]
    frame = run["frames"][str(max(int(k) for k in run["frames"] if k != "attrs"))]
    tau = np.asarray(frame["mode_stress"])
    assert tau.shape == (100, 1, 2, 2) and np.allclose(tau[:, 0, 0, 1], tau[:, 0, 1, 0])
    volume = 1.0 / np.asarray(frame["densities"])  # equal masses: the volume average weighs by 1/rho
    assert np.average(tau[:, 0, 0, 1], weights=volume) == pytest.approx(series["shear_stress"][-1], rel=1e-12)
