"""Several materials in an SPH flow case: the [[materials]] syntax and its errors, the deck and particle file the
adapter writes, the steady two-layer Poiseuille and Couette profiles against their defining conditions, and the
two-layer checks on synthetic runs (the verify scenes themselves run in test_verify_sph.py)."""

from __future__ import annotations

import json

import h5py
import numpy as np
import pytest

from orchestrator.case import load_case
from orchestrator.cli import main
from orchestrator.errors import CaseError, OrchestratorError
from orchestrator.kinds import bind, build_scene
from orchestrator.kinds.sph_flow.checks import check_poiseuille
from orchestrator.kinds.sph_flow.checks_layers import check_two_layer_couette, check_two_layer_poiseuille
from orchestrator.kinds.sph_flow.sph import _frame_material
from orchestrator.reference import sph as ref
from orchestrator.runh5 import read_run
from orchestrator.reference.sph_flows import (
    couette_steady_velocity,
    poiseuille_steady_velocity,
    two_layer_couette_velocity,
    two_layer_poiseuille_velocity,
)
from paths import VERIFICATION

POISEUILLE = VERIFICATION / "sph_two_layer_poiseuille.toml"
COUETTE = VERIFICATION / "sph_two_layer_couette.toml"
CHANNEL_1 = VERIFICATION / "sph_poiseuille_morris1997.toml"


# ------------------------------------------------------------------------------------------ analytic profiles
def test_two_layer_profiles_reduce_to_one_layer_for_equal_fluids():
    y = np.linspace(0.0, 1e-3, 201)
    for h1 in (2e-4, 5e-4, 9e-4):
        two = two_layer_poiseuille_velocity(y, h1, 1e-3, 1000.0, 1000.0, 1e-3, 1e-3, 2e-4)
        np.testing.assert_allclose(two, poiseuille_steady_velocity(y, 1e-3, 1e-6, 2e-4), rtol=1e-12, atol=1e-20)
        two = two_layer_couette_velocity(y, h1, 1e-3, 1e-3, 1e-3, 2.5e-5)
        np.testing.assert_allclose(two, couette_steady_velocity(y, 1e-3, 2.5e-5), rtol=1e-12, atol=1e-20)


@pytest.mark.parametrize("rho1,rho2,mu1,mu2", [(1000.0, 500.0, 1e-3, 2e-3), (800.0, 2000.0, 5e-3, 1e-3)])
def test_two_layer_poiseuille_satisfies_its_conditions(rho1, rho2, mu1, mu2):
    """No slip at both plates; u and mu du/dy continuous at the interface; mu_i u'' = -rho_i F in each layer."""
    L, h1, F, e = 1e-3, 4e-4, 3e-4, 1e-9
    u = lambda y: two_layer_poiseuille_velocity(y, h1, L, rho1, rho2, mu1, mu2, F)
    scale = float(np.max(u(np.linspace(0.0, L, 1001))))
    assert abs(u(0.0)) < 1e-14 * scale and abs(u(L)) < 1e-14 * scale
    assert abs(u(h1 - 1e-15) - u(h1 + 1e-15)) < 1e-9 * scale
    stress_below = mu1 * (u(h1) - u(h1 - e)) / e  # one-sided differences: the slope jumps at h1
    stress_above = mu2 * (u(h1 + e) - u(h1)) / e
    assert stress_above == pytest.approx(stress_below, rel=1e-4)
    assert mu2 / mu1 != 1.0 and (u(h1) - u(h1 - e)) / (u(h1 + e) - u(h1)) == pytest.approx(mu2 / mu1, rel=1e-4)
    # the total force balance: the two wall stresses carry the body force of both layers
    d = 1e-8
    wall_stress = mu1 * (u(d) - u(0.0)) / d - mu2 * (u(L) - u(L - d)) / d
    assert wall_stress == pytest.approx(F * (rho1 * h1 + rho2 * (L - h1)), rel=1e-4)
    for y, rho, mu in ((2e-4, rho1, mu1), (7e-4, rho2, mu2)):
        curvature = (u(y + 1e-6) - 2.0 * u(y) + u(y - 1e-6)) / 1e-12
        assert mu * curvature == pytest.approx(-rho * F, rel=1e-5)


