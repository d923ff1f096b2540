"""The sph executable's Johnson-Cook solid against the numpy reference (orchestrator.reference.sph_solid).

Tiny periodic scenes of Al6061-T6 (Nutto et al. Tables I and II; Steinberg's Mie-Grueneisen constants) at random
velocities of +-120 m/s, written here by hand (deck and particle file): they yield within a few steps, and one
scene fails and heats; in the two_bodies scenes each half of the box is a body of its own material (eq. SC1:
contact in compression only between them). 20 steps in both; positions, velocities, densities, the deviatoric
stresses and the solid scalars (energy, plastic strain and rate, temperature, damage, s_zz) agree to 1e-9.
"""

from __future__ import annotations

import json
import os
import subprocess
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from paths import REPO

from orchestrator.reference import johnson_cook as jc
from orchestrator.reference import sph_solid as ref
from orchestrator.reference.solid_eos import LinearEos, MieGruneisen

STEPS = 20
DT = 3e-8  # s (0.2 h / c at dx = 1 mm)
TOLERANCE = 1e-9
DX = 1e-3  # m
RHO0 = 2703.0  # kg/m^3
SHEAR = 26e9  # Pa
EXECUTABLE = Path(os.environ.get("ORCHESTRATOR_SPH") or REPO / "engines/sph/build/sph")

#: The scenes: dimension, particles per side, eos, failure, heat fraction, artificial stress epsilon, AV alpha, beta,
#: momentum sum (eq. T1 plain or eq. KC1 corrected).
SCENES = {
    "linear_2d": (2, 8, "linear", False, 0.0, 0.3, 0.0, 0.0, "plain"),
    "shock_failure_2d": (2, 8, "mie_gruneisen", True, 0.95, 0.3, 1.0, 1.0, "plain"),
    "linear_3d": (3, 6, "linear", False, 0.95, 0.3, 1.0, 0.0, "plain"),
    "corrected_failure_2d": (2, 8, "mie_gruneisen", True, 0.95, 0.3, 1.0, 1.0, "corrected"),
    "corrected_3d": (3, 6, "linear", False, 0.95, 0.3, 1.0, 0.0, "corrected"),
    "two_bodies_2d": (2, 8, "linear", False, 0.0, 0.3, 1.0, 0.0, "plain"),
    "two_bodies_3d": (3, 6, "mie_gruneisen", True, 0.95, 0.3, 1.0, 1.0, "plain"),
}


