"""The sph executable's PTT fluid with a Cross-law solvent and a plateau modulus G_p against the numpy reference
(orchestrator.reference.sph_ptt): a tiny periodic 2D scene (deck and particle file written here) runs 20 steps in
both; positions, velocities, densities and the stress columns (the modes and the plateau's) agree to 1e-9. The
Cross law is exercised where it thins (K gamma_dot of order 1) and the plateau stress grows well above the
tolerance. Also the deck's refusals of bad Cross and plateau values (one error line naming the key).
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
CROSS = (0.004, 0.0005, 0.5, 0.7)  # eta_0 Pa s, eta_inf Pa s, K s, m -
PLATEAU = 0.05  # G_p, Pa
EXECUTABLE = Path(os.environ.get("ORCHESTRATOR_SPH") or REPO / "engines/sph/build/sph")


def _scene() -> tuple[ref.PttState, ref.PttFluid]:
    rng = np.random.default_rng(7)
    dx = LENGTH / N
    a, b = np.meshgrid(np.arange(N), np.arange(N), indexing="ij")
    x = np.stack([a.ravel() + 0.5, b.ravel() + 0.5], axis=1) * dx + rng.uniform(-0.1, 0.1, (N * N, 2)) * dx
    v = rng.uniform(-0.2, 0.2, (N * N, 2))  # m/s
    rho = 1.0 + rng.uniform(-0.005, 0.005, N * N)
    fluid = ref.PttFluid(rho0=1.0, c0=5.0, lambdas=(0.05, 0.01), etas=(0.01, 0.004), epsilon=0.3, eta_s=0.001,
                         h=1.3 * dx, box=(LENGTH, LENGTH), plateau=PLATEAU, cross=CROSS)
    state = ref.PttState(x=x, v=v, m=np.full(N * N, dx * dx), rho=rho, tau=np.zeros((N * N, 3, 2, 2)),
                         tau_solvent=np.zeros((N * N, 2, 2)))
    return state, fluid


def _material(fluid: ref.PttFluid) -> dict:
    eta_0, eta_inf, time, exponent = fluid.cross
    return {"name": "melt", "model": "ptt", "rho0": fluid.rho0, "c0": fluid.c0, "epsilon": fluid.epsilon,
            "solvent_viscosity": fluid.eta_s, "storage_plateau": fluid.plateau,
            "cross_viscosity": {"eta_0": eta_0, "eta_inf": eta_inf, "time_constant": time, "exponent": exponent},
            "modes": [{"lambda": lam, "eta": eta} for lam, eta in zip(fluid.lambdas, fluid.etas)]}


def _write(state: ref.PttState, material: dict, workdir: Path) -> None:
    import h5py

    with h5py.File(workdir / "particles.h5", "w") as f:
        f["positions"], f["velocities"], f["masses"], f["densities"] = state.x, state.v, state.m, state.rho
        f["kind"] = np.zeros(len(state.x), dtype=np.int8)
    deck = {"dimension": 2, "particles_file": "particles.h5", "physics": [], "v_max": 0.4, "h": 1.3 * LENGTH / N,
            "dx": LENGTH / N, "periodic": {"axes": [0, 1], "lo": [0, 0], "hi": [LENGTH, LENGTH]},
            "materials": [material], "dt": DT, "t_end": STEPS * DT, "threads": 1,
            "output": {"file": "out.h5", "frame_interval": STEPS * DT, "progress_interval": 100}}
    (workdir / "deck.json").write_text(json.dumps(deck))


def _run(workdir: Path) -> subprocess.CompletedProcess:
    return subprocess.run([str(EXECUTABLE), "deck.json"], cwd=workdir, capture_output=True, text=True, timeout=120)


needs_executable = pytest.mark.skipif(not EXECUTABLE.exists(), reason=f"{EXECUTABLE} is not built")


@pytest.mark.sph
@needs_executable
def test_executable_cross_and_plateau_agree_with_the_reference(tmp_path):
    import h5py

    start, fluid = _scene()
    _write(start, _material(fluid), tmp_path)
    done = _run(tmp_path)
    assert done.returncode == 0, done.stderr
    with h5py.File(tmp_path / "out.h5", "r") as h5:
        last = h5["frames"][str(len(h5["frames"]) - 1)]
        assert int(last.attrs["step"]) == STEPS
        frame = {key: last[key][()] for key in ("ids", "positions", "velocities", "densities", "mode_stress")}
    mine = ref.simulate(start, fluid, DT, STEPS)
    ids = frame["ids"]
    box = np.asarray(fluid.box)
    dx = frame["positions"] - mine.x[ids]
    dx -= box * np.round(dx / box)  # the executable wraps positions into the box
    assert np.abs(dx).max() <= TOLERANCE * np.abs(mine.x - start.x).max()
    assert np.abs(frame["velocities"] - mine.v[ids]).max() <= TOLERANCE * np.abs(mine.v).max()
    assert np.abs(frame["densities"] / mine.rho[ids] - 1.0).max() <= TOLERANCE
    tau = frame["mode_stress"].reshape(len(ids), 3, 2, 2)  # two modes and the plateau, row-major
    scale = np.abs(mine.tau).max()
    assert np.abs(tau - mine.tau[ids]).max() <= TOLERANCE * scale
    # Not trivial: the plateau's stress is far above the tolerance, and the Cross law thins over the scene's rates.
    assert np.abs(mine.tau[:, 2]).max() > 1e-3 * scale > 1e-7
    newtonian = ref.simulate(start, replace(fluid, cross=None, eta_s=fluid.eta_s + CROSS[0]), DT, STEPS)
    thinning = np.abs(mine.tau_solvent).max() / np.abs(newtonian.tau_solvent).max()
    assert thinning < 0.9


def test_reference_solvent_follows_the_cross_law_in_simple_shear():
    """L = [[0, g], [0, 0]]: gamma_dot = |g| and tau_xy = (eta_s + eta_C(|g|)) g, at rates across the thinning."""
    fluid = ref.PttFluid(rho0=1.0, c0=1.0, lambdas=(1.0,), etas=(1.0,), epsilon=0.0, eta_s=0.1, h=0.1, box=(1, 1),
                         cross=(10.0, 1.0, 2.0, 0.6))
    g = np.array([-3.0, 0.01, 0.5, 40.0])
    L = np.zeros((len(g), 2, 2))
    L[:, 0, 1] = g
    tau = ref.solvent_stress(L, fluid)
    eta_c = 1.0 + 9.0 / (1.0 + (2.0 * np.abs(g)) ** 0.6)
    assert np.allclose(tau[:, 0, 1], (0.1 + eta_c) * g, rtol=1e-14, atol=0.0)
    assert np.abs(tau[:, 0, 0]).max() == 0.0 and np.abs(tau[:, 1, 1]).max() == 0.0
    assert eta_c[1] > 9.0 and eta_c[3] < 2.0  # the rates span the law


def test_reference_plateau_is_an_upper_convected_elastic_stress():
    """Eq. R2 integrated along simple shear of strain gamma gives G_p (B - I): tau_xy = G_p gamma, N1 = G_p gamma^2,
    tau_yy = 0 (a neo-Hookean solid); the modes' columns are untouched by it."""
    fluid = ref.PttFluid(rho0=1.0, c0=1.0, lambdas=(1.0,), etas=(1.0,), epsilon=0.0, eta_s=0.0, h=0.1, box=(1, 1),
                         plateau=3.0)
    rate, steps, dt = 2.0, 4000, 1e-4  # gamma = 0.8
    L = np.array([[[0.0, rate], [0.0, 0.0]]])
    tau = np.zeros((1, 2, 2, 2))
    for _ in range(steps):  # midpoint rule: second order
        half = tau + 0.5 * dt * ref.ptt_mode_rates(L, tau, fluid)
        tau = tau + dt * ref.ptt_mode_rates(L, half, fluid)
    gamma = rate * steps * dt
    plateau = tau[0, 1]
    assert plateau[0, 1] == pytest.approx(3.0 * gamma, rel=1e-12)
    assert plateau[0, 0] - plateau[1, 1] == pytest.approx(3.0 * gamma ** 2, rel=1e-6)
    assert abs(plateau[1, 1]) < 1e-12


