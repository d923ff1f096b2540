"""`orchestrator rheometry`: a frequency sweep of the numerical rheometer (kind rheometer; Nutto et al.,
section 3, Figs. 2-3). One run per angular frequency (the case's shear.omega replaced), the runs in parallel
through the Workflow machinery; each run's G', G'' (eq. 17) against the multi-mode Maxwell forms (eqs. 18-19).
A table, a JSON list and a figure of G'(omega), G''(omega) on log axes."""

from __future__ import annotations

import json
import math
import sys
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from orchestrator.case import load_case
from orchestrator.cli.common import check_options
from orchestrator.engines import get_engine
from orchestrator.errors import OrchestratorError
from orchestrator.kinds.base import Command
from orchestrator.kinds.rheometer.analysis import maxwell_moduli
from orchestrator.kinds.rheometer.commands import rheometry_steady as steady
from orchestrator.kinds.rheometer.physics import sample_numerics
from orchestrator.plots import save_pyplot_figure
from orchestrator.run import checked_scene
from orchestrator.workflows.base import Workflow

ENGINE = "sph"


@dataclass
class RheometryPoint(steady.SampleRun):
    """One frequency of the sweep: omega rad/s, the fitted and Maxwell moduli (Pa), their relative errors (-),
    the sample's density kg/m^3 and step s (mass scaling), steps, the engine's wall time s, status and message."""

    omega: float
    storage_modulus: float = math.nan
    loss_modulus: float = math.nan
    maxwell_storage_modulus: float = math.nan
    maxwell_loss_modulus: float = math.nan
    storage_error: float = math.nan
    loss_error: float = math.nan


def frequencies_of(case_file: Path, frequencies=None, overrides=()) -> list[float]:
    """The sweep's angular frequencies, rad/s: the given ones, else the case's [sweep] frequencies, else its
    shear.omega; each a finite number above 0 (OrchestratorError otherwise)."""
    model = load_case(case_file, overrides=overrides).model
    if model.case.kind != "rheometer":
        raise OrchestratorError(f"{case_file}: case.kind = {model.case.kind!r}; rheometry runs rheometer cases")
    if not model.shear.oscillatory:
        raise OrchestratorError(f"{case_file}: shear is steady (shear_rate); a frequency sweep needs an oscillatory "
                                "shear (shear.amplitude and shear.omega); give --shear-rates for a steady sweep")
    if frequencies:
        values = [float(w) for w in frequencies]
    elif model.sweep is not None:
        values = list(model.sweep.frequencies)
    else:
        values = [model.shear.omega]
    for w in values:
        if not (math.isfinite(w) and w > 0):
            raise OrchestratorError(f"--frequencies {w:g}: allowed: angular frequencies above 0, rad/s")
    return sorted(dict.fromkeys(values))


def run_point(case_file: Path, omega: float, out_dir: Path, overrides=(), timeout_s: float | None = None
              ) -> RheometryPoint:
    """Run the case at one angular frequency (rad/s) into out_dir and read its moduli (never raises for a failed
    run)."""
    loaded = load_case(case_file, overrides=[*overrides, f"shear.omega={omega!r}"])
    case = loaded.model
    sn = sample_numerics(case)
    g1, g2 = maxwell_moduli(case.material, omega, case.shear.amplitude)
    point = RheometryPoint(omega, maxwell_storage_modulus=float(g1), maxwell_loss_modulus=float(g2),
                           sample_density=sn.density, time_step=sn.dt, run_dir=str(out_dir))
    summary = steady.run_point(loaded, out_dir, timeout_s, point)
    if summary is None:
        return point
    measured = summary.measured
    point.wall_time_s = summary.wall_time_s
    point.steps = int(getattr(summary, "n_steps", 0) or 0)
    if summary.status != "ok" and point.status == "ok":
        point.status = summary.status
    if "storage_modulus" in measured:
        point.storage_modulus, point.loss_modulus = measured["storage_modulus"], measured["loss_modulus"]
        point.storage_error = abs(point.storage_modulus - g1) / g1
        point.loss_error = abs(point.loss_modulus - g2) / g2
    return point


