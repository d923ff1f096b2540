"""The sph executable's multi-mode PTT fluid against the numpy reference (orchestrator.reference.sph_ptt).

A tiny periodic 2D scene of two PTT modes with a solvent viscosity (deck and particle file written here by
hand) runs 20 steps in both; positions, velocities, densities and the mode stresses agree to 1e-9. Also with the
mean extra stress subtracted in the momentum equation (the executable's Lees-Edwards cell at rest,
lees_edwards.subtract_mean_stress).
"""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

from orchestrator.reference import sph_ptt as ref
from paths import REPO

STEPS = 20
DT = 2e-3  # s
TOLERANCE = 1e-9
N = 8  # particles per side
LENGTH = 1.0  # m, box side
EXECUTABLE = Path(os.environ.get("ORCHESTRATOR_SPH") or REPO / "engines/sph/build/sph")


def _scene(subtract_mean_stress: bool = False) -> tuple[ref.PttState, ref.PttFluid]:
    rng = np.random.default_rng(4)
    dx = LENGTH / N
    a, b = np.meshgrid(np.arange(N), np.arange(N), indexing="ij")
    x = np.stack([a.ravel() + 0.5, b.ravel() + 0.5], axis=1) * dx + rng.uniform(-0.1, 0.1, (N * N, 2)) * dx
    v = rng.uniform(-0.2, 0.2, (N * N, 2))  # m/s
    rho = 1.0 + rng.uniform(-0.005, 0.005, N * N)
    fluid = ref.PttFluid(rho0=1.0, c0=5.0, lambdas=(0.05, 0.01), etas=(0.01, 0.004), epsilon=0.3, eta_s=0.002,
                         h=1.3 * dx, box=(LENGTH, LENGTH), subtract_mean_stress=subtract_mean_stress)
    state = ref.PttState(x=x, v=v, m=np.full(N * N, dx * dx), rho=rho, tau=np.zeros((N * N, 2, 2, 2)),
                         tau_solvent=np.zeros((N * N, 2, 2)))
    return state, fluid


def _run_executable(state: ref.PttState, fluid: ref.PttFluid, workdir: Path) -> dict:
    import h5py

    with h5py.File(workdir / "particles.h5", "w") as f:
        f["positions"], f["velocities"], f["masses"], f["densities"] = state.x, state.v, state.m, state.rho
        f["kind"] = np.zeros(len(state.x), dtype=np.int8)
    deck = {"dimension": 2, "particles_file": "particles.h5", "physics": [], "v_max": 0.4, "h": fluid.h,
            "dx": LENGTH / N, "periodic": {"axes": [0, 1], "lo": [0, 0], "hi": [LENGTH, LENGTH]},
            "materials": [{"name": "melt", "model": "ptt", "rho0": fluid.rho0, "c0": fluid.c0,
                           "epsilon": fluid.epsilon, "solvent_viscosity": fluid.eta_s,
                           "modes": [{"lambda": lam, "eta": eta} for lam, eta in zip(fluid.lambdas, fluid.etas)]}],
            "dt": DT, "t_end": STEPS * DT, "threads": 1,
            **({"lees_edwards": {"shear_rate": 0.0, "subtract_mean_stress": True}} if fluid.subtract_mean_stress
               else {}),
            "output": {"file": "out.h5", "frame_interval": STEPS * DT, "progress_interval": 100}}
    (workdir / "deck.json").write_text(json.dumps(deck))
    done = subprocess.run([str(EXECUTABLE), "deck.json"], cwd=workdir, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    with h5py.File(workdir / "out.h5", "r") as h5:
        last = h5["frames"][str(len(h5["frames"]) - 1)]
        assert int(last.attrs["step"]) == STEPS
        return {key: last[key][()] for key in ("ids", "positions", "velocities", "densities", "mode_stress")}


@pytest.mark.sph
@pytest.mark.parametrize("subtract_mean_stress", [False, True], ids=["plain", "mean_stress_subtracted"])
def test_executable_ptt_agrees_with_the_reference(tmp_path, subtract_mean_stress):
    if not EXECUTABLE.exists():
        pytest.skip(f"{EXECUTABLE} is not built")
    start, fluid = _scene(subtract_mean_stress)
    frame = _run_executable(start, fluid, tmp_path)
    mine = ref.simulate(start, fluid, DT, STEPS)
    ids = frame["ids"]
    box = np.asarray(fluid.box)
    dx = frame["positions"] - mine.x[ids]
    dx -= box * np.round(dx / box)  # the executable wraps positions into the box
    moved = np.abs(mine.x - start.x).max()
    assert np.abs(dx).max() <= TOLERANCE * moved
    assert np.abs(frame["velocities"] - mine.v[ids]).max() <= TOLERANCE * np.abs(mine.v).max()
    assert np.abs(frame["densities"] / mine.rho[ids] - 1.0).max() <= TOLERANCE
    tau = frame["mode_stress"].reshape(len(ids), 2, 2, 2)  # per mode, row-major
    scale = np.abs(mine.tau).max()
    assert np.abs(tau - mine.tau[ids]).max() <= TOLERANCE * scale
    # Not trivial: the stresses grew far beyond the tolerance and the modes differ.
    assert scale > 1e-4 and np.abs(mine.tau[:, 0] - mine.tau[:, 1]).max() > 0.1 * scale


def test_reference_mode_rate_matches_steady_simple_shear():
    """At the closed-form steady state of simple shear (f^3 - f^2 - 2 eps Wi^2 = 0), eq. R1 gives zero."""
    fluid = ref.PttFluid(rho0=1.0, c0=1.0, lambdas=(1.0,), etas=(2.0,), epsilon=0.1, eta_s=0.0, h=0.1, box=(1, 1))
    gamma_dot, eta, lam = 1.0, 2.0, 1.0
    f = np.roots([1.0, -1.0, 0.0, -2.0 * fluid.epsilon * (lam * gamma_dot) ** 2])
    f = float(np.real(f[np.isreal(f)][0]))
    assert abs(f - 1.150973) < 1e-6
    tau = np.array([[[[2 * eta * lam * gamma_dot ** 2 / f ** 2, eta * gamma_dot / f], [eta * gamma_dot / f, 0.0]]]])
    L = np.array([[[0.0, gamma_dot], [0.0, 0.0]]])
    assert np.abs(ref.ptt_mode_rates(L, tau, fluid)).max() < 1e-12
    assert np.abs(ref.ptt_mode_rates(np.swapaxes(L, 1, 2), tau, fluid)).max() > 0.1  # a transposed L is wrong


def test_the_mean_stress_subtraction_changes_only_the_momentum_equation():
    """tau_B is the volume mean of the extra stress; subtracting it changes the accelerations (a disordered box turns
    a uniform stress into forces), not the density or stress rates."""
    start, plain = _scene()
    _, subtracted = _scene(True)
    rng = np.random.default_rng(5)
    state = ref.rates(ref.PttState(**{**start.__dict__, "tau": rng.normal(0.0, 1.0, start.tau.shape)}), plain)
    vol = state.m / state.rho
    mean = ref.mean_extra_stress(state)
    assert np.allclose(mean, np.einsum("n,nij->ij", vol, state.tau.sum(axis=1) + state.tau_solvent) / vol.sum())
    a, b = ref.rates(state, plain), ref.rates(state, subtracted)
    assert np.array_equal(a.drho, b.drho) and np.array_equal(a.dtau, b.dtau)
    assert np.abs(a.acc - b.acc).max() > 1e-3 * np.abs(a.acc).max()
