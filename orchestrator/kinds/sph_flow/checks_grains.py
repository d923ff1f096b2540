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


#: The grain in shear is averaged over this last fraction of the run's series.
SHEAR_WINDOW = 0.5


def check_grain_in_shear(case, run) -> tuple[list[dict], dict]:
    """A neutrally buoyant grain in the steady Lees-Edwards cell (shear along x, gradient along y, u_x = gamma_dot
    (y - y_m) with y_m the particles' mean y at the start, where the box's zero momentum puts the still plane): at low Reynolds
    number a free sphere turns at omega_z = -gamma_dot / 2 (Jeffery 1922; the vorticity's half) and its centre moves
    with the fluid at its height, V_x = gamma_dot (Y - y_m) (the sheared periodic cell looks alike from every
    height). Both averaged over the last half of the run: rotation_rate (rad/s) and centre_velocity (m/s)."""
    name = case.case.name
    le = case.lees_edwards
    if len(case.grains) != 1 or le is None or le.shear_rate is None:
        raise OrchestratorError(f"{name}: check 'grain_in_shear' needs one grain in a steady Lees-Edwards cell "
                                "([lees_edwards] shear_rate)")
    grain, fluid = case.grains[0], one_material(case, "grain_in_shear")
    if abs(grain.density / fluid.rho0 - 1.0) > 1e-9:
        raise OrchestratorError(f"{name}: check 'grain_in_shear' needs a neutrally buoyant grain (grains[0].density "
                                f"= {grain.density:g}, the fluid's {fluid.rho0:g} kg/m^3)")
    frames = frames_of(run)
    if not frames:
        raise OrchestratorError(f"{name}: the run has no frame")
    series = run.get("series", {})
    time = np.asarray(series.get("time", []), dtype=float)
    if len(time) == 0:
        raise OrchestratorError(f"{name}: the run has no series")
    omega = np.asarray(series[f"grain_{grain.name}_angular_velocity"], dtype=float)
    velocity = np.asarray(series[f"grain_{grain.name}_velocity"], dtype=float)
    position = np.asarray(series[f"grain_{grain.name}_position"], dtype=float)
    window = time >= (1.0 - SHEAR_WINDOW) * time[-1]
    rate = float(le.shear_rate)
    y_m = float(np.asarray(frames[0][1]["positions"])[:, 1].mean())  # the lattice's particles: equal masses
    spin, spin_expected = float(omega[window, 2].mean()), -0.5 * rate
    v_x = float(velocity[window, 0].mean())
    v_expected = float(rate * (position[window, 1].mean() - y_m))
    mu = fluid.rho0 * fluid.viscosity
    reynolds = fluid.rho0 * abs(rate) * grain.radius**2 / mu
    off_axis = float(np.abs(omega[window, :2]).max() / abs(spin_expected))
    drift = float(np.abs(velocity[window, 1:]).max() / abs(v_expected)) if v_expected else math.nan
    tolerance = {q: tolerance_of(case, q) for q in ("rotation_rate", "centre_velocity")}
    common = f"averaged over the last {SHEAR_WINDOW:.0%} of the run; Re = rho gamma_dot a^2 / mu = {reynolds:.2g}"
    rows = [check_row(name, "rotation_rate", spin, spin_expected, relative(spin, spin_expected),
                      tolerance["rotation_rate"], source="free sphere in simple shear: omega = -gamma_dot / 2",
                      note=f"rotation_rate: omega_z, {common}; |omega_x|, |omega_y| up to {off_axis:.2g} of it"),
            check_row(name, "centre_velocity", v_x, v_expected, relative(v_x, v_expected),
                      tolerance["centre_velocity"], source="the fluid's velocity at the grain's height",
                      note=f"centre_velocity: V_x against gamma_dot (Y - y_m), Y = {position[window, 1].mean():.5g} m, "
                           f"y_m = {y_m:.5g} m; |V_y|, |V_z| up to {drift:.2g} of it; {common}")]
    if run["attrs"].get("status") != "ok":
        for row in rows:
            row["passed"] = False
    lines = [(time, omega[:, 2] / spin_expected, "-", "C0", "omega_z / (-gamma_dot/2)"),
             (time, velocity[:, 0] / v_expected if v_expected else time * 0.0, "-", "C1", "V_x / gamma_dot (Y - y_m)"),
             (time, np.ones(len(time)), "--", "k", "free sphere")]
    plot = {"title": f"{name}: grain in shear", "xlabel": "t (s)", "ylabel": "ratio to the closed form", "lines": lines}
    return rows, plot


