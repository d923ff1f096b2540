"""`orchestrator verify dem`: every verification scene on every installed DEM
engine and on the reference, checked against its closed form.

The scenes are the impact cases in cases/verification/ (shipped with the
package); each case's [[expected]] table names the quantity, the closed form
or value and the relative tolerance. One table row per (scene, engine,
check); a run that ends unstable or failed gives failing rows with the reason.
A PNG overlays the normal-force curves of every engine per scene.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from orchestrator.case import load_case
from orchestrator.case.loader import read_toml_file
from orchestrator.engines import engine_names, get_engine
from orchestrator.errors import CaseError, EngineNotFound, OrchestratorError
from orchestrator.humanize import stamped_dir
from orchestrator.kinds import engines_for_kind
from orchestrator.kinds.impact.analysis import evaluate_checks
from orchestrator.kinds.impact.theory import QUANTITIES
from orchestrator.run import run_case
from orchestrator.runh5 import read_run
from orchestrator.workflows.base import CheckedRun, Workflow
from orchestrator.workflows.base import format_table as base_table

_CANDIDATE_DIRS = (
    Path(__file__).resolve().parent.parent / "verification_cases",  # installed wheel
    Path(__file__).resolve().parent.parent.parent / "cases" / "verification",  # source checkout / editable install
)


def verification_dir() -> Path:
    """Directory holding the verification scenes (cases/verification)."""
    for candidate in _CANDIDATE_DIRS:
        if candidate.is_dir():
            return candidate
    raise OrchestratorError("the verification scenes (cases/verification) are missing; reinstall the package")


def scene_files(directory: Path | None = None, kind: str = "impact") -> list[Path]:
    """The verification case files of one case kind (impact: DEM; sph_flow: SPH), sorted by name."""

    directory = Path(directory) if directory is not None else verification_dir()
    if not directory.is_dir():
        what = "does not exist" if not directory.exists() else "is not a directory"
        raise OrchestratorError(f"--cases {directory} {what}; give a directory of case files (*.toml), e.g. "
                                "cases/verification")
    files = []
    for path in sorted(directory.glob("*.toml")):
        try:  # read_toml_file refuses FIFOs, devices and oversized files before reading anything
            meta = read_toml_file(path, "case").get("case", {})
            file_kind = meta.get("kind") if isinstance(meta, dict) else kind
        except CaseError:
            file_kind = kind  # let the case loader report what is wrong with it
        if file_kind == kind:
            files.append(path)
    if not files:
        raise OrchestratorError(f"no {kind} case files (*.toml) in {directory}")
    return files


def load_scenes(files: list[Path], overrides=(), preset: str | None = None) -> None:
    """Validate every scene with the overrides before any run starts (CaseError naming the file and key)."""

    for path in files:
        load_case(path, preset=preset, overrides=overrides)


def dem_engines(requested=None) -> list[str]:
    """Engines that run impact cases: the requested ones (each must be installed), or every installed one.

    Raises EngineNotFound for a requested engine that is missing and
    OrchestratorError for one that cannot run impact cases.
    """
    if requested:
        out = []
        for name in requested:
            if name not in engine_names():
                raise OrchestratorError(f"unknown engine {name!r}; allowed: {', '.join(engine_names())}")
            if name not in dem_engine_names():
                raise OrchestratorError(f"{name} does not run DEM impact scenes; DEM engines: "
                                        f"{', '.join(dem_engine_names())}")
            get_engine(name).check_available()
            out.append(name)
        return list(dict.fromkeys(out))
    return [name for name in dem_engine_names() if get_engine(name).available()]


def dem_engine_names() -> list[str]:
    """Every registered engine that runs impact cases, installed or not."""
    return engines_for_kind("impact")


@dataclass
class SceneRun(CheckedRun):
    """One DEM scene on one engine: its rows, status and the curves to plot."""

    time: object = None  # (n,) s
    normal_force: object = None  # (n,) N
    peaks: object = None  # (k, 2): peak time s, peak force N of each contact


def run_scene(case_file: Path, engine: str, out_dir: Path, overrides=(), timeout_s: float | None = 600.0) -> SceneRun:
    """Run one verification scene on one engine and check it (never raises for a failed run)."""
    import numpy as np

    loaded = load_case(case_file, overrides=overrides)
    run_dir = Path(out_dir)
    status, message = "ok", ""
    try:
        summary = run_case(loaded, engine=engine, out_dir=run_dir, timeout_s=timeout_s, progress=False, force=True)
        measured, wall = summary.measured, summary.wall_time_s
    except EngineNotFound:
        raise
    except OrchestratorError as exc:
        summary = exc.summary
        status = summary.status if summary is not None else "failed"
        message = str(exc).split("\n")[0]
        measured = summary.measured if summary is not None else {}
        wall = summary.wall_time_s if summary is not None else math.nan
    result = SceneRun(loaded.name, engine, status, message, run_dir, wall_time_s=wall)
    try:
        run = read_run(run_dir)
    except OrchestratorError:
        run = {"attrs": {}}
    deviation = run["attrs"].get("deviation", "")
    for check in evaluate_checks(loaded.model, measured):
        passed = check.passed and status == "ok"
        note = message if status != "ok" else check.note or (f"{engine}: {deviation}" if not passed and deviation
                                                              else "")
        result.rows.append({"scene": loaded.name, "engine": engine, "quantity": check.quantity, "value": check.value,
                            "expected": check.expected, "rel_error": check.rel_error, "tolerance": check.tolerance,
                            "passed": bool(passed), "source": check.source, "note": note})
    series = run.get("series", {})
    if "normal_force" in series:
        result.time, result.normal_force = series["time"], series["normal_force"]
    events = run.get("events", {})
    if "peak_time" in events:
        result.peaks = np.column_stack([events["peak_time"], events["peak_normal_force"]])
    return result


def dem_verification(engines=None, cases_dir=None, overrides=(), timeout_s: float | None = 600.0,
                     name: str = "verify-dem") -> Workflow:
    """The Workflow of every scene in cases_dir on every engine, run directories <folder>/<scene>/<engine>.

    engines: names (default: every installed DEM engine, the reference included); overrides: --set strings applied
    to every scene (e.g. numerics.timestep_factor=0.1); timeout_s: wall-time limit of each run, s.
    """
    files = scene_files(cases_dir)
    names: list[str] = []

    def prepare():
        load_scenes(files, overrides)
        names[:] = dem_engines(engines)

    def jobs(folder: Path):
        return [(run_scene, (path, engine, folder / path.stem / engine, overrides, timeout_s))
                for path in files for engine in names]

    return Workflow(name, jobs, prepare)


def run_verification(engines=None, out_dir=None, cases_dir=None, overrides=(), workers: int | None = None,
                     timeout_s: float | None = 600.0, on_done=None) -> list[SceneRun]:
    """Run dem_verification (see there) into out_dir; workers: parallel runs (default: the number of cores);
    on_done(run, done, total) as each run finishes. Returns the SceneRuns in the order scene x engine."""
    return dem_verification(engines, cases_dir, overrides, timeout_s).run(out_dir, workers, on_done)[1]


def default_out_dir(root: Path = Path("runs"), suite: str = "dem") -> Path:
    """runs/verify-<suite>-<UTC timestamp> (humanize.stamped_dir)."""
    return stamped_dir(f"verify-{suite}", root)


def format_table(runs: list[SceneRun], unit_of=None) -> str:
    """base.format_table with the impact quantities' units by default."""
    return base_table(runs, unit_of or (lambda quantity: QUANTITIES.get(quantity, ("",))[0]))


