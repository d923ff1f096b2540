"""The SPH verification checks of two immiscible layers ([[materials]] scenes): the steady two-layer
Poiseuille and Couette profiles (orchestrator.reference.sph_flows) against the particles of the last frame.

A scene has two fluid blocks stacked along y between boundary blocks, periodic along x, each fluid block of
its own material; the lower block's top is the interface. rel_error is the largest |u - u_exact| over the
fluid particles divided by the steady peak speed (Poiseuille) or the plate speed (Couette).
"""

from __future__ import annotations

import numpy as np

from orchestrator.errors import OrchestratorError
from orchestrator.kinds.sph_flow.case_materials import block_materials, run_materials
from orchestrator.kinds.sph_flow.checks_base import body_force_of, check_row, fluid_mask, frames_of, tolerance_of
from orchestrator.reference.sph_flows import two_layer_couette_velocity, two_layer_poiseuille_velocity


def _layers(case):
    """(y0 m, h1 m, L m, lower material, upper material) of a two-layer scene."""
    fluid = [(b, k) for b, k in zip(case.blocks, block_materials(case)) if b.kind == "fluid"]
    if len(fluid) != 2 or fluid[0][1] == fluid[1][1]:
        raise OrchestratorError(f"{case.case.name}: a two-layer scene needs two fluid blocks of different "
                                f"materials; found {len(fluid)} fluid blocks")
    (lower, k1), (upper, k2) = sorted(fluid, key=lambda item: item[0].lo[1])
    materials = run_materials(case)
    y0 = lower.lo[1]
    return y0, lower.hi[1] - y0, upper.hi[1] - y0, materials[k1], materials[k2]


def check_two_layer_poiseuille(case, run) -> tuple[list[dict], dict]:
    """Steady two-layer Poiseuille profile (body force along x, plates at rest) against the particles."""
    y0, h1, gap, m1, m2 = _layers(case)
    force = float(body_force_of(case)[0])

    def exact(y):
        return two_layer_poiseuille_velocity(y, h1, gap, m1.rho0, m2.rho0, m1.mu, m2.mu, force)

    peak = float(np.max(exact(np.linspace(0.0, gap, 2001))))
    return _profile_rows(case, run, y0, h1, gap, peak, exact, "two_layer_poiseuille",
                         "steady two-layer Poiseuille (continuous u and shear stress at the interface)")


def check_two_layer_couette(case, run) -> tuple[list[dict], dict]:
    """Steady two-layer Couette profile (upper plate moving along x) against the particles."""
    y0, h1, gap, m1, m2 = _layers(case)
    moving = [b for b in case.blocks if b.kind == "boundary" and b.velocity is not None and any(b.velocity)]
    if len(moving) != 1:
        raise OrchestratorError(f"{case.case.name}: a Couette scene needs exactly one moving boundary block "
                                f"(the upper plate); found {len(moving)}")
    speed = float(moving[0].velocity[0])

    def exact(y):
        return two_layer_couette_velocity(y, h1, gap, m1.mu, m2.mu, speed)

    return _profile_rows(case, run, y0, h1, gap, abs(speed), exact, "two_layer_couette",
                         "steady two-layer Couette (one shear stress across both layers)")


def _profile_rows(case, run, y0, h1, gap, peak, exact, check, source):
    name = case.case.name
    frames = frames_of(run)
    tolerance = tolerance_of(case, "u_profile")
    if not frames:
        return [check_row(name, "u_profile", None, None, None, tolerance, passed=False,
                          note="no frames recorded")], {"title": name, "xlabel": "u", "ylabel": "y", "lines": []}
    t, frame = frames[-1]
    fluid = fluid_mask(frame)
    y = np.asarray(frame["positions"])[fluid, 1] - y0
    u = np.asarray(frame["velocities"])[fluid, 0]
    u_exact = exact(y)
    linf = float(np.max(np.abs(u - u_exact))) / peak
    near = np.abs(y - h1) <= np.min(np.abs(y - h1)) + 1e-9 * gap  # the rows next to the interface
    rows = [check_row(name, f"u_profile(t={t:.3g} s)", np.mean(u[near]), np.mean(u_exact[near]), linf, tolerance,
                      source=source,
                      note=f"u_profile: value, expected = speed of the particle rows next to the interface "
                           f"(y = {h1:.4g} m); rel_error = max over the profile of |u - u_steady| / "
                           f"{peak:.3g} m/s ({'the steady peak' if check == 'two_layer_poiseuille' else 'v0'})")]
    y_line = np.linspace(0.0, gap, 201)
    lines = [(u / peak, y / gap, ".", "C0", f"SPH, t = {t:.3g} s"),
             (exact(y_line) / peak, y_line / gap, "-", "k", "steady two-layer profile"),
             ([0.0, 1.0], [h1 / gap, h1 / gap], ":", "0.5", "interface")]
    plot = {"title": f"{name}: u/u_peak", "xlabel": "u / u_peak", "ylabel": "y / L", "lines": lines}
    return rows, plot
