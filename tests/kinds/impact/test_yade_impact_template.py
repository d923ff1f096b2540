"""The Yade impact script without Yade: golden file of the rendered script,
the mapping of the paper's law onto Yade's parameters, and the parser on a
stored Yade output.

Numbers in the golden file are compared within a relative 1e-9 (tests/golden.py).
Regenerate the golden file after an intended template change with:
UPDATE_GOLDEN=1 pytest tests/kinds/impact/test_yade_impact_template.py
"""

import math
import shutil

import numpy as np
import pytest

from orchestrator.kinds import bind
from orchestrator.kinds.impact.yade import impact_context

from orchestrator.dem.yade_law import mindlin_shear_coefficient, thornton_betan, yade_damping_parameters
from orchestrator.kinds.impact.yade import read_impact_output
from orchestrator.case import load_case
from orchestrator.reference import closed_form, contact
from orchestrator.kinds import build_scene

from golden import assert_matches_golden
from paths import VERIFICATION, DATA, GOLDEN

DROP = VERIFICATION / "uhlmann2015_sphere_drop.toml"
GOLDEN_SCRIPT = GOLDEN / "yade_impact_sphere_drop.py"
STORED = DATA / "yade_impact_output"  # Yade 2023.02a on chung_ooi_test2_sphere_plane.toml


def bound_adapter():
    """Yade's impact adapter bound to a Yade that is not installed (files only)."""
    return bind("impact", "yade", executable="/nonexistent/yade")


def test_rendered_script_matches_golden(tmp_path):
    bound_adapter().write_input(build_scene(load_case(DROP).model), tmp_path)
    rendered = (tmp_path / "impact.py").read_text()
    assert_matches_golden(rendered, GOLDEN_SCRIPT)
    compile(rendered, "impact.py", "exec")


def test_command_runs_the_impact_script(tmp_path):
    yade = bound_adapter()
    yade.write_input(build_scene(load_case(DROP).model), tmp_path)
    command, env = yade.command(build_scene(load_case(DROP).model), tmp_path)
    assert command[-1].endswith("impact.py") and env["TMPDIR"].startswith(str(tmp_path.resolve()))


def test_tilted_plane_becomes_one_large_facet(tmp_path):
    case = load_case(DROP, overrides=["plane.normal=[0.0, 0.6, 0.8]", "spheres.0.position=[0, 0.0, 0.02]"]).model
    bound_adapter().write_input(build_scene(case), tmp_path)
    script = (tmp_path / "impact.py").read_text()
    assert "utils.facet(" in script and "utils.wall(" not in script
    compile(script, "impact.py", "exec")


def test_scene_arrays_round_trip(tmp_path):
    scene = build_scene(load_case(VERIFICATION / "chung_ooi_test1_sphere_sphere.toml").model)
    bound_adapter().write_input(scene, tmp_path)
    data = np.load(tmp_path / "scene.npz")
    np.testing.assert_array_equal(data["positions"], scene.positions)
    np.testing.assert_array_equal(data["velocities"], scene.velocities)
    assert list(data["materials"]) == ["glass", "glass"]


def test_damping_maps_to_betan_and_betas():
    # Yade: c_n = 2 betan sqrt(m 3/2 k_n0 delta^(1/2)), c_t = 2 betas sqrt(m k_t0 delta^(1/2));
    # the paper: c_n = c_t = alpha sqrt(m k_n0) delta^(1/4)
    alpha, k_n0, k_t0 = 0.2973, 7.9e10, 5.9e10
    betan, betas = yade_damping_parameters(alpha, k_n0, k_t0)
    assert 2 * betan * math.sqrt(1.5 * k_n0) == pytest.approx(alpha * math.sqrt(k_n0), rel=1e-14)
    assert 2 * betas * math.sqrt(k_t0) == pytest.approx(alpha * math.sqrt(k_n0), rel=1e-14)


def test_render_context_of_the_sphere_drop():
    context = impact_context(build_scene(load_case(DROP).model))
    (row,) = eval(context["pairs_betan"])  # noqa: S307 (a literal we rendered)
    alpha = closed_form.alpha_from_restitution(0.68)
    assert row[:2] == ("ceramic", "steel") and row[2] == pytest.approx(alpha / math.sqrt(6), rel=1e-12)
    (kso,) = eval(context["pairs_kso"])  # noqa: S307
    # eq. 5: 4 G_m / (2 - nu_m) per sqrt(m); Yade's own 8 G* is 19.4 % lower for ceramic on steel
    g_m = (77e9 / 2.38 + 210e9 / 2.6) / 2
    assert kso[2] == pytest.approx(4 * g_m / (2 - 0.245), rel=1e-12)
    assert mindlin_shear_coefficient(77e9, 0.19, 210e9, 0.3) / kso[2] == pytest.approx(0.806, abs=1e-3)
    assert context["native_damping"] is False
    assert [m["name"] for m in context["materials"]] == ["ceramic", "steel"]


def test_rigid_wall_is_a_million_times_stiffer_than_the_sphere():
    context = impact_context(build_scene(load_case(VERIFICATION / "chung_ooi_test2_sphere_plane.toml").model))
    materials = {m["name"]: float(m["young"]) for m in context["materials"]}
    assert materials["rigid"] == 1e6 * materials["aluminium_alloy"]
    assert context["plane"]["axis"] == 2 and context["plane"]["sense"] == 1


def test_thornton_fit_is_what_yade_2023_computes():
    # betan printed by Yade 2023.02a's Ip2_FrictMat_FrictMat_MindlinPhys for en = 0.68 and 0.86
    assert thornton_betan(0.68) == pytest.approx(0.1214876022052592, rel=1e-12)
    assert thornton_betan(0.86) == pytest.approx(0.04523525951933114, rel=1e-12)
    assert thornton_betan(1.0) == 0.0
    # Thornton's fit is a fit of the no-tension law: sqrt(6) betan is within 0.1 % of the exact alpha at 0.68
    assert math.sqrt(6) * thornton_betan(0.68) / closed_form.alpha_from_restitution(0.68) == pytest.approx(
        1.0009, abs=2e-4)
    assert contact.damping_alpha(0.68) < math.sqrt(6) * thornton_betan(0.68)


def test_parser_reads_a_stored_yade_output(tmp_path):
    scene = build_scene(load_case(VERIFICATION / "chung_ooi_test2_sphere_plane.toml").model)
    shutil.copytree(STORED, tmp_path / "output")
    result = read_impact_output(scene, tmp_path)
    assert result.status == "ok" and result.attrs["n_steps"] == 187
    assert result.series["positions"].values.shape == (len(result.time), 1, 3)
    assert result.time[0] == 0.0 and result.time[-1] >= 1e-3
    assert result.events["peak_normal_force"].values[0] == pytest.approx(11370.27, rel=1e-6)
    assert result.series["normal_force"].values.max() <= result.events["peak_normal_force"].values[0]


def test_parser_drops_a_cut_off_row_and_reports_a_missing_status(tmp_path):
    scene = build_scene(load_case(VERIFICATION / "chung_ooi_test2_sphere_plane.toml").model)
    shutil.copytree(STORED, tmp_path / "output")
    (tmp_path / "output" / "status.json").unlink()
    body = (tmp_path / "output" / "series.bin").read_bytes()
    (tmp_path / "output" / "series.bin").write_bytes(body[: len(body) // 2 + 20])
    result = read_impact_output(scene, tmp_path)
    assert result.status == "failed" and "no status" in result.message
    assert len(result.time) == (len(body) // 2 + 20) // (18 * 8)
