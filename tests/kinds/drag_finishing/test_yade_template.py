"""Golden file: the Yade script rendered for the tiny case. A template change is a visible diff.

Numbers are compared within a relative 1e-9 (tests/golden.py): their last digits follow the CPU's BLAS kernel.
Regenerate after an intended change with: UPDATE_GOLDEN=1 pytest tests/kinds/drag_finishing/test_yade_template.py
"""

import numpy as np
import pytest

from orchestrator.kinds import bind
from orchestrator.kinds.drag_finishing.yade import render_context

from orchestrator.case import load_case
from orchestrator.kinds import build_scene

from golden import assert_matches_golden
from paths import GOLDEN as GOLDEN_DIR
from paths import TINY_BOWL

GOLDEN = GOLDEN_DIR / "yade_tiny_bowl.py"


@pytest.fixture(scope="module")
def tiny_scene(tiny_bowl_scene):
    return tiny_bowl_scene


def test_rendered_script_matches_golden(tiny_scene, tmp_path):
    bind("drag_finishing", "yade", executable="/nonexistent/yade").write_input(tiny_scene, tmp_path)
    rendered = (tmp_path / "drag_finishing.py").read_text()
    assert_matches_golden(rendered, GOLDEN)
    compile(rendered, "drag_finishing.py", "exec")  # valid python for Yade's interpreter


def test_scene_inputs_round_trip(tiny_scene, tmp_path):
    bind("drag_finishing", "yade", executable="/nonexistent/yade").write_input(tiny_scene, tmp_path)
    data = np.load(tmp_path / "scene.npz")
    np.testing.assert_array_equal(data["positions"], tiny_scene.positions)
    np.testing.assert_array_equal(data["radii"], tiny_scene.radii)
    np.testing.assert_array_equal(data["rod_faces"], tiny_scene.meshes["rod"].mesh.faces)
    assert (tmp_path / "bowl.stl").is_file() and (tmp_path / "rod.stl").is_file()


def test_same_seed_same_cloud(tiny_scene):
    again = build_scene(load_case(TINY_BOWL).model)
    np.testing.assert_array_equal(again.positions, tiny_scene.positions)
    other = build_scene(load_case(TINY_BOWL, overrides=["case.seed=8"]).model)
    assert not np.array_equal(other.positions, tiny_scene.positions)


def test_render_context_maps_case_to_yade(tiny_scene):
    ctx = render_context(tiny_scene)
    case = tiny_scene.case
    assert float(ctx["dt"]) == pytest.approx(tiny_scene.timestep)
    # angular velocity of the rod about the bowl axis = v_w / path radius
    assert float(ctx["angular_velocity"]) == pytest.approx(0.01 / 0.005)
    # E scaled by numerics.stiffness_scale
    ceramic = next(m for m in ctx["materials"] if m["name"] == "ceramic")
    assert float(ceramic["young"]) == pytest.approx(77e9 * case.numerics.stiffness_scale)
    # per-pair friction as Yade friction angles: atan(mu)
    rows = eval(ctx["pairs_friction_angle"])  # noqa: S307 (a literal tuple we rendered)
    assert dict(((a, b), v) for a, b, v in rows)[("ceramic", "steel")] == pytest.approx(np.arctan(0.28))