def test_two_layer_couette_has_one_stress_and_the_interface_speed():
    L, h1, v0, mu1, mu2 = 1e-3, 5e-4, 2.5e-5, 1e-3, 2e-3
    y = np.array([0.0, 0.25e-3, h1, 0.75e-3, L])
    u = two_layer_couette_velocity(y, h1, L, mu1, mu2, v0)
    assert u[0] == 0.0 and u[-1] == pytest.approx(v0, rel=1e-14)
    assert u[2] == pytest.approx(2.0 / 3.0 * v0, rel=1e-14)  # v0 (h1/mu1) / (h1/mu1 + h2/mu2)
    assert mu1 * (u[2] - u[0]) / h1 == pytest.approx(mu2 * (u[4] - u[2]) / (L - h1), rel=1e-14)


# ------------------------------------------------------------------------------------------ the case format
def _materials(*extra: str) -> list[str]:
    return ["materials=[{name='heavy',model='newtonian',density=1000.0,viscosity=1e-6}," + ",".join(extra) + "]"]


BAD_MATERIALS = [
    (["blocks.0.material='oil'"], "blocks[0].material = 'oil' (lower) is not a [[materials]] name"),
    (_materials("{name='heavy',model='newtonian',density=500.0,viscosity=1e-6}") +
     ["blocks.1.material='heavy'", "blocks.3.material='heavy'"], "materials[1].name = 'heavy' is used twice"),
    (_materials("{name='light',model='bingham',density=500.0,viscosity=1e-6}"),
     "unknown material model 'bingham'; allowed: newtonian, ptt"),
    (_materials("{name='light',model='newtonian',viscosity=1e-6}"), "materials[1].density: required key is missing"),
    (_materials("{name='light',model='newtonian',density=500.0}"), "materials[1].viscosity (light) is missing"),
    (["fluid.density=1000.0"], "fluid.density is given with [[materials]]"),
    (["blocks.2.material=''"], "blocks[2].material"),
]


@pytest.mark.parametrize("overrides,words", BAD_MATERIALS, ids=[w.split(" ")[0] for _, w in BAD_MATERIALS])
def test_bad_materials_name_the_key(overrides, words):
    with pytest.raises(CaseError) as error:
        load_case(POISEUILLE, overrides=overrides)
    assert words in str(error.value)


def test_materials_and_block_material_need_each_other(tmp_path):
    with pytest.raises(CaseError, match="blocks\\[0\\].material = 'heavy' names a material but the case has no"):
        load_case(CHANNEL_1, overrides=["blocks.0.material='heavy'"])
    no_density = tmp_path / "no_density.toml"
    no_density.write_text(CHANNEL_1.read_text().replace("density = 1000.0", ""))
    with pytest.raises(CaseError, match="fluid.density is missing"):
        load_case(no_density)
    with pytest.raises(CaseError, match="blocks\\[3\\].material \\(upper_plate\\) is missing"):
        load_case(POISEUILLE, overrides=["blocks=" + _blocks_without_last_material()])


def _blocks_without_last_material() -> str:
    rows = ["{name='lower',kind='fluid',material='heavy',lo=[0.0,0.0],hi=[0.00025,0.0005]}",
            "{name='upper',kind='fluid',material='light',lo=[0.0,0.0005],hi=[0.00025,0.001]}",
            "{name='lower_plate',kind='boundary',material='heavy',lo=[0.0,-0.000075],hi=[0.00025,0.0]}",
            "{name='upper_plate',kind='boundary',lo=[0.0,0.001],hi=[0.00025,0.001075]}"]
    return "[" + ",".join(rows) + "]"