@needs_executable
@pytest.mark.parametrize("change, key", [
    ({"cross_viscosity": {"eta_0": 1.0, "eta_inf": 2.0, "time_constant": 1.0, "exponent": 0.5}}, "eta_inf"),
    ({"cross_viscosity": {"eta_0": 1.0, "eta_inf": 0.1, "time_constant": 1.0, "exponent": 1.5}}, "exponent"),
    ({"cross_viscosity": {"eta_0": 1.0, "eta_inf": 0.1, "time_constant": 1.0, "exponent": 0.0}}, "exponent"),
    ({"cross_viscosity": {"eta_0": 1.0, "eta_inf": 0.1, "time_constant": 0.0, "exponent": 0.5}}, "time_constant"),
    ({"cross_viscosity": {"eta_0": 1.0, "eta_inf": 0.1, "time_constant": 1.0}}, "exponent"),
    ({"storage_plateau": -1.0}, "storage_plateau"),
    ({"storage_plateau": 1.0, "modes": [{"lambda": 1.0, "eta": 1.0}] * 8}, "modes"),
])
def test_bad_cross_and_plateau_values_are_refused_naming_the_key(tmp_path, change, key):
    start, fluid = _scene()
    _write(start, {**_material(fluid), **change}, tmp_path)
    done = _run(tmp_path)
    assert done.returncode != 0
    lines = [line for line in done.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error:") and key in lines[0], done.stderr
