"""A rigid grain on a Johnson-Cook solid in a fluid: the grain touches the solid through eq. G8 (engines/sph/src/
grains.h: a spring on each solid particle's overlap with the grain's sphere), never through the pair terms, and the
fluid meets the solid through eq. FS1 (fluid_solid.h); the case's deck carries eq. G8's spring, and a solid beside a
fluid without eq. SS1's smoothing is refused."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
from paths import REPO

from orchestrator.case import load_case
from orchestrator.errors import CaseError
from orchestrator.kinds import build_scene
from orchestrator.kinds.sph_flow.case_impactors import stiffness_scale
from orchestrator.kinds.sph_flow.checks_base import frames_of
from orchestrator.kinds.sph_flow.sph import deck_context
from orchestrator.runh5 import read_run

DATA = REPO / "tests/kinds/sph_flow/data"
LAYER = (DATA / "solid_layer_material.toml").read_text()


def _case(tmp_path, text=None):
    text = (DATA / "sph_grain_on_layer.toml").read_text() if text is None else text
    assert text.count("[physics]") == 1
    path = tmp_path / "case.toml"
    path.write_text(text.replace("[physics]", LAYER + "[physics]"))
    return path


def test_a_grain_beside_a_solid_takes_the_contact_spring_of_the_stiffest_material(tmp_path):
    case = load_case(_case(tmp_path)).model
    scene = build_scene(case)
    context = deck_context(scene)
    contact = json.loads(context["grain_contact"])
    # rho0 c_L^2 dx of the layer (c_L^2 = (K + 4 G / 3) / rho0 = 166.7 m^2/s^2): 333 N/m at dx = 1 mm
    assert contact == {"solid_stiffness": pytest.approx(stiffness_scale(scene.materials, 0.001))}
    assert contact["solid_stiffness"] == pytest.approx((2.0e5 + 4.0 / 3.0 * 1.0e5) * 0.001)
    assert json.loads(context["grains"][0])["contact_radius"] == 0.0025


def _refusal(path) -> str:
    with pytest.raises(CaseError) as error:
        load_case(path)
    lines = str(error.value).splitlines()
    assert len(lines) == 2, lines  # "<case>: invalid case" and one line naming the key
    return lines[1]


def test_a_solid_beside_a_fluid_without_smoothing_is_named(tmp_path):
    text = (DATA / "sph_grain_on_layer.toml").read_text()
    path = tmp_path / "case.toml"
    path.write_text(text.replace("[physics]", LAYER.replace("smoothing = 0.02\n", "") + "[physics]"))
    assert "materials[1].solid.smoothing = None: the johnson_cook material 'layer' beside the fluid 'oil' needs" in \
        _refusal(path)


def test_grain_contact_walls_without_the_grains_spring_are_named(tmp_path):
    text = (DATA / "sph_grain_on_layer.toml").read_text() + "\n[grain_contact]\nrestitution = 0.5\n"
    assert "grain_contact.restitution and grain_contact.walls need grain_contact.stiffness" in \
        _refusal(_case(tmp_path, text))


def test_grain_contact_without_a_spring_or_a_solid_is_named(tmp_path):
    text = (DATA / "sph_grain_in_oil.toml").read_text() + "\n[grain_contact]\nsolid_stiffness_factor = 2.0\n"
    (tmp_path / "case.toml").write_text(text)
    assert "grain_contact.stiffness is missing: without it the grains touch only a solid" in \
        _refusal(tmp_path / "case.toml")


@pytest.mark.sph
def test_a_heavy_grain_comes_to_rest_on_a_soft_layer_in_oil(tmp_path):
    out = tmp_path / "run"
    done = subprocess.run([sys.executable, "-m", "orchestrator", "run", str(_case(tmp_path)), "--out", str(out),
                           "--no-progress"], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    run = read_run(out)
    series = {k: np.asarray(run["series"][f"grain_grain_{k}"]) for k in ("position", "velocity", "force", "contact")}
    (_, first), (_, last) = frames_of(run)[0], frames_of(run)[-1]
    mass = 3000.0 * np.count_nonzero(np.asarray(first["kind"]) == 4) * 1e-9  # rho_g N dx^3, kg
    weight = mass * 9.81
    # measured (30 s): the grain comes down onto the layer and stops 6 um (0.006 dx) short of eq. G8's reach, the
    # oil squeezed between them carrying its weight (their sum 1.000 of it over the last 0.1 s); the contact, had
    # it acted, pushes along z only
    late = np.asarray(run["series"]["time"]) >= 0.2
    contact = series["contact"]
    layer_now = (np.asarray(last["material"]) == 1) & (np.asarray(last["kind"]) == 0)
    gap = np.linalg.norm(np.asarray(last["positions"])[layer_now] - series["position"][-1], axis=1).min() - 0.003
    assert gap < 0.02e-3
    assert np.all(contact[:, 2] >= 0.0)
    carried = (series["force"][late, 2] + contact[late, 2]) / weight
    assert np.abs(carried - 1.0).max() < 0.01
    assert np.abs(contact[:, :2]).max() < 1e-9 * weight
    # The layer stays a layer: before eqs. G8 and FS1 the grain's summation density took the solid's heavier
    # particles and pushed 50 of them out into the oil; none leaves and the rim stays within 0.7 dx of the top row
    layer = (np.asarray(last["material"]) == 1) & (np.asarray(last["kind"]) == 0)
    assert np.asarray(last["positions"])[layer, 2].max() < 0.0055 + 0.0007
    # The four top-row particles under the grain sink 0.0175 mm under the squeezed oil, within Hertz's elastic
    # indentation under the grain's submerged weight (0.006-0.022 mm, docs/solids.md); before eq. FS2 the oil's
    # velocity entered the solid's density and velocity gradient and they crept down 0.066 mm in 0.3 s
    x0, z = np.asarray(first["positions"]), dict(zip(np.asarray(last["ids"]), np.asarray(last["positions"])[:, 2]))
    under = (np.asarray(first["material"]) == 1) & (x0[:, 2] > 0.0054) & (np.hypot(x0[:, 0] - 0.006, x0[:, 1] - 0.006)
                                                                          < 0.0008)
    sunk = np.array([0.0055 - z[i] for i in np.asarray(first["ids"])[under]])
    assert len(sunk) == 4 and np.all(sunk > 0.005e-3) and np.all(sunk < 0.03e-3), sunk