def test_deck_and_particle_file_of_two_materials(tmp_path):
    case = load_case(POISEUILLE).model
    scene = build_scene(case)
    bind("sph_flow", "sph", executable="/nonexistent/sph").write_input(scene, tmp_path)
    deck = json.loads((tmp_path / "deck.json").read_text())
    assert not {"rho0", "c0", "gamma", "background_pressure", "viscosity"} & set(deck)
    assert deck["materials"] == [
        {"name": "heavy", "model": "newtonian", "rho0": 1000.0, "c0": pytest.approx(3e-3, rel=1e-15), "gamma": 7.0,
         "background_pressure": 0.0, "viscosity": 1e-6},
        {"name": "light", "model": "newtonian", "rho0": 500.0, "c0": pytest.approx(3e-3, rel=1e-15), "gamma": 7.0,
         "background_pressure": 0.0, "viscosity": 4e-6}]
    with h5py.File(tmp_path / "particles.h5", "r") as h5:
        material, masses, y = h5["material"][()], h5["masses"][()], h5["positions"][()][:, 1]
        assert h5["material"].dtype == np.int32
    # blocks in order: lower (heavy), upper (light), lower plate (heavy), upper plate (light)
    np.testing.assert_array_equal(material, np.where(y > 5e-4, 1, 0))
    np.testing.assert_allclose(masses, np.where(y > 5e-4, 500.0, 1000.0) * 2.5e-5**2, rtol=1e-15)
    np.testing.assert_array_equal(scene.densities, np.where(y > 5e-4, 500.0, 1000.0))
    # the adaptive step: the largest nu (4e-6 m^2/s) sets the viscous bound 0.125 h^2 / nu
    assert scene.timestep == pytest.approx(0.125 * (1.5 * 2.5e-5) ** 2 / 4e-6, rel=1e-12)


def test_a_case_without_materials_writes_no_material(tmp_path):
    scene = build_scene(load_case(CHANNEL_1).model)
    bind("sph_flow", "sph", executable="/nonexistent/sph").write_input(scene, tmp_path)
    with h5py.File(tmp_path / "particles.h5", "r") as h5:
        assert "material" not in h5
    assert "materials" not in json.loads((tmp_path / "deck.json").read_text())
    assert np.all(scene.material == 0) and [m.name for m in scene.materials] == ["fluid"]


def test_frame_material_follows_the_input_rows():
    material = np.array([0, 1, 1, 0], dtype=np.int32)
    np.testing.assert_array_equal(_frame_material(material, np.array([3, 1, 0, 2, 7])), [0, 1, 0, 1, 0])


# ------------------------------------------------------------------------------------------ the checks
def _run(case, profile, perturb=0.0, scale=1.0):
    y = (np.arange(40) + 0.5) * 2.5e-5
    u = profile(y) + perturb * scale * np.sin(np.pi * y / 1e-3)
    arrays = {"kind": np.zeros(len(y), np.int8), "positions": np.column_stack([np.zeros_like(y), y]),
              "velocities": np.column_stack([u, np.zeros_like(y)])}
    return {"attrs": {"status": "ok"}, "series": {}, "frames": {"attrs": {}, "0": {"attrs": {"time": 1.5}, **arrays}}}


def test_two_layer_checks_pass_the_profile_and_fail_a_3_percent_error():
    case = load_case(POISEUILLE).model
    exact = lambda y: two_layer_poiseuille_velocity(y, 5e-4, 1e-3, 1000.0, 500.0, 1e-3, 2e-3, 4e-4)
    peak = float(np.max(exact(np.linspace(0.0, 1e-3, 2001))))
    assert peak == pytest.approx(2.8125e-5, rel=1e-9)
    rows, plot = check_two_layer_poiseuille(case, _run(case, exact))
    assert len(rows) == 1 and rows[0]["passed"] and rows[0]["rel_error"] < 1e-12 and plot["lines"]
    rows, _ = check_two_layer_poiseuille(case, _run(case, exact, 0.03, peak))
    assert not rows[0]["passed"] and rows[0]["rel_error"] == pytest.approx(0.03, rel=2e-3)

    case = load_case(COUETTE).model
    exact = lambda y: two_layer_couette_velocity(y, 5e-4, 1e-3, 1e-3, 2e-3, 2.5e-5)
    rows, _ = check_two_layer_couette(case, _run(case, exact))
    assert rows[0]["passed"] and rows[0]["rel_error"] < 1e-12
    assert rows[0]["expected"] == pytest.approx(2.0 / 3.0 * 2.5e-5, rel=0.05)  # the rows beside the interface
    rows, _ = check_two_layer_couette(case, _run(case, exact, 0.03, 2.5e-5))
    assert not rows[0]["passed"] and rows[0]["rel_error"] == pytest.approx(0.03, rel=2e-3)


