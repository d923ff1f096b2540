"""The sph executable's stress diffusion of the PTT mode stresses (eq. SD1, configuration PTT + Morris in a
Lees-Edwards cell) against the numpy reference (orchestrator.reference.sph_ptt, with its Morris solvent): a tiny
disordered periodic 2D scene in a Lees-Edwards cell at zero shear rate (a plain periodic box, which the reference
models) runs 20 steps in both; positions, velocities, densities and mode stresses agree to 1e-9, and the diffusion
changes the stresses far above that. Also: SD1 leaves a uniform stress alone and damps a sinusoidal one at kappa k^2.
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

from orchestrator.reference import sph_ptt as ref

STEPS = 20
DT = 2e-3  # s
TOLERANCE = 1e-9
N = 8  # particles per side
LENGTH = 1.0  # m, box side
KAPPA = 0.01  # m^2/s
EXECUTABLE = Path(os.environ.get("ORCHESTRATOR_SPH") or REPO / "engines/sph/build/sph")
needs_executable = pytest.mark.skipif(not EXECUTABLE.exists(), reason=f"{EXECUTABLE} is not built")


def _scene() -> tuple[ref.PttState, ref.PttFluid]:
    rng = np.random.default_rng(11)
    dx = LENGTH / N
    a, b = np.meshgrid(np.arange(N), np.arange(N), indexing="ij")
    x = np.stack([a.ravel() + 0.5, b.ravel() + 0.5], axis=1) * dx + rng.uniform(-0.1, 0.1, (N * N, 2)) * dx
    v = rng.uniform(-0.2, 0.2, (N * N, 2))  # m/s
    rho = 1.0 + rng.uniform(-0.005, 0.005, N * N)
    fluid = ref.PttFluid(rho0=1.0, c0=5.0, lambdas=(0.05, 0.01), etas=(0.01, 0.004), epsilon=0.3, eta_s=0.001,
                         h=1.3 * dx, box=(LENGTH, LENGTH), stress_diffusion=KAPPA, morris=True)
    state = ref.PttState(x=x, v=v, m=np.full(N * N, dx * dx), rho=rho, tau=np.zeros((N * N, 2, 2, 2)),
                         tau_solvent=np.zeros((N * N, 2, 2)))
    return state, fluid


def _write(state: ref.PttState, fluid: ref.PttFluid, workdir: Path) -> None:
    import h5py

    with h5py.File(workdir / "particles.h5", "w") as f:
        f["positions"], f["velocities"], f["masses"], f["densities"] = state.x, state.v, state.m, state.rho
        f["kind"] = np.zeros(len(state.x), dtype=np.int8)
    material = {"name": "melt", "model": "ptt", "rho0": fluid.rho0, "c0": fluid.c0, "epsilon": fluid.epsilon,
                "solvent_viscosity": fluid.eta_s, "stress_diffusion": fluid.stress_diffusion,
                "modes": [{"lambda": lam, "eta": eta} for lam, eta in zip(fluid.lambdas, fluid.etas)]}
    deck = {"dimension": 2, "particles_file": "particles.h5", "physics": ["morris_viscosity"], "v_max": 0.4,
            "h": fluid.h, "dx": LENGTH / N, "periodic": {"axes": [0, 1], "lo": [0, 0], "hi": [LENGTH, LENGTH]},
            "lees_edwards": {"shear_rate": 0.0}, "materials": [material], "dt": DT, "t_end": STEPS * DT,
            "threads": 1, "output": {"file": "out.h5", "frame_interval": STEPS * DT, "progress_interval": 100}}
    (workdir / "deck.json").write_text(json.dumps(deck))


@pytest.mark.sph
@needs_executable
def test_executable_stress_diffusion_agrees_with_the_reference(tmp_path):
    import h5py

    start, fluid = _scene()
    _write(start, fluid, tmp_path)
    done = subprocess.run([str(EXECUTABLE), "deck.json"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    with h5py.File(tmp_path / "out.h5", "r") as h5:
        last = h5["frames"][str(len(h5["frames"]) - 1)]
        assert int(last.attrs["step"]) == STEPS
        frame = {key: last[key][()] for key in ("ids", "positions", "velocities", "densities", "mode_stress")}
    mine = ref.simulate(start, fluid, DT, STEPS)
    ids = frame["ids"]
    box = np.asarray(fluid.box)
    dx = frame["positions"] - mine.x[ids]
    dx -= box * np.round(dx / box)
    assert np.abs(dx).max() <= TOLERANCE * np.abs(mine.x - start.x).max()
    assert np.abs(frame["velocities"] - mine.v[ids]).max() <= TOLERANCE * np.abs(mine.v).max()
    assert np.abs(frame["densities"] / mine.rho[ids] - 1.0).max() <= TOLERANCE
    tau = frame["mode_stress"].reshape(len(ids), 2, 2, 2)
    scale = np.abs(mine.tau).max()
    assert np.abs(tau - mine.tau[ids]).max() <= TOLERANCE * scale
    # not trivial: the disordered velocities build a rough stress, which the diffusion changes far above the tolerance
    plain = ref.simulate(start, replace(fluid, stress_diffusion=0.0), DT, STEPS)
    assert np.abs(plain.tau - mine.tau).max() > 1e-3 * scale


def test_reference_diffusion_leaves_a_uniform_stress_and_damps_a_wave():
    """On a square lattice at rest: SD1 of a uniform stress is zero (to rounding); of tau_xy = A sin(k x) it is
    -kappa k^2 tau_xy within the lattice sum's error (5.4 % at 16 particles per wavelength, the plain Morris sum's 0.96 of a Laplacian)."""
    n, length = 32, 1.0
    dx = length / n
    a, b = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    x = np.stack([a.ravel() + 0.5, b.ravel() + 0.5], axis=1) * dx
    fluid = ref.PttFluid(rho0=1.0, c0=1.0, lambdas=(1e9,), etas=(1e9,), epsilon=0.0, eta_s=0.0, h=1.3 * dx,
                         box=(length, length), stress_diffusion=1.0)
    k = 2.0 * np.pi * 2 / length
    tau = np.zeros((n * n, 1, 2, 2))
    tau[:, 0, 0, 1] = tau[:, 0, 1, 0] = np.sin(k * x[:, 0])
    state = ref.PttState(x=x, v=np.zeros_like(x), m=np.full(n * n, dx * dx), rho=np.ones(n * n), tau=tau,
                         tau_solvent=np.zeros((n * n, 2, 2)))
    with_diffusion = ref.rates(state, fluid).dtau[:, 0, 0, 1]
    without = ref.rates(state, replace(fluid, stress_diffusion=0.0)).dtau[:, 0, 0, 1]
    lap = with_diffusion - without
    assert np.allclose(lap, -k * k * tau[:, 0, 0, 1], rtol=0.0, atol=0.06 * k * k)
    uniform = replace(state, tau=np.full_like(tau, 3.0))
    diff = ref.rates(uniform, fluid).dtau - ref.rates(uniform, replace(fluid, stress_diffusion=0.0)).dtau
    assert np.abs(diff).max() < 1e-9
