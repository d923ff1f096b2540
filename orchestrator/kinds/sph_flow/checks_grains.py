"""The grains' verification checks: a sphere settling in a periodic box of viscous fluid against Stokes' drag with
Hasimoto's (1959) periodic-array factor (orchestrator/reference/settling.py). SI units."""

from __future__ import annotations

import math

import numpy as np

from orchestrator.errors import OrchestratorError
from orchestrator.kinds.sph_flow.checks_base import (
    check_row,
    frames_of,
    one_material,
    relative,
    tolerance_of,
)
from orchestrator.reference.settling import (
    hasimoto_factor,
    periodic_terminal_speed,
    solid_fraction,
)

#: The terminal speed is the mean over this last fraction of the run's series.
TERMINAL_WINDOW = 0.2
#: Particle kind of a grain's particles in run.h5's frames (engines/sph/src/physics_terms.h).
BODY = 4


def check_settling(case, run) -> tuple[list[dict], dict]:
    """The terminal superficial slip velocity of the one grain of a cubic periodic box ((1 - c) times its speed
    relative to the fluid's mean velocity) against Stokes with Hasimoto's factor at the lattice sphere's volume radius
    a = (3 N dx^3 / 4 pi)^(1/3), c = (4/3) pi a^3 / L^3."""
    name = case.case.name
    if len(case.grains) != 1 or not case.physics.balance_mean_weight:
        raise OrchestratorError(f"{name}: check 'settling' needs one grain and physics.balance_mean_weight")
    sides = {round(hi - lo, 12) for lo, hi in zip(case.domain.lo, case.domain.hi)}
    if len(sides) != 1 or sorted(case.domain.periodic) != [0, 1, 2]:
        raise OrchestratorError(f"{name}: check 'settling' needs a cubic box periodic along x, y and z")
    grain, fluid = case.grains[0], one_material(case, "settling")
    frames = frames_of(run)
    if not frames:
        raise OrchestratorError(f"{name}: the run has no frame")
    t_last, last = frames[-1]
    kind = np.asarray(last["kind"])
    dx, box = case.numerics.dx, sides.pop()
    n_grain, n_fluid = int((kind == BODY).sum()), int((kind == 0).sum())
    radius = (3.0 * n_grain * dx**3 / (4.0 * math.pi)) ** (1.0 / 3.0)
    g = np.asarray(case.physics.body_force, dtype=float)
    down = g / np.linalg.norm(g)
    mu = fluid.rho0 * fluid.viscosity
    expected = periodic_terminal_speed(grain.density, fluid.rho0, mu, float(np.linalg.norm(g)), radius, box)
    series = run.get("series", {})
    time = np.asarray(series.get("time", []), dtype=float)
    velocity = np.asarray(series.get(f"grain_{grain.name}_velocity", np.zeros((0, 3))), dtype=float)
    # The fluid moves up as the grain moves down (the box's momentum stays zero): the speed relative to the fluid's
    # mean velocity is V (1 + M_g / M_f), M_g = rho_g N dx^3, M_f = rho_f n_f dx^3.
    c = solid_fraction(radius, box)
    gain = (1.0 + grain.density * n_grain / (fluid.rho0 * n_fluid)) * (1.0 - c)
    window = time >= (1.0 - TERMINAL_WINDOW) * time[-1] if len(time) else np.zeros(0, bool)
    speeds = velocity[window] @ down * gain if window.any() else np.array([math.nan])
    value = float(speeds.mean())
    frame_fluid = np.asarray(last["velocities"])[kind == 0].mean(axis=0) @ down
    frame_grain = np.interp(t_last, time, velocity @ down) if len(time) else math.nan
    reynolds = fluid.rho0 * abs(value) * radius / mu
    rows = [check_row(name, "terminal_speed", value, expected, relative(value, expected),
                      tolerance_of(case, "terminal_speed"),
                      source="Stokes drag with Hasimoto (1959), simple cubic array",
                      note=f"terminal_speed: (1 - c) times the grain's speed along g relative to the fluid's mean, "
                           f"averaged over the last {TERMINAL_WINDOW:.0%} of the run (last frame: grain "
                           f"{frame_grain:.4g}, fluid {frame_fluid:.4g} m/s); "
                           f"a = {radius:.4g} m ({n_grain} particles), c = {c:.4f}, K = {hasimoto_factor(c):.4f}, "
                           f"Re = {reynolds:.2g}, spread over the window {np.ptp(speeds) / abs(expected):.2%}")]
    if run["attrs"].get("status") != "ok":
        rows[0]["passed"] = False
    lines = [(time, velocity @ down * gain if len(time) else time, "-", "C0", "SPH grain (relative)"),
             (time, np.full(len(time), expected), "--", "k", "Stokes x Hasimoto")]
    plot = {"title": f"{name}: settling sphere", "xlabel": "t (s)", "ylabel": "U (m/s)", "lines": lines}
    return rows, plot
