"""Rigid grains in the reference SPH (orchestrator.reference.sph_grains) against the sph executable step by step
(eqs. G1-G3 of engines/sph/src/grains.h), and the reference's own balances."""

from __future__ import annotations

import numpy as np
import pytest
from paths import DATA
from test_sph_reference import STEPS, TOLERANCE, _engine_frames

from orchestrator.case import load_case
from orchestrator.kinds import build_scene
from orchestrator.reference import sph as ref
from orchestrator.reference import sph_grains

SCENE = DATA / "sph_reference_grain.toml"


def _reference(scene, steps: int):
    state, model = ref.from_scene(scene)
    grains, state = sph_grains.grains_from_scene(scene, state)
    start = state.x.copy()
    history = []
    for k in range(1, steps + 1):
        state, grains = sph_grains.step(state, grains, model, scene.case.numerics.dt)
        history.append((k, state, grains))
    return start, history


def test_reference_grain_and_fluid_keep_their_momentum():
    scene = build_scene(load_case(SCENE).model)
    start, history = _reference(scene, 5)
    fluid = scene.kind == 0
    totals = []
    for _, state, grains in [(0, None, None)] + history:
        if state is None:
            continue
        body = grains.bodies[0]
        totals.append(state.mass[fluid] @ state.v[fluid] + body.mass * grains.states[0].velocity)
    scale = np.abs(scene.masses[fluid]).sum() * 0.08
    assert np.abs(np.diff(totals, axis=0)).max() < 1e-13 * scale  # pair by pair action and reaction (eq. G1)
    assert np.abs(history[-1][2].force[0]).max() > 0.0  # the fluid does push on the grain


#: The scene as it is, and with the renormalised Morris sum (eq. VC1: a grain's particles take the fluid's factor).
VARIANTS = {"plain": [], "renormalised": ["physics.viscosity_correction=true"]}


@pytest.mark.sph
@pytest.mark.parametrize("variant", sorted(VARIANTS))
def test_executable_and_reference_agree_step_by_step(variant, tmp_path):
    case = load_case(SCENE, overrides=["output.frame_interval=1e-4", *VARIANTS[variant]])  # a frame a step
    scene = build_scene(case.model)
    frames = _engine_frames(scene, tmp_path)
    assert [f["step"] for f in frames] == list(range(STEPS + 1))
    start, history = _reference(scene, STEPS)
    grain = scene.kind == 4
    for (step, mine, _), frame in zip(history, frames[1:]):
        ids = frame["ids"]
        moved = np.abs(mine.x[ids] - start[ids]).max()
        assert np.abs(frame["positions"] - mine.x[ids]).max() <= TOLERANCE * moved, f"positions at step {step}"
        assert np.abs(frame["densities"] / mine.rho[ids] - 1.0).max() <= TOLERANCE, f"densities at step {step}"
    # Not trivial: the grain moved and turned by a good fraction of dx, and the fluid dragged on it.
    turned = np.abs(mine.x[grain] - start[grain] - (mine.x[grain] - start[grain]).mean(axis=0)).max()
    assert np.abs(mine.x[grain] - start[grain]).max() > 0.1 * case.model.numerics.dx and turned > 0.02 * 1e-3
    velocity = history[-1][2].states[0].velocity
    assert np.abs(velocity - np.array([0.08, 0.0, -0.03])).max() > 1e-4