def run_sweep(case_file: Path, frequencies=None, out_dir=None, overrides=(), workers: int | None = None,
              timeout_s: float | None = None, on_done=None) -> tuple[Path, list[RheometryPoint], float]:
    """The sweep as a Workflow: one run per frequency under <folder>/omega_<value>, in parallel (workers: default
    the number of cores). Returns (folder, points in frequency order, the sweep's wall time s)."""
    case_file = Path(case_file)
    omegas: list[float] = []

    def prepare():
        omegas[:] = frequencies_of(case_file, frequencies, overrides)
        for w in omegas:  # every point validates (and its step count is bounded) before anything runs
            checked_scene(load_case(case_file, overrides=[*overrides, f"shear.omega={w!r}"]).model)

    def jobs(folder: Path):
        get_engine(ENGINE).check_available()
        return [(run_point, (case_file, w, folder / f"omega_{w:g}", overrides, timeout_s)) for w in omegas]

    start = time.perf_counter()
    folder, points = Workflow("rheometry", jobs, prepare).run(out_dir, workers, on_done)
    return folder, points, time.perf_counter() - start


def format_sweep(points: list[RheometryPoint]) -> str:
    """Plain-text table: omega, G' and G'' with their Maxwell values and errors, density, step, steps, time."""
    header = ("omega [rad/s]", "G' [Pa]", "Maxwell G' [Pa]", "error", "G'' [Pa]", "Maxwell G'' [Pa]", "error",
              "rho [kg/m^3]", "dt [s]", "steps", "wall [s]", "status")
    rows = [[f"{p.omega:g}", _g(p.storage_modulus), _g(p.maxwell_storage_modulus), _pct(p.storage_error),
             _g(p.loss_modulus), _g(p.maxwell_loss_modulus), _pct(p.loss_error), f"{p.sample_density:.3g}",
             f"{p.time_step:.3g}", str(p.steps), _g(p.wall_time_s, ".1f"), p.status] for p in points]
    widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(header)]
    lines = ["  ".join(h.ljust(w) for h, w in zip(header, widths))]
    lines += ["  ".join(c.ljust(w) for c, w in zip(r, widths)) for r in rows]
    lines += [f"note: omega = {p.omega:g} rad/s: {p.message}" for p in points if p.message]
    return "\n".join(lines)


def json_sweep(points: list[RheometryPoint], wall_time_s: float) -> dict:
    """{"points": [...], "wall_time_s": s} with NaN as None."""
    def clean(value):
        return None if isinstance(value, float) and not math.isfinite(value) else value

    return {"points": [{k: clean(v) for k, v in asdict(p).items()} for p in points], "wall_time_s": wall_time_s}


def _g(value, spec: str = ".5g") -> str:
    return "-" if not math.isfinite(value) else format(value, spec)


def _pct(value) -> str:
    return "-" if not math.isfinite(value) else f"{100 * value:.2f} %"


