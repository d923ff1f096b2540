"""Johnson-Cook solids in an SPH case: the [materials.solid] table reaches the deck, bad values are refused with
one line naming the key (case model and executable), and the executable runs the rendered deck."""

from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest
from paths import REPO

from orchestrator.case import load_case
from orchestrator.errors import CaseError
from orchestrator.kinds import bind, build_scene
from orchestrator.kinds.sph_flow.sph import deck_context

BLOCK = REPO / "tests/kinds/sph_flow/data/sph_solid_block.toml"
EXECUTABLE = REPO / "engines/sph/build/sph"


def test_solid_material_reaches_the_deck():
    context = deck_context(build_scene(load_case(BLOCK).model))
    material = json.loads(context["materials"][0])
    assert material["model"] == "johnson_cook" and "c0" not in material and "gamma" not in material
    assert material["failure"] == {"d1": -0.77, "d2": 1.45, "d3": -0.47, "d4": 0.0, "d5": 1.6}
    assert material["artificial_stress"] == {"epsilon": 0.3, "exponent": 4}
    assert material["bulk_sound_speed"] == 5240.0 and material["heat_fraction"] == 0.95


BAD = [
    (["materials.0.solid.shear_modulus=-1e9"], "materials[0].solid.shear_modulus = -1000000000.0"),
    (["materials.0.solid.bulk_sound_speed=-5240.0"], "materials[0].solid.bulk_sound_speed"),
    (["materials.0.solid.melting_temperature=250.0"], "materials[0].solid.melting_temperature = 250 K is not above"),
    (["materials.0.solid.yield_stress=6e9"], "materials[0].solid.yield_stress = 6e+09 Pa is above what the equation of "
                                             "state's range carries"),
    (["materials.0.solid.eos='linear'"], "materials[0].solid.bulk_modulus is missing"),
    (["materials.0.sound_speed=6000.0"], "materials[0].sound_speed (al6061) is not a key of a johnson_cook material"),
    (["materials.0.solid.rate_form='cubic'"], "materials[0].solid.rate_form = 'cubic'"),
    (["materials.0.solid.heat_fraction=0.0"], "materials[0].solid.heat_capacity = 896 J/(kg K) is given but "
                                              "heat_fraction is 0"),
    (["physics.terms=['artificial_viscosity', 'morris_viscosity']"], "a solid takes artificial_viscosity only"),
    (["materials.0.gamma=5.0"], "materials[0].gamma (al6061) is a key of the fluids' equation of state"),
]


def _refusal(path, overrides=()) -> str:
    with pytest.raises(CaseError) as error:
        load_case(path, overrides=list(overrides))
    lines = str(error.value).splitlines()
    assert len(lines) == 2, lines  # "<case>: invalid case" and one line naming the key
    return lines[1]


@pytest.mark.parametrize("overrides,words", BAD, ids=[w.split(" ")[0] + str(i) for i, (_, w) in enumerate(BAD)])
def test_bad_solid_keys_are_named(overrides, words):
    assert words in _refusal(BLOCK, overrides)


@pytest.mark.parametrize("removed,words", [
    (("yield_stress", "hardening_modulus", "hardening_exponent", "rate_sensitivity", "thermal_exponent",
      "melting_temperature"), "materials[0].solid.failure is a failure model without plasticity"),
    (("heat_capacity",), "materials[0].solid.heat_capacity is missing"),
], ids=["failure_without_plasticity", "heat_without_capacity"])
def test_missing_solid_keys_are_named(removed, words, tmp_path):
    lines = [line for line in BLOCK.read_text().splitlines() if line.split(" = ")[0] not in removed]
    path = tmp_path / "case.toml"
    path.write_text("\n".join(lines) + "\n")
    assert words in _refusal(path)


def _engine(deck: dict, workdir):
    if not EXECUTABLE.exists():
        pytest.skip(f"{EXECUTABLE} is not built")
    (workdir / "deck.json").write_text(json.dumps(deck))
    (workdir / "none.h5").write_bytes(b"")  # the deck is refused before the particle file is read
    return subprocess.run([str(EXECUTABLE), "deck.json"], cwd=workdir, capture_output=True, text=True, timeout=120)


