"""The SPH verification checks: each scene of cases/verification/sph_*.toml against its closed form, series
solution or measurement, computed from its run.h5 (frames, probe and wall-force series) and the case itself.

A scene's [[expected]] rows choose the comparisons (CHECKS) and give each quantity its tolerance. Rows have the keys of `verify dem`
(verify.ROW_KEYS); rel_error is |value - expected| / |expected| unless the row's note names another scale
(profiles: the largest deviation over the profile divided by the steady peak speed; the surge front: the largest
deviation over the measured points divided by the measured Z). Each check also returns what to plot.
"""

from __future__ import annotations

import math

import numpy as np

from orchestrator.errors import OrchestratorError
from orchestrator.kinds.sph_flow.checks_base import (
    FRONT_DATASETS,
    PRESSURE_AVERAGE_S,
    PROFILE_TIMES,
    base_quantity,
    block_of,
    body_force_of,
    check_row,
    fluid_mask,
    frame_at,
    frames_of,
    one_material,
    relative,
    tolerance_of,
)
from orchestrator.kinds.sph_flow.checks_grains import (
    check_grain_collision,
    check_grain_in_shear,
    check_grain_wall_bounce,
    check_settling,
)
from orchestrator.kinds.sph_flow.checks_layers import check_two_layer_couette, check_two_layer_poiseuille
from orchestrator.kinds.sph_flow.checks_open import check_annulus_laminar, check_hagen_poiseuille
from orchestrator.kinds.sph_flow.checks_orifice import check_slot_orifice
from orchestrator.kinds.sph_flow.checks_solids import check_solid_under_water
from orchestrator.kinds.sph_flow.checks_viscoelastic import check_oldroyd_b_startup
from orchestrator.kinds.sph_flow.checks_walls import check_penalty_column, check_penalty_incline
from orchestrator.reference.dam_break_data import SURGE_FRONT_DATA, dimensionless_front, dimensionless_time
from orchestrator.reference.sph_flows import (
    couette_velocity,
    hydrostatic_pressure,
    poiseuille_steady_velocity,
    poiseuille_velocity,
)


# ------------------------------------------------------------------------------------------- channel flows
def check_poiseuille(case, run) -> tuple[list[dict], dict]:
    """Start-up Poiseuille profiles u(y, t) against the series (Morris et al. 1997, eq. 21); the flow along x, across
    the plates along y (2D) or along the one axis of a 3D box that is not periodic (z between a channel's walls)."""

    fluid = block_of(case, "fluid")
    nu = one_material(case, "poiseuille_series").viscosity
    axis = _wall_normal_axis(case)
    gap, force = fluid.hi[axis] - fluid.lo[axis], body_force_of(case)[0]
    peak = float(poiseuille_steady_velocity(gap / 2, gap, nu, force))
    return _channel_rows(case, run, fluid.lo[axis], gap, peak,
                         lambda y, t: poiseuille_velocity(y, t, gap, nu, force),
                         "Morris et al. 1997 eq. 21 (start-up Poiseuille series)", axis)


def _wall_normal_axis(case) -> int:
    """The axis across a channel's plates: y in 2D; in 3D the one axis that is not periodic."""
    if case.domain.dimension == 2:
        return 1
    open_axes = [d for d in range(3) if d not in case.domain.periodic]
    if len(open_axes) != 1:
        raise OrchestratorError(f"{case.case.name}: a 3D channel check needs exactly one axis that is not periodic "
                                f"(the plates' normal); domain.periodic = {list(case.domain.periodic)}")
    return open_axes[0]


