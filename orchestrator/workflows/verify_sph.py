"""`orchestrator verify sph`: the SPH verification scenes (the sph_flow and rheometer cases in
cases/verification/sph_*.toml) on the sph executable, in parallel; each scene's run.h5 is checked by
kinds/sph_flow/checks.py or kinds/rheometer/checks.py against its closed form, series solution or measurement. A
rheometer scene with a [sweep] runs once per frequency (shear.omega set to each). One table (the rows of
`verify dem`) and a PNG of every scene's profiles, pressures, fronts, wall forces and stresses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from orchestrator.case import load_case
from orchestrator.engines import get_engine
from orchestrator.errors import EngineNotFound, OrchestratorError
from orchestrator.kinds.rheometer import checks as rheometer_checks
from orchestrator.kinds.sph_flow.checks import evaluate as evaluate_flow
from orchestrator.kinds.sph_flow.checks_base import ENGINE, UNITS, check_row
from orchestrator.plots import save_pyplot_figure
from orchestrator.run import run_case
from orchestrator.runh5 import read_run
from orchestrator.workflows.base import CheckedRun, Workflow
from orchestrator.workflows.verify import default_out_dir as suite_dir
from orchestrator.workflows.verify import load_scenes
from orchestrator.workflows.verify import scene_files as kind_files


@dataclass
class SphSceneRun(CheckedRun):
    """One SPH scene's run: status, check rows (verify.ROW_KEYS plus source and note) and what to plot."""

    plot: dict = field(default_factory=dict)  # title, xlabel, ylabel, lines: [(x, y, fmt, label)]


#: The case kinds `verify sph` runs, and the checks of each.
KIND_CHECKS = {"sph_flow": evaluate_flow, "rheometer": rheometer_checks.evaluate}


def evaluate(case, run):
    """The check rows and plots of a scene, by its kind (KIND_CHECKS)."""
    return KIND_CHECKS[case.case.kind](case, run)


# ---------------------------------------------------------------------------------------------------- runs
def run_scene(case_file: Path, out_dir: Path, overrides=(), timeout_s: float | None = 3600.0,
              preset: str | None = None) -> SphSceneRun:
    """Run one SPH verification scene on the sph executable and check it (never raises for a failed run)."""

    loaded = load_case(case_file, preset=preset, overrides=overrides)
    if not loaded.model.expected:
        evaluate(loaded.model, {})  # raises: the scene names no checks
    run_dir = Path(out_dir)
    status, message, wall = "ok", "", math.nan
    try:
        summary = run_case(loaded, engine=ENGINE, out_dir=run_dir, timeout_s=timeout_s, progress=False, force=True)
        wall = summary.wall_time_s
    except EngineNotFound:
        raise
    except OrchestratorError as exc:
        status = exc.summary.status if exc.summary is not None else "failed"
        message = str(exc).split("\n")[0]
        wall = exc.summary.wall_time_s if exc.summary is not None else math.nan
    result = SphSceneRun(loaded.name, ENGINE, status, message, run_dir, wall_time_s=wall)
    try:
        run = read_run(run_dir)
    except OrchestratorError:
        run = {"attrs": {}}
    try:
        result.rows, plots = evaluate(loaded.model, run)
        result.plot = plots[0]
    except (KeyError, IndexError, ValueError) as exc:  # a run that stopped too early to measure
        result.rows = [check_row(loaded.name, "run", None, None, None, None, passed=False,
                            note=f"cannot evaluate the checks: {type(exc).__name__}: {exc}")]
    if status != "ok":
        for row in result.rows:
            row["passed"] = False
            row["note"] = f"run {status}: {message}"
    return result


def scene_files(directory: Path | None = None) -> list[Path]:
    """The SPH verification scenes (case kinds sph_flow and rheometer) in directory (default cases/verification),
    sorted by name."""

    files = []
    for kind in KIND_CHECKS:
        try:
            files += kind_files(directory, kind=kind)
        except OrchestratorError:
            if kind == "sph_flow":
                raise
    return sorted(files, key=lambda path: path.name)


def scene_jobs(path: Path, overrides=(), preset: str | None = None) -> list[tuple[str, tuple[str, ...]]]:
    """(run folder name, overrides) of each run of a scene: one, or one per [sweep] frequency of a rheometer scene
    (shear.omega set to it)."""
    sweep = getattr(load_case(path, preset=preset, overrides=overrides).model, "sweep", None)
    if sweep is None:
        return [(path.stem, tuple(overrides))]
    return [(f"{path.stem}/omega_{w:g}", (*overrides, f"shear.omega={w!r}")) for w in sweep.frequencies]


def run_verification(out_dir=None, cases_dir=None, overrides=(), workers: int | None = None,
                     timeout_s: float | None = 3600.0, on_done=None, only=None, preset: str | None = None
                     ) -> list[SphSceneRun]:
    """Every SPH scene (or those whose stem is in `only`) on the sph executable; runs under out_dir/<scene>.

    overrides: --set strings applied to every scene; workers: parallel runs (default: the number of
    cores; each run uses the case's numerics.threads); on_done(run, done, total) as each run ends.
    """

    files = [f for f in scene_files(cases_dir) if not only or f.stem in only]

    def prepare():
        load_scenes(files, overrides, preset)
        for path in files:
            for _, extra in scene_jobs(path, overrides, preset):
                load_case(path, preset=preset, overrides=extra)

    def jobs(folder: Path):
        get_engine(ENGINE).check_available()  # after the folder: a bad --out is named first
        return [(run_scene, (path, folder / name, extra, timeout_s, preset)) for path in files
                for name, extra in scene_jobs(path, overrides, preset)]

    return Workflow("verify-sph", jobs, prepare).run(out_dir, workers, on_done)[1]


def default_out_dir(root: Path = Path("runs")) -> Path:
    """runs/verify-sph-<UTC timestamp>."""

    return suite_dir(root, suite="sph")


def unit_of(quantity: str) -> str:
    """SI unit of a row's quantity ('u_profile(t=0.1 s)' -> 'm/s')."""
    base = quantity.split("(")[0].split("[")[0]
    return UNITS.get(base, rheometer_checks.UNITS.get(base, ""))


def plot_scenes(runs: list[SphSceneRun], path: Path) -> Path:
    """PNG: one panel per scene (profiles against the series, pressure against depth, front against the
    measurements, wall forces)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs = [r for r in runs if r.plot]
    columns = min(3, max(1, len(runs)))
    rows = max(1, math.ceil(len(runs) / columns))
    fig, axes = plt.subplots(rows, columns, figsize=(4.6 * columns, 3.6 * rows), squeeze=False)
    for ax, run in zip(axes.ravel(), runs):
        for x, y, fmt, colour, label in run.plot["lines"]:
            style = dict(color=colour, label=label)
            if fmt in ("-", "--"):
                ax.plot(x, y, fmt, lw=1.2, **style)
            else:
                ax.plot(x, y, fmt, ms=2.5 if fmt == "." else 4, mfc="none" if fmt != "." else None, **style)
        status = "" if run.status == "ok" else f" ({run.status})"
        ax.set_title(run.plot["title"] + status, fontsize=8)
        ax.set_xlabel(run.plot["xlabel"], fontsize=8)
        ax.set_ylabel(run.plot["ylabel"], fontsize=8)
        ax.tick_params(labelsize=7)
        ax.legend(fontsize=6)
    for ax in axes.ravel()[len(runs):]:
        ax.set_visible(False)

    return save_pyplot_figure(fig, path)
