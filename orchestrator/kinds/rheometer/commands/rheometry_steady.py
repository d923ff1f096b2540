"""The steady mode of `orchestrator rheometry` (--shear-rates): one steady Lees-Edwards run of the case's sample per
shear rate, in parallel through the Workflow machinery; each run's viscosity eta(gamma_dot) = tau_xy / gamma_dot and
first normal stress difference N1(gamma_dot) over the last tenth of the run against the multi-mode PTT closed form
(each mode its own f_i, reference/viscoelastic_flows.py), and its start-up overshoot against the ODE integration of
the homogeneous PTT equations. SI units."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from orchestrator.case import load_case
from orchestrator.engines import get_engine
from orchestrator.errors import EngineNotFound, OrchestratorError
from orchestrator.kinds.rheometer.physics import sample_numerics
from orchestrator.plots import save_pyplot_figure
from orchestrator.reference.viscoelastic_flows import ptt_f_in_shear, ptt_multimode_steady_shear
from orchestrator.run import checked_scene, run_case
from orchestrator.workflows.base import Workflow

ENGINE = "sph"


@dataclass(kw_only=True)
class SampleRun:
    """What every point of a rheometer sweep records of its run (keyword-only, after the point's own fields): the
    sample's mass-scaled density kg/m^3 and step s, steps, the engine's wall time s, status, message, run folder."""

    sample_density: float = math.nan
    time_step: float = math.nan
    steps: int = 0
    wall_time_s: float = math.nan
    status: str = "ok"
    message: str = ""
    run_dir: str = ""


@dataclass
class FlowCurvePoint(SampleRun):
    """One shear rate (1/s): the measured and closed-form viscosity (Pa s) and N1 (Pa) with their relative errors
    (-), the start-up overshoot (Pa) against the ODE's, the run's duration (s), density (kg/m^3), step (s), steps,
    the engine's wall time (s), status and message."""

    shear_rate: float
    viscosity: float = math.nan
    viscosity_expected: float = math.nan
    viscosity_error: float = math.nan
    n1: float = math.nan
    n1_expected: float = math.nan
    n1_error: float = math.nan
    peak: float = math.nan
    peak_expected: float = math.nan
    peak_error: float = math.nan
    startup_deviation: float = math.nan
    duration: float = math.nan


def run_point(loaded, out_dir, timeout_s, point):
    """Run one point of a sweep on the sph engine; a failed run sets point.status and point.message and gives the
    RunSummary it left (None when it left none). EngineNotFound is raised (the sweep stops)."""
    try:
        return run_case(loaded, engine=ENGINE, out_dir=out_dir, timeout_s=timeout_s, progress=False, force=True)
    except EngineNotFound:
        raise
    except OrchestratorError as exc:
        point.status, point.message = "failed", str(exc).splitlines()[0]
        return exc.summary


def steady_duration(material, shear_rate: float, relaxation_times: float) -> float:
    """Run time (s) of a steady run at shear_rate (1/s): relaxation_times x the longest lambda_i / f_i (the time
    over which mode i approaches its steady state, f_i from the closed form).

    No more: at a low Weissenberg number that is less than one strain unit, and a longer run would see the
    sample's hexagonal lattice rearrange (its rows slide over each other from a strain of about 0.58 on), whose
    bursts put N1 = 2 eta lambda gamma_dot^2 out by 10-20 % where it is that small (docs/rheometry.md)."""
    return relaxation_times * max(m.relaxation_time / float(ptt_f_in_shear(m.relaxation_time * shear_rate,
                                                                             material.epsilon))
                                  for m in material.modes)


def rates_of(case_file, rates, overrides=()) -> list[float]:
    """The sweep's shear rates, 1/s: each finite and above 0 (OrchestratorError naming --shear-rates otherwise)."""
    model = load_case(case_file, overrides=overrides).model
    if model.case.kind != "rheometer":
        raise OrchestratorError(f"{case_file}: case.kind = {model.case.kind!r}; rheometry runs rheometer cases")
    values = [float(r) for r in rates]
    for r in values:
        if not (math.isfinite(r) and r > 0):
            raise OrchestratorError(f"--shear-rates {r:g}: allowed: shear rates above 0, 1/s (a steady sweep has no "
                                    "rate 0)")
    return sorted(dict.fromkeys(values))


def _overrides(case_file, rate: float, relaxation_times: float, overrides) -> list[str]:
    material = load_case(case_file, overrides=overrides).model.material
    duration = steady_duration(material, rate, relaxation_times)
    return [*overrides, f"shear={{shear_rate={rate!r}, duration={duration!r}}}"]


def run_rate(case_file, rate: float, out_dir, relaxation_times: float, overrides=(), timeout_s=None
             ) -> FlowCurvePoint:
    """Run the case in steady shear at one rate (1/s) into out_dir and read eta, N1 and the overshoot (never raises
    for a failed run)."""
    loaded = load_case(case_file, overrides=_overrides(case_file, rate, relaxation_times, overrides))
    case = loaded.model
    sn = sample_numerics(case)
    exact = ptt_multimode_steady_shear(rate, case.material.modes, case.material.epsilon)
    viscosity = exact.viscosity + case.material.solvent_shear_viscosity(rate)
    point = FlowCurvePoint(rate, viscosity_expected=float(viscosity),
                           n1_expected=float(exact.first_normal_stress_difference), duration=case.shear.duration,
                           sample_density=sn.density, time_step=sn.dt, run_dir=str(out_dir))
    summary = run_point(loaded, out_dir, timeout_s, point)
    if summary is None:
        return point
    m = summary.measured
    point.wall_time_s, point.steps = summary.wall_time_s, int(getattr(summary, "n_steps", 0) or 0)
    if summary.status != "ok" and point.status == "ok":
        point.status = summary.status
    point.viscosity = m.get("shear_viscosity", math.nan)
    point.n1 = m.get("first_normal_stress_difference", math.nan)
    point.peak = m.get("startup_peak_shear_stress", math.nan)
    point.peak_expected = m.get("startup_peak_shear_stress_expected", math.nan)
    point.startup_deviation = m.get("startup_deviation", math.nan)
    point.viscosity_error = abs(point.viscosity / point.viscosity_expected - 1.0)
    point.n1_error = abs(point.n1 / point.n1_expected - 1.0) if point.n1_expected else math.nan
    point.peak_error = abs(point.peak / point.peak_expected - 1.0)
    return point


def run_rate_sweep(case_file, rates, out_dir=None, overrides=(), workers=None, timeout_s=None, on_done=None,
                   relaxation_times: float = 10.0) -> tuple:
    """The steady sweep as a Workflow: one run per rate under <folder>/rate_<value>, in parallel. Returns (folder,
    points in rate order, the sweep's wall time s)."""
    chosen: list[float] = []
    if not (math.isfinite(relaxation_times) and relaxation_times > 0):
        raise OrchestratorError(f"--relaxation-times {relaxation_times:g}: allowed: a number above 0")

    def prepare():
        chosen[:] = rates_of(case_file, rates, overrides)
        for r in chosen:  # every point validates (and its step count is bounded) before anything runs
            checked_scene(load_case(case_file, overrides=_overrides(case_file, r, relaxation_times, overrides)).model)

    def jobs(folder):
        get_engine(ENGINE).check_available()
        return [(run_rate, (case_file, r, folder / f"rate_{r:g}", relaxation_times, overrides, timeout_s))
                for r in chosen]

    start = time.perf_counter()
    folder, points = Workflow("rheometry", jobs, prepare).run(out_dir, workers, on_done)
    return folder, points, time.perf_counter() - start


def format_flow_curve(points) -> str:
    """Plain-text table: rate, eta and N1 against the closed form, the overshoot against the ODE, run data."""
    def g(v, spec=".5g"):
        return "-" if not math.isfinite(v) else format(v, spec)

    def pct(v):
        return "-" if not math.isfinite(v) else f"{100 * v:.2f} %"

    header = ("rate [1/s]", "eta [Pa s]", "PTT eta [Pa s]", "error", "N1 [Pa]", "PTT N1 [Pa]", "error",
              "peak [Pa]", "ODE peak [Pa]", "error", "start-up vs ODE", "t [s]", "steps", "wall [s]", "status")
    rows = [[f"{p.shear_rate:g}", g(p.viscosity), g(p.viscosity_expected), pct(p.viscosity_error), g(p.n1),
             g(p.n1_expected), pct(p.n1_error), g(p.peak), g(p.peak_expected), pct(p.peak_error),
             pct(p.startup_deviation),
             f"{p.duration:.3g}", str(p.steps), g(p.wall_time_s, ".1f"), p.status] for p in points]
    widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(header)]
    lines = ["  ".join(h.ljust(w) for h, w in zip(header, widths))]
    lines += ["  ".join(c.ljust(w) for c, w in zip(r, widths)) for r in rows]
    lines += [f"note: rate = {p.shear_rate:g} 1/s: {p.message}" for p in points if p.message]
    return "\n".join(lines)


