"""The impact case kind without any engine: validation (clear messages), the
scene (time step), the closed forms it names, and the measures of a run."""

from __future__ import annotations

import math
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest
import tomli_w

from orchestrator.kinds.impact.analysis import evaluate_checks, measure_impact
from orchestrator.kinds.impact.theory import QUANTITIES
from orchestrator.kinds.impact.theory import CLOSED_FORMS, expected_value
from orchestrator.engines.base import Result, Series
from orchestrator.case import load_case
from orchestrator.errors import CaseError
from orchestrator.kinds import build_scene
from orchestrator.kinds.impact.physics import critical_timestep
from orchestrator.workflows.verify import get_suite, scene_files
from paths import VERIFICATION

TEST2 = VERIFICATION / "chung_ooi_test2_sphere_plane.toml"
DROP = VERIFICATION / "uhlmann2015_sphere_drop.toml"
BASE = tomllib.loads(TEST2.read_text())


def write_variant(tmp_path, changes: dict, base: dict = BASE) -> Path:
    """The test-2 case with top-level tables replaced (a value None drops the table)."""
    data = {**base, **changes}
    data = {k: v for k, v in data.items() if v is not None}
    path = tmp_path / "case.toml"
    path.write_text(tomli_w.dumps(data))
    return path


@pytest.mark.parametrize("path", scene_files(get_suite("dem"), VERIFICATION), ids=lambda p: p.stem)
def test_every_verification_scene_loads_and_its_closed_forms_evaluate(path):
    loaded = load_case(path)
    assert loaded.kind == "impact" and loaded.model.expected
    for check in loaded.model.expected:
        value = expected_value(loaded.model, check)
        assert math.isfinite(value) and value != 0.0
    scene = build_scene(loaded.model)
    assert 0 < scene.timestep < scene.critical_timestep


def test_hertz_closed_forms_match_the_textbook_for_chung_ooi_test_2():
    # Johnson, Contact Mechanics (1985), section 11.4: delta* = (15 m V^2 / (16 E* R^(1/2)))^(2/5),
    # P* = 4/3 E* R^(1/2) delta*^(3/2), contact time 2.94 delta* / V (sphere on a rigid flat: R* = R, m* = m)
    model = load_case(TEST2).model
    mass = 2699.0 * 4.0 / 3.0 * math.pi * 0.1**3
    e_star = 70e9 / (1 - 0.3**2)
    overlap = (15 * mass * 0.2**2 / (16 * e_star * math.sqrt(0.1))) ** 0.4
    values = {c.quantity: expected_value(model, c) for c in model.expected}
    assert values["max_overlap"] == pytest.approx(overlap, rel=1e-12)
    assert values["max_normal_force"] == pytest.approx(4 / 3 * e_star * math.sqrt(0.1) * overlap**1.5, rel=1e-12)
    assert values["contact_duration"] == pytest.approx(2.9433 * overlap / 0.2, rel=1e-4)
    assert values["max_normal_force"] == pytest.approx(11369.86, rel=1e-6)


def test_sphere_drop_closed_forms():
    model = load_case(DROP).model
    checks = {c.quantity: expected_value(model, c) for c in model.expected}
    v1 = math.sqrt(2 * 9.81 * 0.010)  # 0.4429 m/s at the first impact
    # flight between impacts: 2 e v / g (plus a contact of ~25 us)
    assert checks["time_between_impacts_1"] == pytest.approx(2 * 0.68 * v1 / 9.81, rel=1e-3)
    assert checks["time_between_impacts_2"] == pytest.approx(2 * 0.68**2 * v1 / 9.81, rel=1e-3)
    # damped peaks fall as v^(6/5) with the speed: e_n^(6/5) per bounce
    assert checks["peak_force_2"] / checks["peak_force_1"] == pytest.approx(0.68**1.2, rel=1e-9)
    assert checks["peak_force_3"] / checks["peak_force_2"] == pytest.approx(0.68**1.2, rel=1e-9)
    assert checks["restitution"] == 0.68


def test_eq10_damping_changes_the_alpha_dependent_closed_forms(tmp_path):
    eq10 = load_case(DROP, overrides=['model.damping="eq10"']).model
    rows = {c.closed_form: expected_value(eq10, c) for c in eq10.expected}
    exact = {c.closed_form: expected_value(load_case(DROP).model, c) for c in eq10.expected}
    assert rows["input_restitution"] == 0.68
    # with no tension, eq. 10's alpha rebounds at 0.7007 instead of 0.68: flights are 3 % longer
    assert rows["ballistic_time_between_impacts_1"] / exact["ballistic_time_between_impacts_1"] == pytest.approx(
        0.700702 / 0.68, rel=1e-4)


