"""Mass scaling of a solid target (material.mass_scaling = f): the run's density f rho0 at the same bulk modulus,
wave speed c_L / sqrt(f) (so a step sqrt(f) longer), the same heating per volume; refused where the impact's Mach
number would pass 0.1."""

from __future__ import annotations

import json
import math

import pytest

from orchestrator.case import load_case
from orchestrator.errors import CaseError
from orchestrator.kinds import build_scene
from orchestrator.kinds.sph_flow.sph import deck_context
from paths import VERIFICATION

CRATER = VERIFICATION / "crater_hutchings_100cr6.toml"
TAYLOR = VERIFICATION / "taylor_bar_42crmo4.toml"


def materials(path, *overrides):
    scene = build_scene(load_case(path, preset="quick", overrides=list(overrides)).model)
    return scene, json.loads(deck_context(scene)["materials"][0])


def test_the_scaled_target_keeps_its_stiffness_and_heating_and_gains_inertia():
    plain_scene, plain = materials(CRATER)
    scene, scaled = materials(CRATER, "material.mass_scaling=16")
    assert scaled["rho0"] == pytest.approx(16 * 7810.0, rel=1e-14)
    assert scaled["bulk_sound_speed"] == pytest.approx(4578.0 / 4.0, rel=1e-14)
    # rho0 C0^2 (the Hugoniot's and the Grueneisen term's scale) and rho0 C_p (heat per volume) unchanged
    assert scaled["rho0"] * scaled["bulk_sound_speed"] ** 2 == pytest.approx(7810.0 * 4578.0**2, rel=1e-12)
    assert scaled["rho0"] * scaled["heat_capacity"] == pytest.approx(7810.0 * 475.0, rel=1e-12)
    assert scaled["shear_modulus"] == plain["shear_modulus"] and scaled["yield_stress"] == plain["yield_stress"]
    moving = scene.kind == 0
    assert scene.masses[moving] == pytest.approx(16 * plain_scene.masses[moving], rel=1e-12)
    # the sphere and its contact spring (the target's K + 4G/3 times dx) do not change
    assert json.loads(deck_context(scene)["impactors"][0]) == json.loads(deck_context(plain_scene)["impactors"][0])


def test_a_linear_solid_keeps_its_bulk_modulus_and_the_wall_its_impedance():
    _, plain = materials(TAYLOR)
    scene, scaled = materials(TAYLOR, "material.mass_scaling=4")
    assert scaled["rho0"] == pytest.approx(4 * 7830.0) and scaled["bulk_modulus"] == plain["bulk_modulus"]
    assert scaled["heat_capacity"] == pytest.approx(460.0 / 4)


@pytest.mark.parametrize("path, override, words", [
    (CRATER, "material.mass_scaling=64", "material.mass_scaling = 64 leaves a wave speed of 736.8 m/s, below 10 x "
                                         "sphere.speed = 100 m/s"),
    (TAYLOR, "material.mass_scaling=9", "below 10 x bar.speed = 287 m/s"),
    (CRATER, "material.mass_scaling=0.5", "mass_scaling"),
])
def test_a_scaling_past_mach_one_tenth_is_refused(path, override, words):
    with pytest.raises(CaseError, match=words.replace(".", r"\.")):
        load_case(path, overrides=[override])


def test_the_largest_allowed_scaling_is_named():
    c_l = math.sqrt((7810.0 * 4578.0**2 + 4.0 / 3.0 * 80.769e9) / 7810.0)
    assert f"{(c_l / 1000.0) ** 2:.3g}" == "34.7"
    with pytest.raises(CaseError, match="use a mass_scaling of at most 34.7"):
        load_case(CRATER, overrides=["material.mass_scaling=64"])
    with pytest.raises(CaseError, match=r"below 10 x the fastest of sweep\.speeds = 100 m/s"):
        load_case(CRATER, overrides=["material.mass_scaling=64", "sphere.speed=40"])
