"""The rheometer's verification checks (`verify sph`): each scene's measured quantities (run.h5 /measured, from
analysis.measure_rheometer) against the multi-mode Maxwell moduli (eqs. 18-19), the steady PTT closed forms per
mode (reference/viscoelastic_flows.py) and the Newtonian cell's homogeneous shear. A scene's [[expected]] rows
choose the comparisons and give each quantity its tolerance; rows have the keys of `verify dem` (ROW_KEYS)."""

from __future__ import annotations

import math

import numpy as np

from orchestrator.errors import OrchestratorError
from orchestrator.kinds.rheometer.analysis import maxwell_moduli
from orchestrator.kinds.sph_flow.checks_base import check_row, relative

#: Units of the rheometer's quantities in the table.
UNITS = {"storage_modulus": "Pa", "loss_modulus": "Pa", "shear_viscosity": "Pa s",
         "first_normal_stress_difference": "Pa", "tau_yy_over_tau_xx": "-", "velocity_profile": "-",
         "storage_over_loss": "-"}


def _tolerance(case, check: str, quantity: str):
    return next((row.tolerance for row in case.expected if row.check == check and row.quantity == quantity), None)


def _measured(run) -> dict:
    return run.get("measured", {}).get("attrs", {}) if run else {}


def _stress_plot(case, run, title: str) -> dict:
    """tau_xy / (gamma_A |G*|) against t / T with the fitted eq. 17 (what verify_sph.png shows)."""
    series = run.get("series", {}) if run else {}
    shear = case.shear
    t = np.asarray(series.get("time", []), dtype=float)
    tau = np.asarray(series.get("shear_stress", []), dtype=float)
    scale = shear.amplitude * abs(case.material.complex_modulus(shear.omega))
    lines = [(t / shear.time_scale, tau / scale, ".", "C0", "SPH tau_xy")] if len(t) == len(tau) and len(t) else []
    m = _measured(run)
    if "storage_modulus" in m:
        tt = np.linspace(shear.startup_cycles, shear.startup_cycles + shear.cycles, 200) * shear.time_scale
        fit = shear.amplitude * (m["storage_modulus"] * np.sin(shear.omega * tt) +
                                 m["loss_modulus"] * np.cos(shear.omega * tt)) + m.get("offset", 0.0)
        lines.append((tt / shear.time_scale, fit / scale, "-", "C3", "eq. 17 fit"))
    return {"title": title, "xlabel": "t / T", "ylabel": "tau_xy / (gamma_A |G*|)", "lines": lines}


def check_saos(case, run) -> tuple[list[dict], dict]:
    """G', G'' fitted by eq. 17 against the Maxwell forms at the scene's omega."""
    m, name, omega, material = _measured(run), case.case.name, case.shear.omega, case.material
    g1, g2 = maxwell_moduli(material, omega, case.shear.amplitude)
    rows = []
    source = "multi-mode Maxwell, Nutto et al. eqs. 18-19 (reference/maxwell.py)"
    extra = {"storage_modulus": f", G_p = {material.storage_plateau:g} Pa" if material.storage_plateau else "",
             "loss_modulus": ""}
    if material.cross_loss is not None and m.get("cox_merz_loss_modulus"):
        extra["loss_modulus"] = (f", Cross solvent by its first harmonic at gamma_A (solvent.py); the Cox-Merz "
                                 f"omega eta_C(omega) = {m['cox_merz_loss_modulus']:.4g} Pa is "
                                 f"{relative(m['cox_merz_loss_modulus'], float(g2)):+.3g} from it")
    for quantity, expected in (("storage_modulus", float(g1)), ("loss_modulus", float(g2))):
        value = m.get(quantity)
        rows.append(check_row(name, f"{quantity}(omega={omega:g} rad/s)", value, expected,
                              None if value is None else relative(value, expected),
                              _tolerance(case, "saos_maxwell", quantity), source=source,
                              note=f"{quantity}: eq. 17 over {case.shear.cycles} cycles after "
                                   f"{case.shear.startup_cycles}; gamma_A = {case.shear.amplitude:g}, "
                                   f"{len(material.modes)} mode(s){extra[quantity]}"))
    return rows, _stress_plot(case, run, f"{name}: omega = {omega:g} rad/s")


def check_steady_ptt(case, run) -> tuple[list[dict], dict]:
    """Per mode: shear viscosity eta_i / f_i and N1 = 2 eta_i lambda_i gamma_dot^2 / f_i^2 (each its own f_i), and
    |tau_yy| / tau_xx (0 in steady shear), from the volume-averaged mode stresses of the last frame."""
    m, name = _measured(run), case.case.name
    rows, lines = [], []
    rate = case.shear.shear_rate
    source = "steady linear PTT, f^3 - f^2 - 2 eps Wi^2 = 0 per mode (reference/viscoelastic_flows.py)"
    for i, mode in enumerate(case.material.modes, 1):
        wi = mode.relaxation_time * rate
        for quantity in ("shear_viscosity", "first_normal_stress_difference"):
            value, expected = m.get(f"mode{i}_{quantity}"), m.get(f"mode{i}_{quantity}_expected")
            rows.append(check_row(name, f"{quantity}(mode {i}, Wi={wi:g})", value, expected,
                                  None if value is None or expected is None else relative(value, expected),
                                  _tolerance(case, "steady_ptt", quantity), source=source,
                                  note=f"{quantity}: mode {i} (lambda = {mode.relaxation_time:g} s, eta = "
                                       f"{mode.viscosity:g} Pa s, eps = {case.material.epsilon:g}), volume average "
                                       "of the last frame"))
        ratio = m.get(f"mode{i}_tau_yy_over_tau_xx")
        rows.append(check_row(name, f"tau_yy_over_tau_xx(mode {i}, Wi={wi:g})", ratio, 0.0, ratio,
                              _tolerance(case, "steady_ptt", "tau_yy_over_tau_xx"), source="tau_yy = 0",
                              note="tau_yy_over_tau_xx: rel_error = |tau_yy| / tau_xx (a transposed velocity "
                                   "gradient gives tau_yy = tau_xx)"))
        for quantity, marker, label in (("shear_viscosity", "o", "eta"), ("first_normal_stress_difference", "s",
                                                                         "N1")):
            if m.get(f"mode{i}_{quantity}_expected"):
                ratio = m.get(f"mode{i}_{quantity}", math.nan) / m[f"mode{i}_{quantity}_expected"]
                lines.append(([wi], [ratio], marker, f"C{i}", f"mode {i}: {label} SPH / closed form"))
    lines.append(([0.0, 1.1 * max([mode.relaxation_time * rate for mode in case.material.modes] or [1.0])],
                  [1.0, 1.0], ":", "0.5", None))
    plot = {"title": f"{name}: steady PTT per mode", "xlabel": "Wi = lambda gamma_dot", "ylabel": "SPH / closed form",
            "lines": lines}
    return rows, plot