def plot_flow_curve(case_file, points, path, overrides=()):
    """eta(gamma_dot) (Pa s) and N1(gamma_dot) (Pa) of the sweep (markers; grey crosses: a run that stopped, at its
    last values) against the multi-mode PTT closed form (lines), log-log."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    material = load_case(case_file, overrides=overrides).model.material
    rates = np.array([p.shear_rate for p in points])
    line = np.logspace(math.log10(rates.min()) - 0.5, math.log10(rates.max()) + 0.5, 200)
    exact = ptt_multimode_steady_shear(line, material.modes, material.epsilon)
    fig, (left, right) = plt.subplots(1, 2, figsize=(10.0, 4.2))
    left.loglog(line, exact.viscosity + material.solvent_shear_viscosity(line), "-", color="C0", label="PTT closed form")
    right.loglog(line, exact.first_normal_stress_difference, "-", color="C3", label="PTT closed form")
    measured = [p for p in points if math.isfinite(p.viscosity)]
    for status, marker, what in (("ok", "o", "SPH"), ("failed", "x", "SPH, run stopped (its last values)")):
        shown = [p for p in measured if (p.status == "ok") == (status == "ok")]
        if not shown:
            continue
        left.loglog([p.shear_rate for p in shown], [p.viscosity for p in shown], marker, mfc="none",
                    color="C0" if status == "ok" else "0.4", label=what)
        right.loglog([p.shear_rate for p in shown if p.n1 > 0], [p.n1 for p in shown if p.n1 > 0],
                     "s" if status == "ok" else marker, mfc="none", color="C3" if status == "ok" else "0.4",
                     label=what)
    for ax, label in ((left, "eta [Pa s]"), (right, "N1 [Pa]")):
        ax.set_xlabel("shear rate [1/s]")
        ax.set_ylabel(label)
        ax.grid(True, which="both", lw=0.3, alpha=0.5)
        ax.legend(fontsize=8)
    fig.suptitle(f"{len(material.modes)}-mode linear PTT, epsilon = {material.epsilon:g}: steady shear", fontsize=9)
    return save_pyplot_figure(fig, path)