def plot_sweep(case_file: Path, points: list[RheometryPoint], path: Path, overrides=()) -> Path:
    """G'(omega) and G''(omega) of the sweep (markers) against the Maxwell forms of the case's modes (lines), log
    axes, as the paper's Figs. 2-3; omega rad/s, moduli Pa."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    case = load_case(case_file, overrides=overrides).model
    omegas = np.array([p.omega for p in points])
    line = np.logspace(math.log10(omegas.min()) - 0.5, math.log10(omegas.max()) + 0.5, 200)
    g1, g2 = maxwell_moduli(case.material, line, case.shear.amplitude)
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    ax.loglog(line, g1, "-", color="C0", label="G' Maxwell (eq. 18)")
    ax.loglog(line, g2, "--", color="C3", label="G'' Maxwell (eq. 19)")
    ok = [p for p in points if math.isfinite(p.storage_modulus)]
    ax.loglog([p.omega for p in ok], [p.storage_modulus for p in ok], "o", color="C0", mfc="none", ms=7,
              label="G' SPH (eq. 17)")
    ax.loglog([p.omega for p in ok], [p.loss_modulus for p in ok], "s", color="C3", mfc="none", ms=7,
              label="G'' SPH (eq. 17)")
    ax.set_xlabel("omega [rad/s]")
    ax.set_ylabel("G', G'' [Pa]")
    modes = len(case.material.modes)
    ax.set_title(f"{case.case.name}: {modes} mode{'s' if modes > 1 else ''}, gamma_A = "
                 f"{100 * case.shear.amplitude:g} %, {case.sample.particles} particles across", fontsize=9)
    ax.grid(True, which="both", lw=0.3, alpha=0.5)
    ax.legend(fontsize=8)
    return save_pyplot_figure(fig, path)


def add_arguments(p) -> None:
    """The options of `orchestrator rheometry`."""
    p.add_argument("case", type=Path, help="a rheometer case file (e.g. cases/rheometry/mf20_table3.toml)")
    p.add_argument("--frequencies", type=float, nargs="+", metavar="OMEGA",
                   help="angular frequencies, rad/s (default: the case's [sweep] frequencies, else shear.omega)")
    p.add_argument("--shear-rates", type=float, nargs="+", metavar="RATE",
                   help="steady mode: shear rates, 1/s; eta and N1 against the PTT closed form, the start-up "
                        "overshoot against the ODE (flow_curve.png)")
    p.add_argument("--relaxation-times", type=float, default=10.0, metavar="K",
                   help="steady mode: each run lasts K x the longest lambda_i / f_i at its rate (default 10)")
    p.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                   help="override a case value at every frequency, SI units, e.g. --set numerics.quasi_static=40")
    p.add_argument("--out", metavar="DIR", help="run directories and the PNG (default: runs/rheometry-<time>)")
    p.add_argument("--workers", type=int, metavar="N", help="parallel runs (default: the number of cores)")
    p.add_argument("--timeout", type=float, metavar="SECONDS", help="wall-time limit of each run, s")
    p.add_argument("--json", action="store_true", help="print the points and the sweep's wall time as JSON "
                   "(SI units; null where not measured)")


def cmd_rheometry(args) -> int:
    """Run the sweep, print its table (or JSON), write rheometry.png; exit 1 when a point failed."""
    check_options(args)
    if args.shear_rates:
        return _steady(args)

    def done(point, count, total):
        print(f"rheometry: {count}/{total} omega = {point.omega:g} rad/s: {point.status}", file=sys.stderr,
              flush=True)

    folder, points, wall = run_sweep(args.case, args.frequencies, args.out, args.overrides, args.workers,
                                     args.timeout, done)
    png = plot_sweep(args.case, points, folder / "rheometry.png", args.overrides)
    if args.json:
        print(json.dumps(json_sweep(points, wall)))
    else:
        print(format_sweep(points))
        print(f"sweep: {len(points)} frequencies in {wall:.1f} s of wall time")
        print(f"figure       {png}")
        print(f"runs         {folder}")
    return 0 if all(p.status == "ok" for p in points) else 1


def _steady(args) -> int:
    """The steady mode: the flow curve's table (or JSON) and flow_curve.png; exit 1 when a point failed."""
    if args.frequencies:
        raise OrchestratorError("--shear-rates and --frequencies: give one (a steady or an oscillatory sweep)")

    def done(point, count, total):
        print(f"rheometry: {count}/{total} rate = {point.shear_rate:g} 1/s: {point.status}", file=sys.stderr,
              flush=True)

    folder, points, wall = steady.run_rate_sweep(args.case, args.shear_rates, args.out, args.overrides,
                                                 args.workers, args.timeout, done, args.relaxation_times)
    png = steady.plot_flow_curve(args.case, points, folder / "flow_curve.png", args.overrides)
    if args.json:
        print(json.dumps(json_sweep(points, wall)))
    else:
        print(steady.format_flow_curve(points))
        print(f"sweep: {len(points)} shear rates in {wall:.1f} s of wall time")
        print(f"figure       {png}")
        print(f"runs         {folder}")
    return 0 if all(p.status == "ok" for p in points) else 1


COMMAND = Command(
    help="frequency sweep of the numerical rheometer: G'(omega), G''(omega) against Maxwell; or, with "
         "--shear-rates, the steady flow curve eta, N1 against PTT",
    description="Run a rheometer case (kind rheometer: a Lees-Edwards SPH sample of a multi-mode PTT fluid in "
        "oscillatory shear gamma_A sin(omega t); Nutto et al.) at each angular frequency, in parallel on "
        "the sph executable; fit eq. 17, tau = G' gamma_A sin(omega t) + G'' gamma_A cos(omega t), over the cycles "
        "after the start-up; print omega (rad/s), G' and G'' (Pa) against the multi-mode Maxwell forms (eqs. "
        "18-19) with their relative errors, the sample's mass-scaled density (kg/m^3), step (s), steps and engine "
        "wall time (s); save rheometry.png (log axes, as the paper's Figs. 2-3). Exit code 1 if a run fails.",
    add_arguments=add_arguments, run=cmd_rheometry)
