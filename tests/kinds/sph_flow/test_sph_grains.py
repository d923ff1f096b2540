"""Rigid grains in an SPH case ([[grains]]): the scene carves the sphere out of the fluid lattice, the deck carries the
grains and the balanced mean weight (the external forces sum to zero), bad input is refused with one line naming
the key, and the executable runs a small settling box and writes each grain's series into run.h5."""

from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path

import numpy as np
import pytest
from paths import REPO

from orchestrator.case import load_case
from orchestrator.errors import CaseError
from orchestrator.kinds import bind, build_scene
from orchestrator.kinds.sph_flow.sph import deck_context
from orchestrator.run import checked_scene

SETTLING = REPO / "cases/verification/sph_settling_sphere_box4a.toml"


def _scene(overrides=()):
    """The small settling box at dx = 1 mm: 16^3 sites, the 280 within 4 mm of the centre the grain's."""
    return build_scene(load_case(SETTLING, overrides=["numerics.dx=0.001", *overrides]).model)


def test_the_sphere_is_carved_out_of_the_fluid_lattice():
    scene = _scene()
    body = scene.kind == 4
    assert body.sum() == 280 and (scene.grain[body] == 0).all() and (scene.grain[~body] == -1).all()
    centre = np.array([0.008, 0.008, 0.008])
    assert np.linalg.norm(scene.positions[body] - centre, axis=1).max() < 0.004
    assert np.linalg.norm(scene.positions[~body] - centre, axis=1).min() >= 0.004
    assert len(scene.positions) == 16**3 and np.allclose(scene.masses, 1000.0 * 1e-9, rtol=1e-12)


def test_the_balanced_weight_sums_to_zero():
    scene = _scene()
    context = deck_context(scene)
    grain = json.loads(context["grains"][0])
    fluid_force = np.array(json.loads(context["body_force"]))
    fluid_mass = scene.masses[scene.kind == 0].sum()
    grain_mass = 2000.0 * (scene.kind == 4).sum() * 1e-9  # rho_g N dx^3, as the engine counts it
    total = fluid_mass * fluid_force + grain_mass * np.array(grain["body_force"])
    assert np.abs(total).max() < 1e-14 * fluid_mass * 9.81
    c = 280 / 16**3
    rho_m = c * 2000.0 + (1 - c) * 1000.0
    assert fluid_force[2] == pytest.approx(-9.81 * (1 - rho_m / 1000.0), rel=1e-12)
    assert grain == {"name": "ball", "density": 2000.0, "velocity": [0.0, 0.0, 0.0],
                     "angular_velocity": [0.0, 0.0, 0.0], "body_force": pytest.approx([0.0, 0.0, -9.81 * (1 - rho_m / 2000.0)])}


def test_without_the_balance_the_grain_takes_the_body_force():
    scene = _scene(["physics.balance_mean_weight=false"])
    context = deck_context(scene)
    assert json.loads(context["body_force"]) == [0.0, 0.0, -9.81]
    assert json.loads(context["grains"][0])["body_force"] == [0.0, 0.0, -9.81]


def test_a_case_without_grains_renders_no_grain_key():
    context = deck_context(_scene(["grains=[]", "physics.balance_mean_weight=false"]))
    assert context["grains"] == []


BAD = [
    (["grains.0.density=0.0"], "grains[0].density = 0.0: Input should be greater than 0"),
    (["grains.0.density=-1000.0"], "grains[0].density = -1000.0: Input should be greater than 0"),
    (["grains.0.centre=[0.002, 0.008, 0.008]"], "grains[0].centre = [0.002, 0.008, 0.008]: the grain (radius 0.004 m) "
                                                "reaches outside the domain box"),
    (["grains.0.radius=0.009"], "grains[0].radius = 0.009 m: the grain (0.018 m across) is larger than the domain box"),
    (["grains.0.shape='cube'"], "grains[0].shape = 'cube'"),
    (["grains.0.velocity=[0.0, 0.0, 1.0]"], "grains[0]: its surface moves at up to 1 m/s"),
    (["grains=[]"], "physics.balance_mean_weight balances the weight of [[grains]]; the case has none"),
]


def _refusal(overrides) -> str:
    with pytest.raises(CaseError) as error:
        load_case(SETTLING, overrides=list(overrides))
    lines = str(error.value).splitlines()
    assert len(lines) == 2, lines  # "<case>: invalid case" and one line naming the key
    return lines[1]


@pytest.mark.parametrize("overrides,words", BAD, ids=[w.split(" ")[0] + str(i) for i, (_, w) in enumerate(BAD)])
def test_bad_grain_keys_are_named(overrides, words):
    assert words in _refusal(overrides)


def test_two_overlapping_grains_are_refused(tmp_path):
    text = SETTLING.read_text().replace('[numerics]', '[[grains]]\nname = "other"\nradius = 0.002\ndensity = 2000.0\n'
                                        'centre = [0.008, 0.008, 0.0125]\n\n[numerics]')
    path = tmp_path / "case.toml"
    path.write_text(text)
    with pytest.raises(CaseError) as error:
        load_case(path)
    assert "grains[1].centre: grain 'other' overlaps grains[0] ('ball') by 0.0015 m" in str(error.value)


