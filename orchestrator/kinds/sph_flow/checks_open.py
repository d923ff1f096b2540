"""SPH verification of open boundaries in 3D: laminar flow through a circular pipe (Hagen-Poiseuille) and a concentric
annulus, fed by the first inlet (a disc, with a parabolic or annular profile) and drained by the first outlet.

Over the second half of the run (the steady state) and the middle half of the length (away from the buffers):
- u_profile: the axial speed averaged in radial bins of dx/2 against the exact laminar profile (averaged over the
  same particles)
  u(r) = G / (4 mu) [R^2 - r^2 + (R^2 - Ri^2) ln(r/R) / ln(R/Ri)] (Ri = 0: Hagen-Poiseuille, G = -dp/dx) for the
  measured flow rate Q, G = Q / q(1) with q(1) the flow per unit pressure gradient of
  reference.hydraulics.annulus_laminar_flow; rel_error = largest bin deviation / the exact peak speed;
- pressure_gradient: G from a least-squares line p(x) through the fluid particles' pressures, against Q / q(1);
- mass_balance: (V_in - V_out - dM / rho0) / V_in with V_in, V_out the inflow and outflow volumes (m / rho0 per
  particle) and dM the change of the fluid's mass between the first and last frame of the window;
- density_drift: the change of the fluid's mean density over the window / rho0 (a reference pressure at the outlet
  keeps it near zero).
"""

from __future__ import annotations

import math

import numpy as np

from orchestrator.errors import OrchestratorError
from orchestrator.kinds.sph_flow.checks_base import (
    check_row,
    fluid_mask,
    frames_of,
    relative,
    tolerance_of,
)
from orchestrator.reference.hydraulics import annulus_laminar_flow

SOURCE = {0: "Hagen-Poiseuille (White, Viscous Fluid Flow, eq. 3-34)",
          1: "laminar annulus (White, Viscous Fluid Flow, eqs. 3-48, 3-49)"}


def annulus_velocity(r, gradient, r_outer, r_inner, mu):
    """Exact laminar axial speed, m/s, at radius r (m) in a concentric annulus (r_inner = 0: a pipe) driven by the
    pressure gradient G = -dp/dx (Pa/m); mu in Pa s."""
    r = np.asarray(r, dtype=float)
    shape = r_outer**2 - r**2
    if r_inner > 0.0:
        shape = shape + (r_outer**2 - r_inner**2) * np.log(r / r_outer) / math.log(r_outer / r_inner)
    return gradient / (4.0 * mu) * shape


def check_hagen_poiseuille(case, run) -> tuple[list[dict], dict]:
    """The pipe: profile, pressure gradient, mass balance and density drift (see the module docstring)."""
    return _open_rows(case, run)


def check_annulus_laminar(case, run) -> tuple[list[dict], dict]:
    """The annulus: profile, pressure gradient, mass balance and density drift (see the module docstring)."""
    return _open_rows(case, run)


