"""Rheometer runs: the moduli fitted by eq. 17 (oscillatory shear) or the steady viscosity and normal stresses,
from the series and frames the sph executable writes (run.h5), against the multi-mode Maxwell forms (eqs. 18-19,
reference/maxwell.py) and the steady PTT closed forms (reference/viscoelastic_flows.py). SI units."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.kinds.base import print_run_measures
from orchestrator.kinds.rheometer.physics import sample_numerics
from orchestrator.kinds.rheometer.solvent import cox_merz_loss_modulus, first_harmonic_loss_modulus
from orchestrator.reference.maxwell import Mode, loss_modulus, storage_modulus
from orchestrator.reference.viscoelastic_flows import ptt_startup_shear, ptt_steady_shear
from orchestrator.outputs import save_figure


#: The measured quantities (measure_rheometer): name or fnmatch pattern -> (SI unit, meaning).
QUANTITIES: dict[str, tuple[str, str]] = {
    "sample_density": ("kg/m^3", "the sample's mass-scaled density"),
    "time_step": ("s", "the sample's time step"),
    "storage_modulus": ("Pa", "G' fitted by eq. 17"),
    "loss_modulus": ("Pa", "G'' fitted by eq. 17"),
    "maxwell_storage_modulus": ("Pa", "G' of the multi-mode Maxwell form (eq. 18)"),
    "maxwell_loss_modulus": ("Pa", "G'' of the multi-mode Maxwell form (eq. 19), the solvent's first harmonic added"),
    "cox_merz_loss_modulus": ("Pa", "G'' with the Cross solvent read as omega eta_C(omega) (Cox-Merz)"),
    "offset": ("Pa", "constant term of the eq. 17 fit"),
    "drift": ("Pa", "linear drift of the eq. 17 fit over the fitted cycles"),
    "fit_residual": ("-", "RMS residual of the eq. 17 fit relative to the stress amplitude"),
    "fitted_records": ("-", "shear-stress records in the fitted cycles"),
    "shear_viscosity": ("Pa s", "steady shear: tau_xy / shear rate over the last tenth of the run"),
    "shear_viscosity_expected": ("Pa s", "steady shear: sum eta_i / f_i + eta_s + eta_C(gamma_dot), closed form"),
    "first_normal_stress_difference": ("Pa", "steady shear: N1 over the last tenth of the run"),
    "mode*_shear_viscosity*": ("Pa s", "one mode's shear viscosity (measured, or *_expected: its closed form)"),
    "mode*_first_normal_stress_difference*": ("Pa", "one mode's N1 (measured, or *_expected: its closed form)"),
    "mode*_tau_yy_over_tau_xx": ("-", "one mode's |tau_yy| / |tau_xx|"),
    "velocity_profile": ("-", "relative error of the velocity profile against homogeneous shear"),
    "startup_peak_shear_stress*": ("Pa", "steady shear: the start-up overshoot (measured, or *_expected: the ODE)"),
    "startup_peak_time*": ("s", "steady shear: the time of the overshoot (measured, or *_expected: the ODE)"),
    "startup_deviation": ("-", "steady shear: the largest |tau_xy(t) - the ODE's| over the records, over the ODE's "
                               "largest tau_xy"),
}


def maxwell_moduli(material, omega, amplitude: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """G'(omega), G''(omega) in Pa of the material's modes (eqs. 18-19) plus its plateau G_p in G' and its solvent in
    G'': eta_s omega, and a Cross law's first harmonic at the strain amplitude gamma_A (solvent.py; without an
    amplitude its linear limit eta_0 omega)."""
    modes = [Mode(m.relaxation_time, m.viscosity) for m in material.modes]
    omega = np.asarray(omega, dtype=float)
    loss = loss_modulus(omega, modes) + material.solvent_viscosity * omega
    if material.cross_loss is not None:
        law = material.cross_loss
        loss = loss + (first_harmonic_loss_modulus(law.viscosity, omega, amplitude) if amplitude
                       else law.zero_shear_viscosity * omega)
    return storage_modulus(omega, modes, material.storage_plateau), loss


def fit_moduli(t, tau, omega: float, amplitude: float, t_start: float, t_end: float) -> dict[str, float]:
    """Least squares of eq. 17 over the records in [t_start, t_end] (whole cycles):

        tau(t) = G' gamma_A sin(omega t) + G'' gamma_A cos(omega t) + a + b (t - t_mid) / (t_end - t_start)

    (a, b: the start-up transient of modes slower than the window, a slowly decaying offset). t s, tau Pa,
    omega rad/s, gamma_A -. Returns storage_modulus, loss_modulus (Pa), offset a (Pa), drift b (Pa) and the RMS
    residual over the stress amplitude (-)."""
    t, tau = np.asarray(t, dtype=float), np.asarray(tau, dtype=float)
    span = t_end - t_start
    keep = (t >= t_start - 1e-9 * span) & (t <= t_end + 1e-9 * span) & np.isfinite(tau)
    t, tau = t[keep], tau[keep]
    if len(t) < 8:
        raise ValueError(f"{len(t)} shear-stress records in the fitted cycles; the fit needs at least 8")
    design = np.column_stack([amplitude * np.sin(omega * t), amplitude * np.cos(omega * t), np.ones_like(t),
                              (t - 0.5 * (t_start + t_end)) / span])
    coef, *_ = np.linalg.lstsq(design, tau, rcond=None)
    residual = tau - design @ coef
    scale = amplitude * math.hypot(coef[0], coef[1])
    return {"storage_modulus": float(coef[0]), "loss_modulus": float(coef[1]), "offset": float(coef[2]),
            "drift": float(coef[3]), "fit_residual": float(np.sqrt(np.mean(residual**2)) / scale) if scale else math.inf,
            "fitted_records": float(len(t))}


def startup_peak(t, tau, case) -> dict[str, float]:
    """The start-up overshoot of a steady run: the largest recorded shear stress (Pa) and its time (s), with the
    homogeneous PTT start-up integrated at the same record times (reference.viscoelastic_flows.ptt_startup_shear)
    as startup_peak_shear_stress_expected (nothing when the run stopped before the expected peak: no overshoot
    within it), and always the whole start-up's largest deviation from that integration (startup_deviation)."""
    t, tau = np.asarray(t, dtype=float), np.asarray(tau, dtype=float)
    exact = ptt_startup_shear(t, case.shear.shear_rate, case.material.modes, case.material.epsilon,
                              float(case.material.solvent_shear_viscosity(case.shear.shear_rate)))
    scale = float(np.max(np.abs(exact.shear_stress)))
    deviation = {"startup_deviation": float(np.max(np.abs(tau - exact.shear_stress))) / scale} if scale else {}
    if exact.peak_time >= t[-1]:
        return deviation
    peak = int(np.argmax(tau))
    return {**deviation, "startup_peak_shear_stress": float(tau[peak]), "startup_peak_time": float(t[peak]),
            "startup_peak_shear_stress_expected": exact.peak_shear_stress,
            "startup_peak_time_expected": exact.peak_time}