@pytest.mark.sph
def test_two_layer_run_records_each_particles_material(capsys, tmp_path):
    """A short two-layer Couette through `orchestrator run`: run.h5 frames carry material (layers stay apart),
    and after 0.05 s the momentum of the plate has entered the light upper layer, not yet the heavy lower one."""
    out = tmp_path / "run"
    code = main(["run", str(COUETTE), "--set", "simulation.duration=0.05", "--set", "output.frame_interval=0.025",
                 "--out", str(out), "--no-progress", "--json"])
    assert code == 0 and json.loads(capsys.readouterr().out)["status"] == "ok"
    run = read_run(out)
    frames = [run["frames"][k] for k in sorted((k for k in run["frames"] if k != "attrs"), key=int)]
    assert len(frames) == 3
    for frame in frames:
        y, material = frame["positions"][:, 1], frame["material"]
        assert material.dtype == np.int32
        np.testing.assert_array_equal(material[y < 4.5e-4], 0)
        np.testing.assert_array_equal(material[y > 5.5e-4], 1)
    last = frames[-1]
    fluid = last["kind"] == 0
    u, material = last["velocities"][fluid, 0], last["material"][fluid]
    assert u[material == 1].mean() > 3.0 * u[material == 0].mean() > 0.0


def test_one_fluid_checks_refuse_two_materials():
    case = load_case(POISEUILLE, overrides=['expected=[{check="poiseuille_series", quantity="u_profile", '
                                            'tolerance=0.02}]']).model
    with pytest.raises(OrchestratorError, match="check 'poiseuille_series' compares one fluid but the case has 2"):
        check_poiseuille(case, {"frames": {}})


def test_reference_pair_viscosity_is_the_harmonic_mean_across_materials():
    model = ref.SphModel(dimension=2, rho0=1000.0, c0=1.0, h=0.01, materials=(
        ref.SphMaterial(1000.0, 1.0, viscosity=1e-6), ref.SphMaterial(500.0, 2.0, viscosity=4e-6),
        ref.SphMaterial(800.0, 1.0)))
    mu = ref.pair_viscosity(model)
    np.testing.assert_allclose(np.diag(mu), [1e-3, 2e-3, 0.0], rtol=1e-15)
    assert mu[0, 1] == mu[1, 0] == pytest.approx(2 * 1e-3 * 2e-3 / 3e-3, rel=1e-15)  # 1.333e-3 Pa s
    assert mu[0, 2] == 0.0 and model.viscous


def test_an_inlet_names_a_known_material():
    from types import SimpleNamespace

    from orchestrator.kinds.sph_flow.case_materials import check_materials

    fluid = SimpleNamespace(density=1000.0, max_speed=1.0, min_pressure=None, given=lambda keys: [])
    physics = SimpleNamespace(terms=())
    inlet = SimpleNamespace(material="oil")
    bare = SimpleNamespace(fluid=fluid, physics=physics, materials=(), blocks=(), inlets=(inlet,))
    with pytest.raises(ValueError, match=r"inlets\[0\].material = 'oil' names a material but the case has no"):
        check_materials(bare)
    water = SimpleNamespace(name="water", viscosity=None, sound_speed=None)
    block = SimpleNamespace(material="water", name="fluid")
    named = SimpleNamespace(fluid=fluid, physics=physics, materials=(water,), blocks=(block,), inlets=(inlet,))
    with pytest.raises(ValueError, match=r"inlets\[0\].material = 'oil' is not a \[\[materials\]\] name; allowed: water"):
        check_materials(named)