@pytest.mark.sph
def test_the_executable_settles_the_grain_and_run_h5_holds_its_series(tmp_path):
    scene = _scene(["simulation.duration=0.002", "output.frame_interval=0.001", "output.series_interval=0.0005"])
    adapter = bind("sph_flow", "sph")
    if not adapter.profile.executable or not Path(adapter.profile.executable).exists():
        pytest.skip("the sph executable is not built")
    adapter.write_input(scene, tmp_path)
    command, env = adapter.command(scene, tmp_path)
    done = subprocess.run(command, cwd=tmp_path, env={**env, "PATH": "/usr/bin:/bin"}, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    result = adapter.read_output(scene, tmp_path)
    assert result.status == "ok"
    for what, columns in (("position", 3), ("velocity", 3), ("angular_velocity", 3), ("orientation", 4),
                          ("force", 3), ("torque", 3), ("contact", 3)):
        assert result.series[f"grain_ball_{what}"].values.shape == (len(result.time), columns), what
    velocity = result.series["grain_ball_velocity"].values
    assert velocity[-1, 2] < 0.0 and abs(velocity[-1, 0]) < 1e-3 * abs(velocity[-1, 2])  # it sinks straight down
    assert np.abs(result.series["grain_ball_angular_velocity"].values[-1]).max() < 1e-6  # and does not turn
    # The box's momentum stays zero: the fluid moves up as the grain sinks.
    _, frame = result.frames[-1]
    fluid = frame["kind"] == 0
    momentum = 1e-6 * frame["velocities"][fluid].sum(axis=0)[2] + 2000.0 * 280e-9 * velocity[-1, 2]
    assert abs(momentum) < 1e-6 * 2000.0 * 280e-9 * abs(velocity[-1, 2]) + 1e-18
    assert math.isfinite(float(result.series["grain_ball_force"].values[-1, 2]))


SHEAR = REPO / "cases/verification/sph_grain_in_shear.toml"


def test_a_grain_near_the_sheared_faces_is_refused():
    """The grain's pairs must not cross the Lees-Edwards faces: 2h and the skin, 2 x 1.3 x 1.1 mm, inside them."""
    assert load_case(SHEAR, overrides=["grains.0.centre=[0.01, 0.01286, 0.01]"]).model.grains[0].centre[1] == 0.01286
    with pytest.raises(CaseError) as error:
        load_case(SHEAR, overrides=["grains.0.centre=[0.01, 0.0132, 0.01]"])
    assert ("grains[0].centre = [0.01, 0.0132, 0.01]: in a Lees-Edwards cell the grain must stay 0.00286 m (the "
            "support 2h and the neighbour list's skin) inside the sheared faces y = 0 and 0.02 m") in str(error.value)


def test_grain_contact_reaches_the_deck_with_each_sphere_radius():
    context = deck_context(_scene(["grain_contact.stiffness=2.5", "grain_contact.restitution=0.5"]))
    assert json.loads(context["grain_contact"]) == {"stiffness": 2.5, "restitution": 0.5}
    assert json.loads(context["grains"][0])["contact_radius"] == 0.004
    plain = deck_context(_scene())
    assert plain["grain_contact"] is None and "contact_radius" not in json.loads(plain["grains"][0])


@pytest.mark.parametrize("overrides,words", [
    (["grain_contact.stiffness=2.5", "grain_contact.restitution=0.0"], "grain_contact.restitution = 0.0"),
    (["grain_contact.stiffness=2.5", "grain_contact.restitution=1.5"], "grain_contact.restitution = 1.5"),
    (["grain_contact.stiffness=-1.0"], "grain_contact.stiffness = -1.0"),
    (["grain_contact.stiffness=2.5", "grains=[]", "physics.balance_mean_weight=false"], "grain_contact needs [[grains]]"),
])
def test_bad_grain_contact_is_named(overrides, words):
    assert words in _refusal(overrides)


WALL_BOUNCE = REPO / "cases/verification/sph_grain_wall_bounce.toml"


def test_contact_walls_reach_the_deck_with_unit_normals():
    case = load_case(WALL_BOUNCE, overrides=["grain_contact.walls.0.normal=[0.0, 0.0, 2.0]"]).model
    deck = json.loads(deck_context(build_scene(case))["grain_contact"])
    assert deck == {"stiffness": 24.0, "restitution": 0.8, "walls": [{"point": [0.0, 0.0, 0.003],
                                                                      "normal": [0.0, 0.0, 1.0]}]}


@pytest.mark.parametrize("overrides,words", [
    (["grain_contact.walls.0.normal=[0.0, 0.0, 0.0]"], "grain_contact.walls[0].normal = [0.0, 0.0, 0.0]: must not be zero"),
    (["grain_contact.walls.0.normal=[1.0, 0.0, 1.0]"], "has a component along the periodic axis 0"),
    (["grains.0.centre=[0.004, 0.004, 0.004]"], "grain 'ball' (radius 0.0021 m) lies 0.001 m from grain_contact.walls[0]"),
])
def test_bad_contact_walls_and_stiffness_are_named(overrides, words):
    with pytest.raises(CaseError) as error:
        load_case(WALL_BOUNCE, overrides=overrides)
    lines = str(error.value).splitlines()
    assert len(lines) == 2 and words in lines[1], lines


def test_a_contact_shorter_than_twenty_steps_is_refused_with_the_engine_s_grain_mass():
    """The grain's mass as the engine counts it, rho N dx^3 = 1000 x 42 x 1e-9 kg (the sphere's volume would say
    3.88e-5 kg): pi sqrt(m / k) at 1e5 N/m lasts 6.44e-5 s, about one step of 6.5e-5 s."""
    case = load_case(WALL_BOUNCE, overrides=["grain_contact.stiffness=1e5"]).model
    with pytest.raises(CaseError) as error:
        checked_scene(case)
    assert ("grain_contact.stiffness = 100000 N/m makes a contact of pi sqrt(m / k) = 6.44e-05 s (m = 4.2e-05 kg), "
            "0.991 steps") in str(error.value)
    assert (build_scene(load_case(WALL_BOUNCE).model).kind == 4).sum() == 42