def _volume_mean(frame: dict, values: np.ndarray) -> np.ndarray:
    """Volume average over the fluid (equal masses: weights 1/rho) of per-particle values (n, ...)."""
    fluid = np.asarray(frame["kind"]) == 0
    weights = 1.0 / np.asarray(frame["densities"], dtype=float)[fluid]
    return np.tensordot(weights / weights.sum(), np.asarray(values)[fluid], axes=(0, 0))


def profile_error(frames, case) -> tuple[float, float]:
    """Largest deviation of u_x from the homogeneous shear gamma_dot(t) (y - L/2) + mean over the fluid,
    divided by gamma_dot_peak L / 2, over the frames at the peaks of |gamma_dot| in the fitted cycles
    (oscillation) or the last frame (steady); and the time of the worst frame (s)."""
    shear, size = case.shear, case.sample.size
    if shear.oscillatory:
        start = shear.startup_cycles * shear.time_scale
        chosen = [(t, f) for t, f in frames if t >= start - 1e-9 and abs(math.cos(shear.omega * t)) > 0.999]
    else:
        chosen = frames[-1:]
    worst, when = math.nan, math.nan
    for t, frame in chosen:
        rate = shear.amplitude * shear.omega * math.cos(shear.omega * t) if shear.oscillatory else shear.shear_rate
        fluid = np.asarray(frame["kind"]) == 0
        y = np.asarray(frame["positions"])[fluid, 1]
        u = np.asarray(frame["velocities"])[fluid, 0]
        deviation = u - rate * (y - 0.5 * size)
        error = float(np.max(np.abs(deviation - deviation.mean()))) / (0.5 * shear.peak_rate * size)
        if not error <= worst:
            worst, when = error, t
    return worst, when