def check_couette(case, run) -> tuple[list[dict], dict]:
    """Start-up Couette profiles u(y, t) against the series (Morris et al. 1997, eq. 22)."""

    fluid = block_of(case, "fluid")
    gap, nu = fluid.hi[1] - fluid.lo[1], one_material(case, "couette_series").viscosity
    moving = [b for b in case.blocks if b.kind == "boundary" and b.velocity is not None and any(b.velocity)]
    if len(moving) != 1:
        raise OrchestratorError(f"{case.case.name}: a Couette scene needs exactly one moving boundary block "
                                f"(the upper plate); found {len(moving)}")
    speed = float(moving[0].velocity[0])
    return _channel_rows(case, run, fluid.lo[1], gap, speed,
                         lambda y, t: couette_velocity(y, t, gap, nu, speed),
                         "Morris et al. 1997 eq. 22 (start-up Couette series)")


def _channel_rows(case, run, y0, gap, peak, exact, source, axis=1):
    frames = frames_of(run)
    name = case.case.name
    t_end = case.simulation.duration
    rows, lines = [], []
    times = [t for t in PROFILE_TIMES if t < t_end] + [t_end]
    y_line = np.linspace(0.0, gap, 101)
    for k, t_want in enumerate(times):
        t, frame = frame_at(frames, t_want)
        fluid = fluid_mask(frame)
        y = np.asarray(frame["positions"])[fluid, axis] - y0
        u = np.asarray(frame["velocities"])[fluid, 0]
        u_exact = exact(y, t)
        linf = float(np.max(np.abs(u - u_exact))) / abs(peak)
        mid = np.abs(y - gap / 2) <= np.min(np.abs(y - gap / 2)) + 1e-12 * gap
        label = "steady" if t_want == t_end else "start-up"
        rows.append(check_row(name, f"u_profile(t={t:.3g} s)", np.mean(u[mid]), np.mean(u_exact[mid]), linf,
                         tolerance_of(case, "u_profile"), source=source,
                         note=f"u_profile: value, expected = mid-gap speed; rel_error = max over the profile of "
                              f"|u - u_series| / {abs(peak):.3g} m/s (the steady peak)"))
        colour = f"C{k}"
        lines.append((y / gap, u / peak, ".", colour, None))
        lines.append((y_line / gap, exact(y_line, t) / peak, "-", colour, f"t = {t:.3g} s ({label})"))
    if not times or not frames:
        rows.append(check_row(name, "u_profile", None, None, None, tolerance_of(case, "u_profile"), passed=False,
                         note="no frames recorded"))
    plot = {"title": f"{name}: u/u_peak (dots SPH, lines series)", "xlabel": "y / L", "ylabel": "u / u_peak",
            "lines": lines}
    return rows, plot


