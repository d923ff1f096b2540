"""Speed against error: a verification suite's scenes at several time-step
factors (the case key its owner names, Verification.timestep_key: e.g.
numerics.timestep_factor, the fraction of the critical step) on each engine.

For every (engine, factor) point: the worst check of every scene (relative
error over its tolerance, and the relative error itself), how many checks
pass, and the engines' compute time (the time the engine spent inside its
run, start-up of the interpreter excluded, summed over the scenes). A PNG
plots the worst relative error and the compute time against the factor.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from orchestrator.plots import save_pyplot_figure
from orchestrator.runh5 import read_run
from orchestrator.workflows.base import Workflow
from orchestrator.errors import OrchestratorError
from orchestrator.workflows.verify import get_suite, suites, verification

#: Factors swept by default (fractions of the critical step).
DEFAULT_FACTORS = (0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0)


@dataclass(frozen=True)
class SweepPoint:
    """One engine at one factor over all scenes: the largest relative error (-), the check closest to (or
    farthest past) its tolerance and that ratio, checks passed, unstable runs, compute time (s), steps."""

    engine: str
    factor: float
    max_rel_error: float
    worst_check: str
    max_error_over_tolerance: float
    checks_passed: int
    checks: int
    unstable_runs: int
    compute_time_s: float
    steps: int


def run_timestep_sweep(suite: str, factors=DEFAULT_FACTORS, engines=None, out_dir=None, cases_dir=None,
                       workers=None):
    """Run the suite's verification at each factor; returns (points, runs by factor). Run directories:
    out_dir/f<factor>/... OrchestratorError for a suite whose owner names no time-step key."""

    chosen = get_suite(suite)
    key = chosen.declared.timestep_key
    if not key:
        swept = [name for name, other in suites().items() if other.declared.timestep_key]
        raise OrchestratorError(f"--timestep-factors: the {suite} suite has no time-step factor to sweep; suites "
                                f"that do: {', '.join(swept) or 'none'}")
    sweeps = {factor: verification(chosen, engines, cases_dir, [f"{key}={factor}"]) for factor in factors}
    planned: list[float] = []  # the factor of each job, in order

    def prepare():
        for sweep in sweeps.values():
            sweep.prepare()

    def jobs(folder: Path):
        out = []
        for factor, sweep in sweeps.items():
            mine = sweep.jobs(folder / f"f{factor:g}")
            planned.extend([factor] * len(mine))
            out += mine
        return out

    _, results = Workflow("timestep-sweep", jobs, prepare).run(out_dir, workers)
    runs_by_factor = {factor: [run for f, run in zip(planned, results) if f == factor] for factor in factors}
    return summarize(runs_by_factor), runs_by_factor


def summarize(runs_by_factor: dict) -> list[SweepPoint]:
    """One SweepPoint per (engine, factor)."""

    points = []
    for factor, runs in runs_by_factor.items():
        for engine in dict.fromkeys(run.engine for run in runs):
            mine = [run for run in runs if run.engine == engine]
            rows = [row for run in mine for row in run.rows]
            errors = [(row["rel_error"] if math.isfinite(row["rel_error"]) else math.inf, row) for row in rows]
            worst_error = max((e for e, _ in errors), default=math.nan)
            ratio, worst_row = max(((e / row["tolerance"], row) for e, row in errors), key=lambda item: item[0],
                                   default=(math.nan, None))
            compute, steps = 0.0, 0
            for run in mine:
                try:
                    attrs = read_run(run.run_dir)["attrs"]
                    compute += float(attrs.get("engine_wall_time_s", attrs.get("wall_time_s", 0.0)))
                    steps += int(attrs.get("n_steps", 0))
                except Exception:  # noqa: BLE001 (a run without run.h5 counts as no time)
                    pass
            points.append(SweepPoint(
                engine, float(factor), float(worst_error),
                f"{worst_row['scene']}: {worst_row['quantity']}" if worst_row else "", float(ratio),
                sum(row["passed"] for row in rows), len(rows), sum(run.status == "unstable" for run in mine),
                compute, steps))
    return points


def format_sweep(points: list[SweepPoint]) -> str:
    """Table: engine, factor, worst rel_error and its check, error / tolerance, checks passed, unstable runs,
    compute time (s), steps."""
    header = ("engine", "factor", "max_rel_error", "error/tol", "passed", "unstable", "compute_s", "steps",
              "check with the largest error/tol")
    table = [(p.engine, f"{p.factor:g}", f"{p.max_rel_error:.2e}", f"{p.max_error_over_tolerance:.2f}",
              f"{p.checks_passed}/{p.checks}", str(p.unstable_runs), f"{p.compute_time_s:.2f}", str(p.steps),
              p.worst_check) for p in sorted(points, key=lambda p: (p.engine, p.factor))]
    widths = [max(len(h), *(len(r[i]) for r in table)) for i, h in enumerate(header)]
    lines = ["  ".join(h.ljust(w) for h, w in zip(header, widths))]
    lines += ["  ".join(c.ljust(w) for c, w in zip(row, widths)) for row in table]
    return "\n".join(lines)


def plot_sweep(points: list[SweepPoint], path: Path) -> Path:
    """PNG: the worst relative error over its tolerance (-) and the compute time (s) against the time-step
    factor (-), one line per engine."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    for k, engine in enumerate(dict.fromkeys(p.engine for p in points)):
        mine = sorted((p for p in points if p.engine == engine), key=lambda p: p.factor)
        factors = [p.factor for p in mine]
        ratios = [p.max_error_over_tolerance if math.isfinite(p.max_error_over_tolerance) else 1e3 for p in mine]
        left.loglog(factors, ratios, "o-", color=f"C{k}", label=engine)
        for p, ratio in zip(mine, ratios):
            if p.unstable_runs:
                left.annotate(f"{p.unstable_runs} unstable", (p.factor, ratio), fontsize=7)
        right.loglog(factors, [p.compute_time_s for p in mine], "o-", color=f"C{k}", label=engine)
    left.axhline(1.0, color="grey", ls=":", lw=1)
    left.axvline(0.05, color="grey", ls="--", lw=1)
    left.set_xlabel("time-step factor (fraction of the critical step)")
    left.set_ylabel("worst relative error / tolerance of all checks")
    left.set_title("error (above the dotted line a check fails; dashed: the default 0.05)", fontsize=9)
    right.axvline(0.05, color="grey", ls="--", lw=1)
    right.set_xlabel("time-step factor (fraction of the critical step)")
    right.set_ylabel("engine compute time, all scenes [s]")
    right.set_title("speed", fontsize=9)
    for ax in (left, right):
        ax.legend(fontsize=8)
        ax.grid(True, which="both", alpha=0.3)

    return save_pyplot_figure(fig, path)