def check_grain_collision(case, run) -> tuple[list[dict], dict]:
    """Two grains that collide (engine eq. G6, [grain_contact]): restitution, the relative speed along the line of
    their centres after the contact over the one before it, against the set coefficient; momentum_change, |P(end) -
    P(start)| of grains and fluid together over the grains' sum |M V| at the start (the fluid's particles each
    rho0 dx^3 on the lattice), expected 0 (its tolerance an absolute bound)."""
    name = case.case.name
    if len(case.grains) != 2 or case.grain_contact is None:
        raise OrchestratorError(f"{name}: check 'grain_collision' needs two grains and [grain_contact]")
    series = run.get("series", {})
    time = np.asarray(series.get("time", []), dtype=float)
    frames = frames_of(run)
    if len(time) < 2 or len(frames) < 2:
        raise OrchestratorError(f"{name}: the run has too few series samples or frames")
    a, b = case.grains
    x = [np.asarray(series[f"grain_{g.name}_position"], dtype=float) for g in (a, b)]
    v = [np.asarray(series[f"grain_{g.name}_velocity"], dtype=float) for g in (a, b)]
    line = np.asarray(b.centre, float) - np.asarray(a.centre, float)
    line /= np.linalg.norm(line)
    closing = (v[1] - v[0]) @ line
    gap = np.linalg.norm(x[1] - x[0], axis=1) - a.radius - b.radius
    touching = np.nonzero(gap < 0.0)[0]
    if not len(touching) or touching[-1] == len(time) - 1:
        raise OrchestratorError(f"{name}: the grains did not touch and part again within the run")
    before, after = float(closing[touching[0] - 1]), float(closing[-1])
    value, expected = -after / before, float(case.grain_contact.restitution)
    fluid = one_material(case, "grain_collision")
    volume = case.numerics.dx ** case.domain.dimension
    first = frames[0][1]
    body = np.asarray(first["positions"])[np.asarray(first["kind"]) == BODY]
    nearer_b = np.linalg.norm(body - x[1][0], axis=1) < np.linalg.norm(body - x[0][0], axis=1)
    masses = [g.density * volume * n for g, n in zip((a, b), (int((~nearer_b).sum()), int(nearer_b.sum())))]
    totals = []
    for t, frame in (frames[0], frames[-1]):
        kind = np.asarray(frame["kind"])
        p_fluid = fluid.rho0 * volume * np.asarray(frame["velocities"])[kind == 0].sum(axis=0)
        p_grains = sum(m * np.array([np.interp(t, time, vk[:, k]) for k in range(3)]) for m, vk in zip(masses, v))
        totals.append(p_fluid + p_grains)
    scale = sum(m * np.linalg.norm(vk[0]) for m, vk in zip(masses, v))
    drift = float(np.linalg.norm(totals[1] - totals[0]) / scale)
    rows = _contact_rows(case, value, "the contact law's coefficient (linear spring-dashpot)",
                         f"restitution: -(V_b - V_a) . n after / before the contact (closing at {before:.4g} m/s, "
                         f"parting at {after:.4g} m/s); closest gap {gap.min():.3g} m between the contact spheres",
                         "momentum_change", drift, "grains and fluid exchange equal and opposite forces",
                         "momentum_change: |P(end) - P(start)| / sum |M V| at the start, grains (rho_g N dx^3, as the "
                         "engine counts them) and fluid")
    return _contact_result(run, rows, f"{name}: grain collision", time, closing, "(V_b - V_a) . n", expected * before)



def check_grain_wall_bounce(case, run) -> tuple[list[dict], dict]:
    """One grain that bounces off the first wall plane of [grain_contact] (engine eq. G7): restitution, minus its
    velocity along the wall's normal at the end over the one at the start, against the set coefficient;
    tangential_change, the change of its velocity along the wall over its speed at the start, expected 0 (the contact
    is frictionless; its tolerance an absolute bound)."""
    name = case.case.name
    contact = case.grain_contact
    if len(case.grains) != 1 or contact is None or not contact.walls:
        raise OrchestratorError(f"{name}: check 'grain_wall_bounce' needs one grain and [[grain_contact.walls]]")
    series = run.get("series", {})
    time = np.asarray(series.get("time", []), dtype=float)
    if len(time) < 2:
        raise OrchestratorError(f"{name}: the run has too few series samples")
    grain, wall = case.grains[0], contact.walls[0]
    n = wall.unit_normal()
    x = np.asarray(series[f"grain_{grain.name}_position"], dtype=float)
    v = np.asarray(series[f"grain_{grain.name}_velocity"], dtype=float)
    distance = (x - np.asarray(wall.point)) @ n
    normal = v @ n
    if distance.min() >= grain.radius or normal[-1] <= 0.0:
        raise OrchestratorError(f"{name}: the grain did not touch the wall and leave it within the run")
    before, after = float(normal[0]), float(normal[-1])
    value, expected = -after / before, float(contact.restitution)
    tangential = v - normal[:, None] * n
    slide = float(np.linalg.norm(tangential[-1] - tangential[0]) / np.linalg.norm(v[0]))
    rows = _contact_rows(case, value, "the contact law's coefficient (linear spring-dashpot on a plane)",
                         f"restitution: -V . n after / before the contact ({before:.4g} m/s in, {after:.4g} m/s out); "
                         f"nearest centre {distance.min():.4g} m from the plane, contact radius {grain.radius:.4g} m",
                         "tangential_change", slide, "a frictionless contact leaves the velocity along the wall",
                         "tangential_change: |V_t(end) - V_t(start)| / |V(start)| (the light fluid's drag included)")
    return _contact_result(run, rows, f"{name}: grain on a wall", time, normal, "V . n", expected * before)


def _contact_rows(case, restitution, source, note, quantity, value, bound_source, bound_note) -> list[dict]:
    """A contact check's two rows: the restitution against [grain_contact]'s coefficient, and `quantity`, expected 0
    with its tolerance an absolute bound on `value`."""
    name, expected, bound = case.case.name, float(case.grain_contact.restitution), tolerance_of(case, quantity)
    return [check_row(name, "restitution", restitution, expected, relative(restitution, expected),
                      tolerance_of(case, "restitution"), source=source, note=note),
            check_row(name, quantity, value, 0.0, value, bound, passed=value <= (bound or 0.0), source=bound_source,
                      note=bound_note)]


def _contact_result(run, rows, title, time, speed, label, expected_before):
    """A contact check's rows (all failed unless the run's status is ok) and its plot: the normal speed (m/s) over
    time (s) against -e times the speed before (expected_before = e x before)."""
    if run["attrs"].get("status") != "ok":
        for row in rows:
            row["passed"] = False
    lines = [(time, speed, "-", "C0", label), (time, -expected_before + 0 * time, "--", "k", "-e x before")]
    return rows, {"title": title, "xlabel": "t (s)", "ylabel": "m/s", "lines": lines}