# ---------------------------------------------------------------------------------------------- hydrostatic
def check_hydrostatic(case, run) -> tuple[list[dict], dict]:
    """Tank at rest: pressure against rho g (H - y), spurious speeds, and the run reaching its end."""

    name = case.case.name
    water = block_of(case, "fluid")
    g = float(np.linalg.norm(body_force_of(case)))
    rho0, y0 = one_material(case, "hydrostatic").rho0, water.lo[1]
    depth = (water.hydrostatic_surface if water.hydrostatic_surface is not None else water.hi[1]) - y0
    scale = rho0 * g * depth
    source = "hydrostatic rho g (H - y)"
    rows = []
    series = run.get("series", {})
    time = np.asarray(series.get("time", []))
    probes = [p for p in case.output.probes if f"pressure_probe_{p.name}" in series]
    lines = []
    if probes and len(time):
        late = time >= time[-1] - PRESSURE_AVERAGE_S
        heights = np.array([p.point[1] - y0 for p in probes])
        measured = np.array([np.nanmean(np.asarray(series[f"pressure_probe_{p.name}"])[late]) for p in probes])
        expected = hydrostatic_pressure(heights, depth, rho0, g)
        l1 = float(np.mean(np.abs(measured - expected))) / scale
        deepest = int(np.argmin(heights))
        rows.append(check_row(name, "pressure_profile", measured[deepest], expected[deepest], l1, tolerance_of(case, "pressure_profile"),
                         source=source,
                         note=f"pressure_profile: {len(probes)} probes on a vertical line, averaged over the last "
                              f"{PRESSURE_AVERAGE_S:g} s; value, expected at the deepest; rel_error = mean "
                              f"|p - rho g (H - y)| / (rho g H = {scale:.4g} Pa)"))
        lines.append((measured / scale, heights / depth, "s", "C1", "probes (kernel-interpolated)"))
    else:
        rows.append(check_row(name, "pressure_profile", None, None, None, tolerance_of(case, "pressure_profile"), passed=False,
                         note="pressure_profile: the case has no pressure probes, or they recorded nothing"))
    frames = frames_of(run)
    if frames:
        t, frame = frames[-1]
        fluid = fluid_mask(frame)
        y = np.asarray(frame["positions"])[fluid, 1] - y0
        p = np.asarray(frame["pressures"])[fluid]
        exact = hydrostatic_pressure(y, depth, rho0, g)
        l1 = float(np.mean(np.abs(p - exact))) / scale
        bottom = y <= y.min() + 0.5 * case.numerics.dx
        rows.append(check_row(name, "particle_pressure", np.mean(p[bottom]), np.mean(exact[bottom]), l1,
                         tolerance_of(case, "particle_pressure"), source=source,
                         note=f"particle_pressure: every fluid particle's own pressure at t = {t:.3g} s; value, "
                              "expected: mean of the bottom row; rel_error = mean |p - rho g (H - y)| / (rho g H); "
                              "weakly compressible SPH without density diffusion carries a few % of particle-level "
                              "noise, hence the wider tolerance"))
        speed = float(np.max(np.linalg.norm(np.asarray(frame["velocities"])[fluid], axis=1)))
        rows.append(check_row(name, "spurious_speed", speed, 0.0, speed / math.sqrt(g * depth), tolerance_of(case, "spurious_speed"),
                         source="at rest",
                         note=f"spurious_speed: fastest fluid particle at t = {t:.3g} s; rel_error = value / "
                              f"sqrt(g H) = {math.sqrt(g * depth):.3g} m/s"))
        lines.insert(0, (p / scale, y / depth, ".", "C0", f"particles, t = {t:.3g} s"))
    y_line = np.linspace(0.0, depth, 50)
    lines.append((hydrostatic_pressure(y_line, depth, rho0, g) / scale, y_line / depth, "-", "k", "rho g (H - y)"))
    reached = float(run["attrs"].get("simulated_time", 0.0))
    limit = tolerance_of(case, "simulated_time")
    rows.append(check_row(name, "simulated_time", reached, case.simulation.duration,
                     relative(reached, case.simulation.duration), limit, source="case simulation.duration",
                     passed=run["attrs"].get("status") == "ok" and limit is not None and
                     relative(reached, case.simulation.duration) <= limit,
                     note="simulated_time: stable to the end of the run (status ok)"))
    plot = {"title": f"{name}: pressure", "xlabel": "p / (rho g H)", "ylabel": "y / H", "lines": lines}
    return rows, plot