def _scene(name: str) -> tuple[ref.SolidState, ref.SolidScene, dict]:
    dim, n, eos_name, fails, chi, epsilon, alpha, beta, momentum = SCENES[name]
    eos = LinearEos(RHO0, 70e9) if eos_name == "linear" else MieGruneisen(RHO0, 5240.0, 1.4, 1.97)
    failure = jc.Failure(D1=0.002, D2=0.01, D3=-0.47, D4=0.0, D5=1.6) if fails else None
    solid = jc.Solid(SHEAR, eos, jc.AL6061_T6_STRENGTH, failure, heat_capacity=896.0, heat_fraction=chi)
    scene = ref.SolidScene(solid, True, 1.3 * DX, DX, (n * DX,) * dim, epsilon, 4, alpha, beta,
                           momentum == "corrected")
    rng = np.random.default_rng(3 + dim)
    grid = np.stack(np.meshgrid(*[np.arange(n)] * dim, indexing="ij"), -1).reshape(-1, dim)
    count = len(grid)
    x = (grid + 0.5 + rng.uniform(-0.1, 0.1, grid.shape)) * DX
    state = ref.SolidState(x=x, v=rng.uniform(-120.0, 120.0, grid.shape), m=np.full(count, RHO0 * DX ** dim),
                           rho=RHO0 * (1.0 + rng.uniform(-1e-3, 1e-3, count)), s=np.zeros((count, dim, dim)),
                           scalars=ref.start_scalars(scene, count),
                           body=(grid[:, 0] >= n // 2).astype(np.int32) if name.startswith("two_bodies") else None)
    material = {"name": "al", "model": "johnson_cook", "rho0": RHO0, "shear_modulus": SHEAR,
                "yield_stress": 324e6, "hardening_modulus": 114e6, "hardening_exponent": 0.42,
                "rate_sensitivity": 0.002, "thermal_exponent": 1.34, "melting_temperature": 925.0,
                "artificial_stress": {"epsilon": epsilon, "exponent": 4}, "momentum": momentum}
    if eos_name == "linear":
        material["bulk_modulus"] = 70e9
    else:
        material.update(eos="mie_gruneisen", bulk_sound_speed=5240.0, hugoniot_slope=1.4, gruneisen=1.97)
    if chi > 0.0:
        material.update(heat_fraction=chi, heat_capacity=896.0)
    if fails:
        material["failure"] = {"d1": 0.002, "d2": 0.01, "d3": -0.47, "d4": 0.0, "d5": 1.6}
    deck = {"dimension": dim, "particles_file": "particles.h5", "physics": ["artificial_viscosity"] if alpha else [],
            "v_max": 250.0, "h": scene.h, "dx": DX,
            "materials": [material] if state.body is None else [material, {**material, "name": "al2"}],
            "periodic": {"axes": list(range(dim)), "lo": [0.0] * dim, "hi": list(scene.box)},
            "dt": DT, "t_end": STEPS * DT, "threads": 1,
            "output": {"file": "out.h5", "frame_interval": STEPS * DT, "progress_interval": 100}}
    if alpha:
        deck.update(alpha=alpha, beta=beta)
    return state, scene, deck


def _run_executable(state: ref.SolidState, deck: dict, workdir: Path) -> dict:
    import h5py

    with h5py.File(workdir / "particles.h5", "w") as f:
        f["positions"], f["velocities"], f["masses"], f["densities"] = state.x, state.v, state.m, state.rho
        f["kind"] = np.zeros(len(state.x), dtype=np.int8)
        if state.body is not None:
            f["material"] = state.body
    (workdir / "deck.json").write_text(json.dumps(deck))
    done = subprocess.run([str(EXECUTABLE), "deck.json"], cwd=workdir, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    with h5py.File(workdir / "out.h5", "r") as h5:
        last = h5["frames"][str(len(h5["frames"]) - 1)]
        assert int(last.attrs["step"]) == STEPS
        return {key: last[key][()] for key in ("ids", "positions", "velocities", "densities", "stress",
                                               "solid_state")}


@pytest.mark.sph
@pytest.mark.parametrize("name", sorted(SCENES))
def test_executable_solid_agrees_with_the_reference(name, tmp_path):
    if not EXECUTABLE.exists():
        pytest.skip(f"{EXECUTABLE} is not built")
    start, scene, deck = _scene(name)
    frame = _run_executable(start, deck, tmp_path)
    mine = ref.simulate(start, scene, DT, STEPS)
    ids, dim = frame["ids"], start.x.shape[1]
    box = np.asarray(scene.box)
    dx = frame["positions"] - mine.x[ids]
    dx -= box * np.round(dx / box)  # the executable wraps positions into the box
    moved = np.abs(mine.x - start.x).max()
    assert np.abs(dx).max() <= TOLERANCE * moved
    assert np.abs(frame["velocities"] - mine.v[ids]).max() <= TOLERANCE * np.abs(mine.v).max()
    assert np.abs(frame["densities"] / mine.rho[ids] - 1.0).max() <= TOLERANCE
    s = frame["stress"].reshape(len(ids), dim, dim)
    assert np.abs(s - mine.s[ids]).max() <= TOLERANCE * np.abs(mine.s).max()
    scalars, expected = frame["solid_state"], mine.scalars[ids]
    for column in range(6):
        scale = np.abs(expected[:, column]).max()
        assert np.abs(scalars[:, column] - expected[:, column]).max() <= TOLERANCE * max(scale, 1e-300), column
    # Not trivial: most particles yielded, the stresses reach the yield stress, the artificial stress matters.
    plastic = mine.scalars[:, ref.PLASTIC_STRAIN] > 0.0
    assert plastic.mean() > 0.5 and np.abs(mine.s).max() > 1e8
    if SCENES[name][3]:
        failed = mine.scalars[:, ref.DAMAGE] >= 1.0
        assert 0 < failed.sum() < len(failed)
        assert mine.scalars[:, ref.TEMPERATURE].max() > 294.0
    plain = ref.simulate(start, replace(scene, artificial_stress=0.0), DT, STEPS)
    assert np.abs(plain.v - mine.v).max() > 1e3 * TOLERANCE * np.abs(mine.v).max()
    if start.body is not None:  # eq. SC1 matters: touching pairs, and one body moves otherwise
        assert ref.contact_energy(start, scene) > 0.0
        welded = ref.simulate(replace(start, body=None), scene, DT, STEPS)
        assert np.abs(welded.v - mine.v).max() > 1e3 * TOLERANCE * np.abs(mine.v).max()
    if scene.corrected_momentum:  # eq. KC1 matters on the perturbed lattice
        uncorrected = ref.simulate(start, replace(scene, corrected_momentum=False), DT, STEPS)
        assert np.abs(uncorrected.v - mine.v).max() > 1e3 * TOLERANCE * np.abs(mine.v).max()


def test_artificial_stress_takes_the_tensile_principal_stresses():
    sigma = np.array([[[1.0, 2.0], [2.0, 1.0]], [[-2.0, 1.0], [1.0, -2.0]]])  # principal (3, -1) and (-1, -3)
    R = ref.artificial_stress(sigma, 0.3)
    np.testing.assert_allclose(R[0], -0.45 * np.ones((2, 2)), atol=1e-14)
    np.testing.assert_allclose(R[1], 0.0, atol=1e-14)


@pytest.mark.parametrize("name", sorted(SCENES))
def test_kinetic_plus_internal_energy_is_conserved_to_the_time_step(name):
    """The internal energy takes the pair forces' work (stress, artificial stress and viscosity), so kinetic plus
    internal energy changes only by the time integration's error: below 0.5 % over 20 steps in which the kinetic
    energy falls by 44-92 % (measured 0.10 %, 0.26 %, 0.44 %), and about four times less at half the step (second
    order; measured 4.7, 3.9, 3.8 x)."""
    start, scene, _ = _scene(name)

    def total(state):
        return (0.5 * np.sum(state.m[:, None] * state.v ** 2) + np.sum(state.m * state.scalars[:, ref.ENERGY])
                + ref.contact_energy(state, scene))

    e0 = total(start)
    coarse = total(ref.simulate(start, scene, DT, STEPS)) / e0 - 1.0
    fine = total(ref.simulate(start, scene, DT / 2, 2 * STEPS)) / e0 - 1.0
    # Two bodies: the jittered lattices start overlapping, their springs (eq. SC1, counted in the total) holding 3.3
    # times the kinetic energy, released in the first steps: 2.0 % at DT, 0.37 % and 0.12 % at DT / 2 and DT / 4.
    assert abs(coarse) < (3e-2 if start.body is not None else 5e-3) and abs(fine) < abs(coarse) / 3.0
    kinetic = 0.5 * np.sum(start.m[:, None] * ref.simulate(start, scene, DT, STEPS).v ** 2) / e0
    assert kinetic < 0.6  # not trivial: most of the kinetic energy went into the solid