def test_critical_step_is_rayleigh_or_the_contact_limit_whichever_is_smaller(tmp_path):
    model = load_case(TEST2).model
    g = 70e9 / 2.6
    rayleigh = math.pi * 0.1 * math.sqrt(2699 / g) / (0.1631 * 0.3 + 0.8766)
    assert critical_timestep(model) == pytest.approx(rayleigh, rel=1e-12)  # 1.07e-4 s vs 3.6e-4 s for the contact
    # the same sphere at 200 m/s: the Hertz contact limit 1.461 delta_max / v binds
    fast = load_case(TEST2, overrides=["spheres=[{material='aluminium_alloy', radius=0.1, position=[0, 0, 0.1], "
                                       "velocity=[0, 0, -200.0]}]"]).model
    mass = 2699.0 * 4.0 / 3.0 * math.pi * 0.1**3
    overlap = (15 * mass * 200.0**2 / (16 * 70e9 / 0.91 * math.sqrt(0.1))) ** 0.4
    assert critical_timestep(fast) == pytest.approx(2 / math.sqrt(15 / 8) * overlap / 200.0, rel=1e-9)
    assert critical_timestep(fast) < rayleigh


def test_default_step_is_a_twentieth_of_the_critical_one_and_can_be_set():
    scene = build_scene(load_case(TEST2).model)
    assert scene.timestep == pytest.approx(0.05 * scene.critical_timestep)
    fixed = build_scene(load_case(TEST2, overrides=["numerics.timestep=1e-6"]).model)
    assert fixed.timestep == 1e-6


BAD_CASES = {
    "unknown quantity": ({"expected": [{"quantity": "max_force", "value": 1.0, "tolerance": 0.01}]},
                         ["expected[0]", "max_force", "max_normal_force"]),
    "unknown closed form": ({"expected": [{"quantity": "max_overlap", "closed_form": "hertz", "tolerance": 0.01}]},
                            ["expected[0]", "'hertz'", "hertz_max_overlap"]),
    "closed form of another quantity": (
        {"expected": [{"quantity": "max_overlap", "closed_form": "hertz_max_force", "tolerance": 0.01}]},
        ["gives max_normal_force, not max_overlap"]),
    "both value and closed form": (
        {"expected": [{"quantity": "max_overlap", "closed_form": "hertz_max_overlap", "value": 1.0,
                       "tolerance": 0.01}]}, ["exactly one of value"]),
    "tolerance of 100 %": ({"expected": [{"quantity": "max_overlap", "value": 1.0, "tolerance": 1.0}]},
                           ["expected[0].tolerance", "less than 1"]),
    "sphere in the plane": (
        {"spheres": [{"material": "aluminium_alloy", "radius": 0.1, "position": [0, 0, 0.05]}]},
        ["spheres[0] starts overlapping the plane", "at least one radius"]),
    "sphere behind the plane": (
        {"spheres": [{"material": "aluminium_alloy", "radius": 0.1, "position": [0, 0, -0.5]}]},
        ["spheres[0] starts behind the plane"]),
    "overlapping spheres": (
        {"plane": None, "contacts": [{"pair": ["aluminium_alloy", "aluminium_alloy"], "restitution": 1.0,
                                      "friction": 0.0}],
         "spheres": [{"material": "aluminium_alloy", "radius": 0.1, "position": [0, 0, 0]},
                     {"material": "aluminium_alloy", "radius": 0.1, "position": [0.15, 0, 0]}], "expected": []},
        ["spheres[0] and spheres[1] overlap by 0.05 m"]),
    "missing contact pair": ({"contacts": [{"pair": ["aluminium_alloy", "aluminium_alloy"], "restitution": 1.0,
                                            "friction": 0.0}]},
                             ["no entry for the pair (aluminium_alloy, rigid)", "[[contacts]]"]),
    "rigid as a material name": ({"materials": {"rigid": {"density": 1.0, "young_modulus": 1e9,
                                                          "poisson_ratio": 0.3}}},
                                 ["materials.rigid is reserved"]),
    "zero normal": ({"plane": {"normal": [0, 0, 0]}}, ["plane.normal", "zero vector"]),
    "negative radius": ({"spheres": [{"material": "aluminium_alloy", "radius": -0.1, "position": [0, 0, 1]}]},
                        ["spheres[0].radius = -0.1", "greater than 0"]),
    "unknown material of a sphere": ({"spheres": [{"material": "steel", "radius": 0.1, "position": [0, 0, 1]}]},
                                     ["spheres[0].material = 'steel' is not defined", "aluminium_alloy"]),
    "unknown key": ({"simulation": {"duration": 1e-3, "gravity": False, "dt": 1e-6}},
                    ["simulation.dt: unknown key", "duration, gravity"]),
    "engine damping with an alpha closed form": (
        {"model": {"damping": "engine"},
         "expected": [{"quantity": "restitution", "closed_form": "damped_hertz_restitution", "tolerance": 0.01}]},
        ["model.damping = 'engine'", "damped_hertz_restitution"]),
    "separate e_t under the paper's law": (
        {"contacts": [{"pair": ["aluminium_alloy", "rigid"], "restitution": 0.9, "tangential_restitution": 0.5,
                       "friction": 0.0}]}, ["c_t = c_n", "tangential_restitution = 0.5"]),
    "record interval longer than the run": ({"output": {"record_interval": 1.0}},
                                            ["output.record_interval = 1.0 s", "simulation.duration"]),
    "a value that is not a number": ({"simulation": {"duration": "long"}}, ["simulation.duration = 'long'"]),
}