@pytest.mark.sph
def test_the_executable_runs_the_rendered_deck(tmp_path):
    scene = build_scene(load_case(BLOCK).model)
    adapter = bind("sph_flow", "sph")
    adapter.write_input(scene, tmp_path)
    command, env = adapter.command(scene, tmp_path)
    done = subprocess.run(command, cwd=tmp_path, env={**env, "PATH": "/usr/bin:/bin"}, capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    import h5py

    with h5py.File(tmp_path / "out.h5", "r") as h5:
        last = h5["frames"][str(len(h5["frames"]) - 1)]
        assert last["solid_state"].shape == (60, 6) and last["stress"].shape == (60, 4)
        assert (last["solid_state"][()][:, 3] == 293.0).all()  # a rigid translation: no plastic work
    # the reader hands the solid's fields to run.h5 by name: stress (n, D, D) Pa and the scalars of solid_state
    from orchestrator.kinds.sph_flow.sph import read_sph_output

    with h5py.File(tmp_path / "out.h5", "a") as h5:  # known values in the last frame, to see the columns land by name
        last = h5["frames"][str(len(h5["frames"]) - 1)]
        last["solid_state"][:, :] = np.arange(6.0)[None, :] + np.arange(60.0)[:, None] * 10
        last["stress"][:, :] = np.array([1.0, 2.0, 3.0, 4.0])
    time, frame = read_sph_output(tmp_path, scene).frames[-1]
    row = int(np.flatnonzero(frame["ids"] == 5)[0])
    assert frame["stress"].shape == (60, 2, 2) and frame["stress"][row].tolist() == [[1.0, 2.0], [3.0, 4.0]]
    for k, name in enumerate(("internal_energy", "plastic_strain", "plastic_strain_rate", "temperature", "damage",
                              "stress_zz")):
        assert frame[name][row] == 10 * row + k, name


ENGINE_BAD = [
    ({"shear_modulus": -1.0}, "'materials[0].shear_modulus' must be > 0"),
    ({"melting_temperature": 200.0}, "'materials[0].melting_temperature' = 200.000000 K must be above"),
    ({"yield_stress": None, "melting_temperature": None}, "'materials[0].failure' is given but 'yield_stress' is not"),
    ({"c0": 5000.0}, "unknown key 'materials[0].c0'"),
    ({"eos": "tait"}, "'materials[0].eos' = 'tait' is not allowed; allowed: linear, mie_gruneisen"),
    ({"hugoniot_slope": 1.4}, "'materials[0].hugoniot_slope' is not a key of eos 'linear'"),
    ({"failure": {"d1": 0.1, "d2": 0.1}}, "missing key 'materials[0].failure.d3'"),
    ({"artificial_stress": {"exponent": 2.5}}, "'materials[0].artificial_stress.exponent' must be a whole number"),
]


@pytest.mark.sph
@pytest.mark.parametrize("change,words", ENGINE_BAD, ids=[w.split("'")[1] for _, w in ENGINE_BAD])
def test_the_executable_names_a_bad_solid_key(change, words, tmp_path):
    material = {"name": "al", "model": "johnson_cook", "rho0": 2700.0, "shear_modulus": 26e9, "bulk_modulus": 70e9,
                "yield_stress": 3e8, "melting_temperature": 925.0, "failure": {"d1": 0.1, "d2": 0.1, "d3": -0.5}}
    material.update(change)
    material = {key: value for key, value in material.items() if value is not None}
    deck = {"dimension": 2, "particles_file": "none.h5", "physics": [], "v_max": 10.0, "h": 1.3e-3, "dx": 1e-3,
            "materials": [material], "dt": 1e-8, "t_end": 1e-7, "output": {"frame_interval": 1e-7}}
    done = _engine(deck, tmp_path)
    assert done.returncode == 2
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and words in lines[0], done.stderr


UNDER_WATER = REPO / "cases/verification/sph_solid_under_water.toml"


def test_a_newtonian_fluid_beside_a_solid_reaches_the_deck_with_its_pair_terms():
    context = deck_context(build_scene(load_case(UNDER_WATER).model))
    models = [json.loads(m)["model"] for m in context["materials"]]
    assert models == ["newtonian", "johnson_cook"]


@pytest.mark.parametrize("overrides,words", [
    (["physics.viscosity_correction=true"], "physics.viscosity_correction is set with the fluid 'water' beside"),
])
def test_a_fluid_beside_a_solid_outside_the_compiled_configurations_is_named(overrides, words):
    assert words in _refusal(UNDER_WATER, overrides)


def test_an_inviscid_fluid_beside_a_solid_is_named(tmp_path):
    text = UNDER_WATER.read_text().replace('"morris_viscosity", ', "")
    text = "\n".join(line for line in text.splitlines() if not line.startswith("viscosity = "))
    (tmp_path / "case.toml").write_text(text)
    assert "has no 'morris_viscosity', which the fluid 'water' beside the johnson_cook material materials[1]" in \
        _refusal(tmp_path / "case.toml")


def test_a_grain_reaching_into_a_solid_block_is_named(tmp_path):
    text = (REPO / "tests/kinds/sph_flow/data/sph_grain_in_oil.toml").read_text()
    solid = (REPO / "tests/kinds/sph_flow/data/solid_layer_material.toml").read_text() + "[physics]"
    layer = """[[blocks]]
name = "layer"
kind = "fluid"
material = "layer"
lo = [0.0, 0.0, 0.003]
hi = [0.012, 0.012, 0.007]

[[blocks]]
name = "oil"
"""
    text = text.replace("[physics]", solid, 1).replace('[[blocks]]\nname = "oil"\n', layer, 1)
    text = text.replace("lo = [0.0, 0.0, 0.003]\nhi = [0.012, 0.012, 0.014]", "lo = [0.0, 0.0, 0.007]\nhi = [0.012, 0.012, 0.014]")
    (tmp_path / "case.toml").write_text(text)
    assert ("grains[0].centre = [0.006, 0.006, 0.009]: grain 'grain' (radius 0.0025 m) reaches 0.0005 m into blocks[0] "
            "('layer') of the johnson_cook material materials[1] (layer); a grain starts in the fluid") in \
        _refusal(tmp_path / "case.toml")