def _open_rows(case, run):
    name = case.case.name
    if not case.inlets or not case.outlets or case.inlets[0].radius is None:
        raise OrchestratorError(f"{name}: an open-boundary check needs a disc inlet and an outlet")
    inlet, outlet = case.inlets[0], case.outlets[0]
    r_outer, r_inner = float(inlet.radius), float(inlet.inner_radius or 0.0)
    mu = case.fluid.density * case.fluid.viscosity
    axis = np.asarray(inlet.normal, dtype=float) / np.linalg.norm(inlet.normal)
    origin = np.asarray(inlet.center, dtype=float)
    length = float(np.dot(np.asarray(outlet.center, dtype=float) - origin, axis))
    source = SOURCE[r_inner > 0.0]
    t_end = case.simulation.duration
    window = [(t, f) for t, f in frames_of(run) if t >= 0.5 * t_end - 1e-9]
    if len(window) < 2:
        return [check_row(name, q, None, None, None, tolerance_of(case, q), passed=False, note="fewer than two "
                          "frames in the second half") for q in ("u_profile", "pressure_gradient")], {}
    t0, t1 = window[0][0], window[-1][0]
    v_in, v_out = _window_volumes(run.get("series", {}), t0, t1, inlet.name, outlet.name)
    flow = v_in / (t1 - t0)
    q_unit = annulus_laminar_flow(1.0, 1.0, r_outer, r_inner, mu)  # m^3/s per Pa/m
    gradient_exact = flow / q_unit
    s, r, u, p, counts, mean_rho = _middle_fluid(window, origin, axis, length)
    gradient = -float(np.polyfit(s, p, 1)[0])
    dx = case.numerics.dx
    u_particle = annulus_velocity(r, gradient_exact, r_outer, r_inner, mu)  # binned like u: no bin-width bias
    r_bin, u_bin, u_exact = _radial_bins(r, u, u_particle, np.arange(r_inner, r_outer + 1e-12 * r_outer, 0.5 * dx))
    r_line = np.linspace(max(r_inner, 1e-9 * r_outer), r_outer, 200)
    peak = float(np.max(annulus_velocity(r_line, gradient_exact, r_outer, r_inner, mu)))
    worst = float(np.max(np.abs(u_bin - u_exact))) / peak
    at_peak = int(np.argmax(u_exact))
    mass_in_volumes = (counts[-1] - counts[0]) * dx**3  # every fluid particle has mass rho0 dx^3
    imbalance = (v_in - v_out - mass_in_volumes) / v_in
    drift = (mean_rho[-1] - mean_rho[0]) / case.fluid.density
    through = length / (flow / (math.pi * (r_outer**2 - r_inner**2)))
    window_note = f"over t = {t0:.3g}..{t1:.3g} s ({(t1 - t0) / through:.2f} flow-through times), Q = {flow:.4g} m^3/s"
    rows = [
        check_row(name, "u_profile", u_bin[at_peak], u_exact[at_peak], worst, tolerance_of(case, "u_profile"),
                  source=source, note=f"u_profile: value, expected = speed in the bin of the exact peak; rel_error = "
                                      f"max over {len(r_bin)} radial bins of |u - u_exact| / {peak:.4g} m/s; "
                                      + window_note),
        check_row(name, "pressure_gradient", gradient, gradient_exact, relative(gradient, gradient_exact),
                  tolerance_of(case, "pressure_gradient"), source=source,
                  note="-dp/dx, Pa/m, least squares over the middle half; " + window_note),
        check_row(name, "mass_balance", imbalance, 0.0, abs(imbalance), tolerance_of(case, "mass_balance"),
                  note=f"(V_in - V_out - dM/rho0) / V_in: V_in = {v_in:.4g}, V_out = {v_out:.4g}, "
                       f"dM/rho0 = {mass_in_volumes:.4g} m^3; " + window_note),
        check_row(name, "density_drift", drift, 0.0, abs(drift), tolerance_of(case, "density_drift"),
                  note=f"change of the fluid's mean density / rho0 ({mean_rho[0]:.6g} -> {mean_rho[-1]:.6g} kg/m^3); "
                       + window_note),
    ]
    if run["attrs"].get("status") != "ok":
        for row in rows:
            row["passed"] = False
    plot = {"title": f"{name}: u(r) (dots SPH, line exact)", "xlabel": "r / R", "ylabel": "u / u_peak",
            "lines": [(r_bin / r_outer, u_bin / peak, "o", "C0", "SPH"),
                      (r_line / r_outer, annulus_velocity(r_line, gradient_exact, r_outer, r_inner, mu) / peak, "-",
                       "C1", "exact")]}
    return rows, plot


def _window_volumes(series: dict, t0: float, t1: float, inlet: str, outlet: str) -> tuple[float, float]:
    """Volumes (m^3) that flowed in through the inlet and out through the outlet in (t0, t1] s."""
    time = np.asarray(series["time"], dtype=float)
    inside = (time > t0 + 1e-12) & (time <= t1 + 1e-12)
    steps = np.diff(time, prepend=time[0])
    v_in = float(np.sum((np.asarray(series[f"inflow_{inlet}"]) * steps)[inside]))
    v_out = float(np.sum((np.asarray(series[f"outflow_{outlet}"]) * steps)[inside]))
    return v_in, v_out


def _middle_fluid(window: list, origin: np.ndarray, axis: np.ndarray, length: float):
    """The fluid in the middle half of the length over the window's frames: axial position s (m), radius r (m),
    axial speed u (m/s), pressure p (Pa), pooled; and per frame the fluid count and its mean density (kg/m^3)."""
    s_all, r_all, u_all, p_all = [], [], [], []
    counts, mean_rho = [], []
    for _, frame in window:
        fluid = fluid_mask(frame)
        x = np.asarray(frame["positions"])[fluid] - origin
        s = x @ axis
        radial = np.linalg.norm(x - np.outer(s, axis), axis=1)
        mid = (s > 0.25 * length) & (s < 0.75 * length)
        s_all.append(s[mid]), r_all.append(radial[mid])
        u_all.append((np.asarray(frame["velocities"])[fluid] @ axis)[mid])
        p_all.append(np.asarray(frame["pressures"])[fluid][mid])
        counts.append(int(fluid.sum()))
        mean_rho.append(float(np.mean(np.asarray(frame["densities"])[fluid])))
    s, r, u, p = (np.concatenate(a) for a in (s_all, r_all, u_all, p_all))
    return s, r, u, p, counts, mean_rho


def _radial_bins(r: np.ndarray, u: np.ndarray, u_particle: np.ndarray, edges: np.ndarray):
    """(mean r m, mean u, mean exact u) in the radial bins of edges holding at least 5 particles."""
    which = np.digitize(r, edges) - 1
    r_bin, u_bin, u_exact = [], [], []
    for k in range(len(edges) - 1):
        sel = which == k
        if np.count_nonzero(sel) >= 5:
            r_bin.append(float(np.mean(r[sel]))), u_bin.append(float(np.mean(u[sel])))
            u_exact.append(float(np.mean(u_particle[sel])))
    return np.asarray(r_bin), np.asarray(u_bin), np.asarray(u_exact)