@pytest.mark.parametrize("name", list(BAD_CASES))
def test_bad_impact_cases_name_key_and_what_is_allowed(tmp_path, name):
    changes, words = BAD_CASES[name]
    with pytest.raises(CaseError) as info:
        load_case(write_variant(tmp_path, changes))
    for word in words:
        assert word in str(info.value), str(info.value)


def test_bad_impact_case_on_the_command_line_gives_one_error_and_no_traceback(tmp_path):
    path = write_variant(tmp_path, BAD_CASES["sphere in the plane"][0])
    proc = subprocess.run([sys.executable, "-m", "orchestrator", "run", str(path), "--engine", "reference", "--out",
                           str(tmp_path / "r")], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2 and proc.stderr.startswith("error:") and "Traceback" not in proc.stderr
    assert "overlapping the plane" in proc.stderr and not (tmp_path / "r").exists()


def synthetic_result(case) -> Result:
    """Three wall contacts of sphere 0 and a state record after each."""
    result = Result()
    starts = np.array([0.010, 0.050, 0.080])
    ends = starts + 0.002
    result.events = {
        "sphere": Series(np.zeros(3, np.int64), "-"), "other_kind": Series(np.ones(3, np.int64), "-"),
        "other": Series(np.zeros(3, np.int64), "-"), "start_time": Series(starts, "s"), "end_time": Series(ends, "s"),
        "impact_speed": Series(np.array([2.0, 1.0, 0.5]), "m/s"),
        "rebound_speed": Series(np.array([1.0, 0.5, 0.25]), "m/s"),
        "peak_normal_force": Series(np.array([30.0, 20.0, 10.0]), "N"),
        "peak_time": Series(starts + 0.001, "s"), "max_overlap": Series(np.array([3e-6, 2e-6, 1e-6]), "m"),
    }
    result.time = np.linspace(0.0, 0.1, 101)
    velocities = np.zeros((101, 1, 3))
    velocities[:, 0, 0] = np.where(result.time < 0.0115, 1.5, 0.7)
    spins = np.zeros((101, 1, 3))
    spins[:, 0, 1] = np.where(result.time < 0.0115, 0.0, 40.0)
    result.series = {"velocities": Series(velocities, "m/s"), "angular_velocities": Series(spins, "rad/s")}
    return result


def test_measures_from_events_and_series():
    case = load_case(TEST2, overrides=["spheres=[{material='aluminium_alloy', radius=0.1, position=[0, 0, 0.1], "
                                       "velocity=[1.5, 0, -0.2]}]"]).model
    measured = measure_impact(case, synthetic_result(case))
    assert measured["n_contacts"] == 3
    assert measured["max_normal_force"] == 30.0 and measured["max_overlap"] == 3e-6
    assert measured["contact_duration"] == pytest.approx(0.002)
    assert measured["restitution"] == pytest.approx(0.5)
    assert [measured[f"peak_force_{k}"] for k in (1, 2, 3)] == [30.0, 20.0, 10.0]
    assert measured["time_between_impacts_1"] == pytest.approx(0.040)
    assert measured["time_between_impacts_2"] == pytest.approx(0.030)
    # the first record after the first contact (t = 0.012 s), along +x and about n x t = z x x = +y
    assert measured["rebound_tangential_velocity"] == pytest.approx(0.7)
    assert measured["rebound_spin"] == pytest.approx(40.0)
    assert set(measured) <= set(QUANTITIES)


def test_checks_report_errors_and_what_was_not_measured():
    case = load_case(TEST2).model
    expected = {c.quantity: expected_value(case, c) for c in case.expected}
    measured = {"max_normal_force": expected["max_normal_force"] * 1.005,
                "max_overlap": expected["max_overlap"] * 1.02}
    rows = {row.quantity: row for row in evaluate_checks(case, measured)}
    assert rows["max_normal_force"].passed and rows["max_normal_force"].rel_error == pytest.approx(0.005)
    assert not rows["max_overlap"].passed and rows["max_overlap"].rel_error == pytest.approx(0.02)
    assert not rows["contact_duration"].passed and "not measured" in rows["contact_duration"].note
    assert rows["max_normal_force"].source == "hertz_max_force"


def test_closed_forms_refuse_scenes_they_do_not_describe(tmp_path):
    three = write_variant(tmp_path, {"plane": None, "contacts": [
        {"pair": ["aluminium_alloy", "aluminium_alloy"], "restitution": 1.0, "friction": 0.0}],
        "spheres": [{"material": "aluminium_alloy", "radius": 0.1, "position": [0.3 * k, 0, 0]} for k in range(3)]})
    rows = evaluate_checks(load_case(three).model, {})
    assert all(not row.passed and "closed form not applicable" in row.note for row in rows)
    assert "one sphere with a plane, or two spheres" in rows[0].note


def test_every_closed_form_names_a_measured_quantity():
    assert {form.quantity for form in CLOSED_FORMS.values()} <= set(QUANTITIES)