def measure_rheometer(case, result) -> dict[str, float]:
    """Measured quantities of a rheometer run (Pa, Pa s, -): sample_density kg/m^3 and time_step s (the mass
    scaling); oscillation: storage_modulus, loss_modulus (eq. 17 over the cycles after the start-up), the Maxwell
    values maxwell_storage_modulus, maxwell_loss_modulus (eqs. 18-19), fit_residual; steady: shear_viscosity =
    tau_xy / gamma_dot and first_normal_stress_difference averaged over the last tenth of the run, and per mode i
    (last frame) mode<i>_shear_viscosity, mode<i>_first_normal_stress_difference, mode<i>_tau_yy_over_tau_xx with
    their closed forms *_expected; both: velocity_profile (profile_error). Empty when the run recorded nothing."""
    sn = sample_numerics(case)
    measured = {"sample_density": sn.density, "time_step": sn.dt}
    series, shear = result.series, case.shear
    if result.time is None or "shear_stress" not in series or not len(result.time):
        return measured
    t, tau = np.asarray(result.time, dtype=float), np.asarray(series["shear_stress"].values, dtype=float)
    frames = [(time, arrays) for time, arrays in result.frames]
    if shear.oscillatory:
        start = shear.startup_cycles * shear.time_scale
        if t[-1] >= shear.duration_s * (1 - 1e-9):
            measured.update(fit_moduli(t, tau, shear.omega, shear.amplitude, start, shear.duration_s))
        g1, g2 = maxwell_moduli(case.material, shear.omega, shear.amplitude)
        measured.update(maxwell_storage_modulus=float(g1), maxwell_loss_modulus=float(g2))
        if case.material.cross_loss is not None:
            measured["cox_merz_loss_modulus"] = float(g2 - first_harmonic_loss_modulus(
                case.material.cross_loss.viscosity, shear.omega, shear.amplitude) + cox_merz_loss_modulus(
                case.material.cross_loss.viscosity, shear.omega))
    else:
        late = t >= t[-1] - 0.1 * shear.duration
        # a Morris solvent is not in the recorded stress; in homogeneous shear it adds eta_s exactly
        solvent = case.material.solvent_viscosity if sn.morris_viscosity > 0.0 else 0.0
        measured["shear_viscosity"] = float(np.mean(tau[late]) / shear.shear_rate) + solvent
        measured["shear_viscosity_expected"] = float(sum(
            ptt_steady_shear(shear.shear_rate, m.relaxation_time, m.viscosity, case.material.epsilon).viscosity
            for m in case.material.modes) + case.material.solvent_shear_viscosity(shear.shear_rate))
        measured.update(startup_peak(t, tau + solvent * shear.shear_rate, case))
        if "first_normal_stress_difference" in series:
            measured["first_normal_stress_difference"] = float(np.mean(
                np.asarray(series["first_normal_stress_difference"].values)[late]))
        if frames and "mode_stress" in frames[-1][1]:
            stress = _volume_mean(frames[-1][1], frames[-1][1]["mode_stress"])  # (modes, D, D)
            for i, (mode, s) in enumerate(zip(case.material.modes, stress), 1):
                exact = ptt_steady_shear(shear.shear_rate, mode.relaxation_time, mode.viscosity, case.material.epsilon)
                measured[f"mode{i}_shear_viscosity"] = float(s[0, 1] / shear.shear_rate)
                measured[f"mode{i}_shear_viscosity_expected"] = float(exact.viscosity)
                measured[f"mode{i}_first_normal_stress_difference"] = float(s[0, 0] - s[1, 1])
                measured[f"mode{i}_first_normal_stress_difference_expected"] = float(
                    exact.first_normal_stress_difference)
                measured[f"mode{i}_tau_yy_over_tau_xx"] = float(abs(s[1, 1]) / abs(s[0, 0]))
    if frames:
        measured["velocity_profile"] = profile_error(frames, case)[0]
    return {k: v for k, v in measured.items() if not (isinstance(v, float) and math.isnan(v))}


def analyze_rheometer_run(run_dir: Path, run: dict, case, render: bool = True) -> dict:
    """`orchestrator analyze` of a rheometer run: print the measured quantities against their references and
    write stress.png (the shear stress against time with the fitted eq. 17). Returns {name: path}."""
    print_run_measures(run_dir, run, {}, width=48)
    path = plot_stress(run, case, Path(run_dir) / "stress.png")
    print(f"{'stress':<10} {path}")
    return {"stress": path}


def plot_stress(run: dict, case, path: Path) -> Path:
    """The sample's shear stress (Pa) against time (s); oscillation: the fitted eq. 17 over the fitted cycles."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    series = run.get("series", {})
    t = np.asarray(series.get("time", []), dtype=float)
    tau = np.asarray(series.get("shear_stress", []), dtype=float)
    fig = Figure(figsize=(8.0, 3.6), dpi=120, layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    ax.plot(t, tau, ".", ms=2.5, label="SPH, volume-averaged tau_xy")
    measured = run.get("measured", {}).get("attrs", {})
    shear = case.shear
    if shear.oscillatory and "storage_modulus" in measured:
        start = shear.startup_cycles * shear.time_scale
        tt = np.linspace(start, shear.duration_s, 400)
        fit = shear.amplitude * (measured["storage_modulus"] * np.sin(shear.omega * tt) +
                                 measured["loss_modulus"] * np.cos(shear.omega * tt))
        ax.plot(tt, fit + measured.get("offset", 0.0), "-", lw=1.0,
                label=f"eq. 17: G' = {measured['storage_modulus']:.4g} Pa, G'' = {measured['loss_modulus']:.4g} Pa")
        ax.axvline(start, color="0.6", ls=":", lw=1)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("tau_xy [Pa]")
    ax.legend(fontsize=8, loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=2, frameon=False)
    save_figure(fig, path, dpi=fig.dpi, layout=False)  # the output policy: temporary name, rename
    return Path(path)
