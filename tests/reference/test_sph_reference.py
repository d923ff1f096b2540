"""The reference SPH (orchestrator.reference.sph) against the sph executable,
step by step, and its building blocks against their formulas.

The tiny scenes (tests/data/sph_reference_{2d,3d,two_materials}.toml) switch
on every term between them: Morris and artificial viscosity, gravity, fixed
boundary particles (one wall sliding; artificial viscosity with and without
the wall pairs), hydrostatic start densities,
triangle-mesh penalty walls, a periodic axis, background pressure, two
materials (each its own EOS and viscosity, the harmonic mean of eq. 10
across them).
"""

from __future__ import annotations

import math
import subprocess
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from orchestrator.kinds import bind

from orchestrator.case import load_case
from orchestrator.reference import sph as ref
from orchestrator.reference.sph_walls import PenaltyWalls, penalty_force
from orchestrator.kinds import build_scene
from paths import DATA

STEPS = 20
#: Agreement required after 20 steps: positions relative to the largest displacement, densities relative.
TOLERANCE = 1e-9

needs_sph = pytest.mark.sph


def _engine_frames(scene, workdir: Path) -> list[dict]:
    """Run the executable on the scene; every frame as {step, ids, positions, densities}."""
    import h5py

    bound_adapter = bind("sph_flow", "sph")
    bound_adapter.write_input(scene, workdir)
    command, env = bound_adapter.command(scene, workdir)
    done = subprocess.run(command, cwd=workdir, env={**env, "PATH": "/usr/bin:/bin"}, capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    with h5py.File(workdir / "out.h5", "r") as h5:
        return [{"step": int(h5["frames"][k].attrs["step"]), "ids": h5["frames"][k]["ids"][()],
                 "positions": h5["frames"][k]["positions"][()], "densities": h5["frames"][k]["densities"][()]}
                for k in sorted(h5["frames"], key=int)]


@needs_sph
@pytest.mark.parametrize("name,overrides", [
    ("sph_reference_2d", []), ("sph_reference_3d", []), ("sph_reference_two_materials", []),
    ("sph_reference_2d", ["physics.artificial_viscosity.walls=false"]),  # eqs. 11-12 on fluid-fluid pairs only
    ("sph_reference_2d", ["physics.viscosity_correction=true"]),  # the renormalised Morris sum (eq. VC1)
    ("sph_reference_2d", ["physics.eddy_viscosity=0.5"]),  # Smagorinsky's eddy viscosity (eqs. SM1-SM2)
    ("sph_reference_2d", ["physics.eddy_viscosity=0.5", "physics.eddy_viscosity_walls=false"]),  # fluid pairs only
    ("sph_reference_2d", ["physics.density_diffusion=0.5"]),  # eq. DD1 (lanes path; with the body force)
    ("sph_reference_3d", ["physics.density_diffusion=0.5"]),  # eq. DD1 (lanes path; periodic)
    ("sph_reference_2d", ["physics.density_diffusion=0.5", "physics.eddy_viscosity=0.5"]),  # eq. DD1, chunk path
])
def test_executable_and_reference_agree_step_by_step(name, overrides, tmp_path):
    case = load_case(DATA / f"{name}.toml", overrides=["output.frame_interval=2e-4", *overrides])  # a frame a step
    scene = build_scene(case.model)
    frames = _engine_frames(scene, tmp_path)
    assert [f["step"] for f in frames] == list(range(STEPS + 1))

    state, model = ref.from_scene(scene)
    start = state.x.copy()
    _, states = ref.simulate(state, model, case.model.numerics.dt, STEPS, every=1)
    for (step, mine), frame in zip(states, frames[1:]):
        assert frame["step"] == step
        ids = frame["ids"]
        moved = np.abs(mine.x[ids] - start[ids]).max()
        assert np.abs(frame["positions"] - mine.x[ids]).max() <= TOLERANCE * moved, f"positions at step {step}"
        assert np.abs(frame["densities"] / mine.rho[ids] - 1.0).max() <= TOLERANCE, f"densities at step {step}"
    # The scene is not trivial: particles moved by a good fraction of dx and densities changed by far more
    # than the tolerance.
    assert moved > 0.1 * case.model.numerics.dx
    assert np.abs(mine.rho / state.rho - 1.0).max() > 1e3 * TOLERANCE


@pytest.mark.parametrize("name,term", [
    ("sph_reference_2d", "viscosity"), ("sph_reference_2d", "alpha"), ("sph_reference_2d", "av_walls"),
    ("sph_reference_2d", "body_force"),
    ("sph_reference_3d", "walls"), ("sph_reference_3d", "periodic_axes"),
    ("sph_reference_two_materials", "materials"), ("sph_reference_2d", "viscosity_correction"),
    ("sph_reference_2d", "eddy_viscosity"), ("sph_reference_2d", "density_diffusion"),
    ("sph_reference_3d", "density_diffusion"),
])
def test_every_term_changes_the_tiny_scenes(name, term):
    """Each term matters in its scene far beyond the tolerance (so the comparison above can fail)."""
    scene = build_scene(load_case(DATA / f"{name}.toml").model)
    state, model = ref.from_scene(scene)
    if term == "viscosity_correction":  # off in the scene: on against off
        model = replace(model, viscosity_correction=True)
    if term == "eddy_viscosity":  # off in the scene: cs = 0.5 against off
        model = replace(model, eddy_viscosity=0.5)
    if term == "density_diffusion":  # off in the scene: delta = 0.5 against off
        model = replace(model, density_diffusion=0.5)
    dt = scene.case.numerics.dt
    full, _ = ref.simulate(state, model, dt, 5)
    without = {"periodic_axes": {"periodic_axes": (), "periodic_lo": (), "periodic_hi": ()},
               "materials": {"materials": model.materials[:1] * len(model.materials)},
               "av_walls": {"av_walls": False},
               "viscosity_correction": {"viscosity_correction": False}}.get(term, {term: None})
    cut, _ = ref.simulate(state, replace(model, **without), dt, 5)
    moved = np.abs(full.x - state.x).max()
    assert np.abs(cut.x - full.x).max() > 1e3 * TOLERANCE * moved


@pytest.mark.parametrize("dimension", [2, 3])
def test_corrected_morris_sum_is_the_exact_laplacian_on_a_lattice(dimension):
    """Eq. VC1: on a regular lattice at rest density the Morris sum of a quadratic field v = 1/2 y^T A y is
    nu tr(A) times the lattice's second moment tr(S) / D (0.9627 in 2D, 0.9696 in 3D at h = 1.3 dx: the 3 %
    bias), and nu tr(A) itself with the correction, at every particle with a full support."""
    n, dx, nu = 9, 1e-3, 1e-4
    grid = np.stack(np.meshgrid(*[np.arange(n) * dx] * dimension, indexing="ij"), -1).reshape(-1, dimension)
    y = grid - 0.5 * (n - 1) * dx
    A = np.array([[3.0, 2.0, 1.5], [2.0, -1.0, 0.7], [1.5, 0.7, 4.0]])[:dimension, :dimension]  # 1/(m s)
    v = np.zeros_like(grid)
    v[:, 0] = 0.5 * np.einsum("ij,jk,ik->i", y, A, y)
    count = len(grid)
    state = ref.SphState(x=grid, v=v, rho=np.full(count, 1000.0), mass=np.full(count, 1000.0 * dx**dimension),
                         kind=np.zeros(count, np.int8))
    model = ref.SphModel(dimension=dimension, rho0=1000.0, c0=1.0, h=1.3 * dx, viscosity=nu)
    inside = np.all(np.abs(y) <= 0.5 * (n - 1) * dx - 2.6 * dx + 1e-12, axis=1)
    assert inside.sum() == 3**dimension
    plain, _ = ref.rates(state, model)
    corrected, _ = ref.rates(state, replace(model, viscosity_correction=True))
    moment = {2: 0.96268, 3: 0.96957}[dimension]
    np.testing.assert_allclose(plain[inside, 0], nu * np.trace(A) * moment, rtol=1e-5)
    np.testing.assert_allclose(corrected[inside, 0], nu * np.trace(A), rtol=1e-12)
    np.testing.assert_allclose(corrected[inside, 1:], 0.0, atol=1e-12 * nu * abs(np.trace(A)))


@pytest.mark.parametrize("dimension", [2, 3])
def test_wendland_kernel_is_normalised_and_its_gradient_matches(dimension):
    h = 0.01
    r = np.linspace(0.0, 2.0 * h, 200001)
    w = ref.kernel_value(r, h, dimension)
    shell = 2.0 * math.pi * r if dimension == 2 else 4.0 * math.pi * r**2
    assert np.trapezoid(w * shell, r) == pytest.approx(1.0, rel=1e-8)
    # F(r) r = dW/dr (central differences), and W, F vanish at the support 2h
    mid = r[1:-1]
    dw = (w[2:] - w[:-2]) / (r[2] - r[0])
    assert np.allclose(ref.kernel_gradient_factor(mid, h, dimension) * mid, dw, atol=1e-6 * np.abs(dw).max())
    assert ref.kernel_value(2.0 * h, h, dimension) == 0.0


def test_tait_pressure_and_sound_speed():
    model = ref.SphModel(dimension=2, rho0=1000.0, c0=20.0, h=0.01, background_pressure=50.0)
    assert ref.tait_pressure(1000.0, model) == pytest.approx(50.0)
    # p = B ((rho/rho0)^7 - 1) + p_B, B = rho0 c0^2 / 7
    assert ref.tait_pressure(1010.0, model) == pytest.approx(1000.0 * 400.0 / 7.0 * (1.01**7 - 1.0) + 50.0)
    # c^2 = dp/drho
    dp = (ref.tait_pressure(1010.0 + 1e-4, model) - ref.tait_pressure(1010.0 - 1e-4, model)) / 2e-4
    assert ref.sound_speed(1010.0, model) ** 2 == pytest.approx(dp, rel=1e-7)


def test_penalty_force_of_eq14():
    R, s, psi = 0.01, 0.004, 2.0
    assert penalty_force(0.0, R, s, psi) == pytest.approx(psi)
    assert penalty_force(s, R, s, psi) == pytest.approx(0.0, abs=1e-15)
    assert penalty_force(R, R, s, psi) == 0.0 and penalty_force(1.5 * R, R, s, psi) == 0.0
    assert penalty_force(0.7 * s, R, s, psi) > 0.0 > penalty_force(0.5 * (s + R), R, s, psi)


def test_tessellated_flat_wall_pushes_once():
    """A particle above the diagonal of a square made of two triangles feels one face, not two."""
    vertices = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]])
    walls = PenaltyWalls({"floor": (vertices, np.array([[0, 1, 2], [0, 2, 3]]))}, 0.01, 0.004, 2.0)
    points = np.array([[0.5, 0.5, 0.002], [0.3, 0.6, 0.002], [1.0 + 0.002, 0.5, 0.0]])
    force = walls.forces(points)
    expected = penalty_force(0.002, 0.01, 0.004, 2.0)
    np.testing.assert_allclose(force[0], [0.0, 0.0, expected], rtol=1e-12, atol=1e-12 * expected)
    np.testing.assert_allclose(force[1], [0.0, 0.0, expected], rtol=1e-12, atol=1e-12 * expected)
    # the open rim edge counts once
    np.testing.assert_allclose(force[2], [expected, 0.0, 0.0], rtol=1e-12, atol=1e-12 * expected)