# ------------------------------------------------------------------------------------------------ dam break
def check_dam_break(case, run) -> tuple[list[dict], dict]:
    """Surge front Z = x/a against T = t sqrt(2 g / a), compared with the measured series."""

    name = case.case.name
    column = block_of(case, "fluid")
    a = column.hi[0] - column.lo[0]
    g = float(np.linalg.norm(body_force_of(case)))
    frames = frames_of(run)
    t = np.array([time for time, _ in frames])
    front = np.array([np.asarray(f["positions"])[fluid_mask(f), 0].max() for _, f in frames]) - column.lo[0]
    T = dimensionless_time(t, a, g)
    Z = dimensionless_front(front + 0.5 * case.numerics.dx, a)  # the particle's own extent: Z(0) = 1
    wall = min(b.lo[0] for b in case.blocks if b.kind == "boundary" and b.lo[0] > column.hi[0]) - column.lo[0]
    lines = [(T, Z, "-", "k", "SPH front")]
    rows = []
    for k, (key, data) in enumerate(SURGE_FRONT_DATA.items()):
        Te, Ze = np.asarray(data.T), np.asarray(data.Z)
        inside = (Te > 0) & (Te <= T[-1]) & (Ze < wall / a) if len(T) else np.zeros(len(Te), bool)
        shown = Te <= (T[-1] if len(T) else 0.0) + 0.3
        lines.append((Te[shown], Ze[shown], "os^v"[k % 4], f"C{k}", f"{data.name}"))
        if key not in FRONT_DATASETS:
            continue
        if not inside.any():
            rows.append(check_row(name, f"surge_front_Z[{data.name}]", None, None, None, tolerance_of(case, "surge_front_Z"), passed=False,
                             note="surge_front_Z: the run ended before the first measured point"))
            continue
        simulated = np.interp(Te[inside], T, Z)
        errors = np.abs(simulated - Ze[inside]) / Ze[inside]
        worst = int(np.argmax(errors))
        rows.append(check_row(name, f"surge_front_Z[{data.name}]", simulated[-1], Ze[inside][-1], float(errors[worst]),
                         tolerance_of(case, "surge_front_Z"), source=f"{data.experiment}; digitised by {data.digitised_by}",
                         note=f"surge_front_Z: value, expected at the last measured T; rel_error = max over "
                              f"{int(inside.sum())} points of |Z - Z_exp| / Z_exp (worst at T = "
                              f"{Te[inside][worst]:.3g}); front = rightmost fluid particle + dx/2, "
                              "T = t sqrt(2 g / a)"))
    if run["attrs"].get("status") != "ok":
        for row in rows:
            row["passed"] = False
    plot = {"title": f"{name}: surge front", "xlabel": "T = t sqrt(2g/a)", "ylabel": "Z = x / a", "lines": lines}
    return rows, plot


#: The comparisons a scene's [[expected]] rows name (case_parts.CHECK_QUANTITIES lists what each measures).
CHECKS = {
    "poiseuille_series": check_poiseuille,
    "couette_series": check_couette,
    "hydrostatic": check_hydrostatic,
    "surge_front": check_dam_break,
    "penalty_column": check_penalty_column,
    "penalty_incline": check_penalty_incline,
    "two_layer_poiseuille": check_two_layer_poiseuille,
    "two_layer_couette": check_two_layer_couette,
    "hagen_poiseuille": check_hagen_poiseuille,
    "annulus_laminar": check_annulus_laminar,
    "oldroyd_b_startup": check_oldroyd_b_startup,
    "settling": check_settling,
    "grain_in_shear": check_grain_in_shear,
    "grain_collision": check_grain_collision,
    "grain_wall_bounce": check_grain_wall_bounce,
    "solid_under_water": check_solid_under_water,
    "slot_orifice": check_slot_orifice,
}


def evaluate(case, run) -> tuple[list[dict], list[dict]]:
    """The check rows and plots of the comparisons the scene's [[expected]] rows name, with their tolerances; only
    the quantities the rows list. OrchestratorError for a scene without [[expected]] rows."""
    if not case.expected:
        raise OrchestratorError(f"{case.case.name} has no [[expected]] rows: nothing to check; add rows such as "
                                '[[expected]] check = "poiseuille_series", quantity = "u_profile", tolerance = 0.02')
    rows, plots = [], []
    for check in dict.fromkeys(row.check for row in case.expected):
        listed = {row.quantity for row in case.expected if row.check == check}
        measured, plot = CHECKS[check](case, run)
        rows += [row for row in measured if base_quantity(row["quantity"]) in listed]
        plots.append(plot)
    return rows, plots


def check_run(case, engine: str, run: dict) -> tuple[list[dict], dict]:
    """The sph_flow kind's part of `verify sph`: the scene's check rows and its first panel (title, xlabel, ylabel,
    lines) for the suite's picture (pictures.plot_scenes)."""
    rows, plots = evaluate(case, run)
    return rows, plots[0]