def check_steady_viscosity(case, run) -> tuple[list[dict], dict]:
    """The sample's steady shear viscosity tau_xy / gamma_dot (modes, solvent and Cross law together) against
    sum eta_i / f_i + eta_s + eta_C(gamma_dot)."""
    m, name, rate = _measured(run), case.case.name, case.shear.shear_rate
    value, expected = m.get("shear_viscosity"), m.get("shear_viscosity_expected")
    row = check_row(name, f"shear_viscosity(gamma_dot={rate:g} 1/s)", value, expected,
                    None if value is None or expected is None else relative(value, expected),
                    _tolerance(case, "steady_viscosity", "shear_viscosity"),
                    source="steady PTT per mode plus eta_s + eta_C(gamma_dot) (Cross law)",
                    note="shear_viscosity: the volume-averaged tau_xy / gamma_dot over the last tenth of the run")
    ratio = math.nan if not (value and expected) else value / expected
    plot = {"title": f"{name}: steady shear viscosity", "xlabel": "gamma_dot [1/s]", "ylabel": "SPH / closed form",
            "lines": [([rate], [ratio], "o", "C0", "eta SPH / closed form"), ([0.0, 1.1 * rate], [1.0, 1.0], ":",
                                                                              "0.5", None)]}
    return [row], plot


def check_newtonian_cell(case, run) -> tuple[list[dict], dict]:
    """A Newtonian sample (the solvent): u_x linear in y within tolerance of gamma_dot L/2 at the peaks of the rate,
    G'/G'' below tolerance, G'' = eta_s omega."""
    m, name, omega = _measured(run), case.case.name, case.shear.omega
    g1, g2 = maxwell_moduli(case.material, omega, case.shear.amplitude)
    profile = m.get("velocity_profile")
    storage, loss = m.get("storage_modulus"), m.get("loss_modulus")
    ratio = None if storage is None or not loss else abs(storage) / loss
    rows = [check_row(name, "velocity_profile", profile, 0.0, profile,
                      _tolerance(case, "newtonian_cell", "velocity_profile"), source="homogeneous shear",
                      note="velocity_profile: rel_error = max |u_x - gamma_dot(t) (y - L/2) - mean| / "
                           "(gamma_dot_peak L / 2) over the frames at the peaks of |gamma_dot| after the start-up"),
            check_row(name, "storage_over_loss", ratio, 0.0, ratio, _tolerance(case, "newtonian_cell",
                      "storage_over_loss"), source="Newtonian: G' = 0",
                      note="storage_over_loss: rel_error = |G'| / G'' (eq. 17)"),
            check_row(name, f"loss_modulus(omega={omega:g} rad/s)", loss, float(g2),
                      None if loss is None else relative(loss, float(g2)),
                      _tolerance(case, "newtonian_cell", "loss_modulus"), source="G'' = eta_s omega (+ the modes')",
                      note=f"loss_modulus: Maxwell G' of the modes = {float(g1):.3g} Pa")]
    return rows, _stress_plot(case, run, f"{name}: Newtonian cell")


CHECKS = {"saos_maxwell": check_saos, "steady_ptt": check_steady_ptt, "steady_viscosity": check_steady_viscosity,
          "newtonian_cell": check_newtonian_cell}


def evaluate(case, run) -> tuple[list[dict], list[dict]]:
    """The rows and plots of the comparisons the scene's [[expected]] rows name (only their quantities)."""
    if not case.expected:
        raise OrchestratorError(f"{case.case.name} has no [[expected]] rows: nothing to check")
    rows, plots = [], []
    for check in dict.fromkeys(row.check for row in case.expected):
        listed = {row.quantity for row in case.expected if row.check == check}
        measured, plot = CHECKS[check](case, run)
        rows += [row for row in measured if row["quantity"].split("(")[0] in listed]
        plots.append(plot)
    return rows, plots


def check_run(case, engine: str, run: dict) -> tuple[list[dict], dict]:
    """The rheometer's part of `verify sph`: the scene's check rows and its first panel for the suite's picture."""
    rows, plots = evaluate(case, run)
    return rows, plots[0]


def sweep_runs(case, stem: str) -> list[tuple[str, tuple[str, ...]]]:
    """(run folder, overrides) of each run of a verification scene: one, or one per [sweep] frequency (shear.omega
    set to it, rad/s)."""
    if case.sweep is None:
        return [(stem, ())]
    return [(f"{stem}/omega_{w:g}", (f"shear.omega={w!r}",)) for w in case.sweep.frequencies]
