"""Study: a sweep of one case over parameters and engines, with cached,
resumable runs.

A run's identity (orchestrator.identity) is sha256 of the resolved case, the engine, its version, its MPI
ranks and the rendered engine input files; its directory is <study dir>/<engine>-<id[:12]>. A run whose run.h5
has status ok and the same identity is reused; a failed, interrupted or
changed one is run again. Runs go to any concurrent.futures.Executor (a local
process pool by default, sized so runs never oversubscribe the cores: cores / (threads x MPI ranks) runs at once).
"""

from __future__ import annotations

import csv
import json
import os
import shutil
from concurrent.futures import Executor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from orchestrator import signals
from orchestrator.case import load_case
from orchestrator.engines import engine_names, get_engine
from orchestrator.errors import CaseError, OrchestratorError
from orchestrator.humanize import check_out_dir
from orchestrator.identity import run_identity
from orchestrator.kinds import bind, build_scene, engines_for_kind
from orchestrator.measure import remeasure
from orchestrator.run import run_case
from orchestrator.runh5 import read_run
from orchestrator.study.spec import Sweep, load_study_spec
from orchestrator.workflows.base import Workflow

INDEX_NAME = "index.csv"


@dataclass(frozen=True)
class PlannedRun:
    """One run of a study: engine, the sweep point's overrides, identity and directory."""

    run_id: str
    engine: str
    point: dict[str, Any]
    run_dir: Path
    threads: int
    mpi_ranks: int = 1


#: What a study directory says about itself (name, kind, description, case, preset, engines), for its report.
STUDY_INFO = "study.json"


@dataclass
class Study:
    """A sweep of `case` over `points` (dicts of dotted case keys -> values) on `engines`.

    Build one from a study file with Study.from_file, or directly::

        Study("cases/drag_finishing_uhlmann2015.toml", preset="quick",
              points=grid({"numerics.stiffness_scale": [1e-3, 1e-4]}), out_dir="runs/studies/e")
    """

    case: Path
    points: list[dict[str, Any]]
    engines: tuple[str, ...] = ("yade",)
    preset: str | None = None
    out_dir: Path | None = None
    name: str = "study"
    timeout_s: float | None = None
    description: str = ""
    mpi_ranks: int | None = None
    _planned: list[PlannedRun] = field(default_factory=list, init=False, repr=False)
    _kind: str = field(default="", init=False, repr=False)

    def __post_init__(self):
        self.case = Path(self.case).resolve()
        self.out_dir = Path(self.out_dir) if self.out_dir is not None else Path("runs") / "studies" / self.name
        if not self.points:
            raise CaseError("the study has no runs: its sweep is empty")

    @classmethod
    def from_file(cls, path, out_dir=None) -> "Study":
        """A Study from a study TOML file (see orchestrator.study.spec)."""

        spec, case_path = load_study_spec(path)
        return cls(case=case_path, points=spec.sweep.points(), engines=spec.study.engines, preset=spec.study.preset,
                   out_dir=out_dir, name=spec.study.name, timeout_s=spec.study.timeout,
                   description=spec.study.description, mpi_ranks=spec.study.mpi_ranks)

    def plan(self) -> list[PlannedRun]:
        """Validate every run's case and engine, and compute identities (raises CaseError / OrchestratorError)."""

        planned = []
        for engine in self.engines:
            if engine not in engine_names():
                raise OrchestratorError(f"study engine {engine!r} is unknown; allowed: {', '.join(engine_names())}")
        cases = []
        for i, point in enumerate(self.points):
            overrides = [f"{key}={_toml_value(value)}" for key, value in point.items()]
            try:
                cases.append(load_case(self.case, preset=self.preset, overrides=overrides))
            except CaseError as exc:
                raise CaseError(f"study run {i + 1} ({_describe(point)}): {exc}") from None
        _check_engines_run(self.engines, cases, self.case)
        self._kind = cases[0].kind
        versions, ranks = {}, {}
        options = {} if self.mpi_ranks is None else {"mpi_ranks": self.mpi_ranks}
        for engine in self.engines:
            profile = _study_engine(engine, options)
            profile.check_available()
            versions[engine], ranks[engine] = profile.version(), int(getattr(profile, "mpi_ranks", 1))
        for point, loaded in zip(self.points, cases):
            scene = _build_scene(loaded)
            for engine in self.engines:
                bound = bind(loaded.kind, engine, scene, **options)
                run_id = run_identity(loaded, engine, versions[engine], bound, scene)
                planned.append(PlannedRun(run_id, engine, dict(point), self.out_dir / f"{engine}-{run_id[:12]}",
                                          loaded.model.numerics.threads, ranks[engine]))
        self._planned = planned
        return planned

    def run(self, executor: Executor | None = None, force: bool = False, progress: bool = True,
            max_workers: int | None = None) -> list[dict]:
        """Run what is not finished yet (everything with force); returns one row per run and writes index.csv."""

        check_out_dir(self.out_dir)
        planned = self.plan()  # validates every run before the folder is made
        rows: dict[str, dict] = {}
        todo: list[PlannedRun] = []
        bar = None

        def jobs(folder: Path):
            nonlocal bar
            (folder / STUDY_INFO).write_text(json.dumps(
                {"name": self.name, "kind": self._kind, "description": self.description, "case": str(self.case),
                 "preset": self.preset, "engines": list(self.engines)}, indent=1))
            for run in planned:
                done = None if force else finished_row(run)
                if done is not None:
                    rows[run.run_id] = {**done, "reused": True}
                else:
                    todo.append(run)
            bar = _bar(len(planned), len(rows), progress, self.name)
            return [(execute_run, (str(self.case), self.preset, r.point, r.engine, str(r.run_dir), self.timeout_s,
                                   r.run_id, self.mpi_ranks)) for r in todo]

        def on_done(row, _done, _total):
            rows[row["run_id"]] = {**row, "reused": False}
            self._write_index(planned, rows)
            if bar is not None:
                failed = sum(1 for item in rows.values() if item["status"] != "ok")
                bar.set_postfix_str(f"failed {failed}", refresh=False)
                bar.update(1)

        own_pool = executor is None
        cores_per_run = max((r.threads * r.mpi_ranks for r in planned), default=1)
        workers = max_workers or max(1, (os.cpu_count() or 1) // cores_per_run)
        try:
            Workflow(self.name, jobs).run(self.out_dir, workers, on_done, executor,
                                                   signals.install_in_worker if own_pool else None)
        except KeyboardInterrupt as exc:
            finished = (f"{self.out_dir / INDEX_NAME} lists the {len(rows)} runs finished or reused before it"
                        if rows else "no run of the study had finished")
            exc.kept = (f"{finished}; the stopped runs keep their run.h5 (status terminated) and run again when the "
                        "study is run again")
            raise
        finally:
            if bar is not None:
                bar.close()
        self._write_index(planned, rows)
        return [rows[r.run_id] for r in planned if r.run_id in rows]

    def _write_index(self, planned: list[PlannedRun], rows: dict[str, dict]) -> None:
        ordered = [rows[r.run_id] for r in planned if r.run_id in rows]
        write_index(self.out_dir / INDEX_NAME, ordered)

    def results(self):
        """The study's index: a pandas DataFrame when pandas is installed, else a numpy structured array."""
        return read_index(self.out_dir, as_frame=True)


def _build_scene(loaded):
    """The scene of a planned run (its engine inputs decide the run's identity)."""
    try:
        return build_scene(loaded.model)
    except ValueError as exc:
        raise OrchestratorError(f"cannot build the scene of {loaded.name}: {exc}") from None


def _study_engine(engine: str, options: dict):
    """The study engine's profile with the study's options (its MPI ranks); OrchestratorError naming the study key
    when the engine does not run under MPI."""
    try:
        return get_engine(engine, **options)
    except OrchestratorError as exc:
        if "mpi_ranks" not in options:
            raise
        raise OrchestratorError(f"study.mpi_ranks = {options['mpi_ranks']}: {str(exc).split(': ', 1)[-1]} (leave "
                                "mpi_ranks out, or run the MPI engines in a study of their own)") from None


def _check_engines_run(engines, cases, case_path: Path) -> None:
    """Raise OrchestratorError when a study engine does not run the kind of the study's case."""
    for kind in dict.fromkeys(loaded.kind for loaded in cases):
        allowed = engines_for_kind(kind)
        wrong = [engine for engine in engines if engine not in allowed]
        if wrong:
            default = " (the default when [study] gives no engines)" if tuple(engines) == ("yade",) else ""
            raise OrchestratorError(
                f"study.engines = {json.dumps(list(engines))}{default}: {', '.join(wrong)} does not run {kind} cases "
                f"such as {case_path.name}; allowed: {', '.join(allowed)}; e.g. engines = {json.dumps(allowed)} in "
                "[study]")


def grid(parameters: dict[str, list]) -> list[dict]:
    """Every combination of the given values (dotted case keys -> lists)."""

    return Sweep(mode="grid", parameters=parameters).points()


def zipped(parameters: dict[str, list]) -> list[dict]:
    """The i-th values of each list together (lists of equal length)."""

    return Sweep(mode="zip", parameters=parameters).points()


def execute_run(case_path: str, preset: str | None, point: dict, engine: str, run_dir: str,
                timeout_s: float | None, run_id: str, mpi_ranks: int | None = None) -> dict:
    """Run one study point (in a worker process; timeout_s in s, mpi_ranks None: the engine's default); returns its
    row. Never raises for a failed run."""

    run_path = Path(run_dir)
    if run_path.exists():
        shutil.rmtree(run_path)  # an interrupted or changed run starts clean
    overrides = [f"{key}={_toml_value(value)}" for key, value in point.items()]
    base = {"run_id": run_id, "engine": engine, "run_dir": run_dir, **{f"param:{k}": v for k, v in point.items()}}
    try:
        with signals.task():
            loaded = load_case(case_path, preset=preset, overrides=overrides)
            summary = run_case(loaded, engine=engine, out_dir=run_path, timeout_s=timeout_s, progress=False,
                               force=True, extra_attrs={"run_id": run_id}, mpi_ranks=mpi_ranks)
    except OrchestratorError as exc:
        summary = exc.summary
        if summary is None:
            return {**base, "status": "failed", "message": str(exc).splitlines()[0]}
    return {**base, **_summary_row(summary)}


def finished_row(run: PlannedRun) -> dict | None:
    """The row of a finished run with the same identity, or None if it must run (again)."""
    import h5py

    path = run.run_dir / "run.h5"
    if not path.is_file():
        return None
    try:
        with h5py.File(path, "r") as h5:
            attrs = dict(h5.attrs)
            measured = dict(h5["measured"].attrs) if "measured" in h5 else {}
    except OSError:
        return None
    if attrs.get("status") != "ok" or attrs.get("run_id") != run.run_id:
        return None
    row = {"run_id": run.run_id, "engine": run.engine, "run_dir": str(run.run_dir),
           **{f"param:{k}": v for k, v in run.point.items()}, "status": "ok", "message": "",
           "wall_time_s": float(attrs["wall_time_s"]), "n_steps": int(attrs["n_steps"]),
           "n_particles": int(attrs["n_particles"]), "dt": float(attrs["dt"])}
    row.update({k: _plain(v) for k, v in measured.items()})
    row.update(_fresh_measures(path))
    return row


def _fresh_measures(path: Path) -> dict:
    """A reused run's quantities recomputed by the current analysis (a new measure needs no rerun);
    empty when the stored run cannot be re-read, and the stored values stand."""

    try:
        return remeasure(read_run(path))
    except (OrchestratorError, KeyError, ValueError):
        return {}


def _summary_row(summary) -> dict:
    return {"status": summary.status, "message": summary.message, "wall_time_s": summary.wall_time_s,
            "n_steps": summary.n_steps, "n_particles": summary.n_particles, "dt": summary.dt, **summary.measured}


def write_index(path: Path, rows: list[dict]) -> None:
    """One CSV row per run (written to a temporary name, then renamed)."""
    columns: list[str] = []
    for row in rows:
        columns += [key for key in row if key not in columns]
    tmp = path.with_name(path.name + ".tmp")
    with open(tmp, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=columns)
        writer.writeheader()
        writer.writerows(rows)
    os.replace(tmp, path)


def read_index_rows(study_dir) -> list[dict]:
    """A study's index.csv as a list of dicts (column -> text).

    Raises OrchestratorError naming the file when there is none, or it is not a text CSV written by a study
    (binary, not UTF-8, NUL bytes, malformed, or without the columns run_id, engine and status).
    """
    path = Path(study_dir) / INDEX_NAME
    if not path.is_file():
        raise OrchestratorError(f"no {INDEX_NAME} in {study_dir}; give a study directory written by 'orchestrator "
                                "study' (run the study first: orchestrator study STUDY.toml)")
    try:
        with open(path, newline="", encoding="utf-8") as fh:
            rows = list(csv.DictReader(fh))
    except UnicodeDecodeError:
        raise OrchestratorError(f"{path} is not a text file (not UTF-8); it is not an index written by "
                                "'orchestrator study': run the study again to rewrite it") from None
    except (csv.Error, ValueError) as exc:
        raise OrchestratorError(f"{path} is not a readable CSV ({exc}); run the study again to rewrite it") from None
    except OSError as exc:
        raise OrchestratorError(f"cannot read {path}: {exc.strerror or exc}") from None
    missing = [c for c in ("run_id", "engine", "status") if rows and c not in rows[0]]
    if missing:
        raise OrchestratorError(f"{path} has no column {missing[0]!r}; it is not an index written by "
                                "'orchestrator study': run the study again to rewrite it")
    return rows


def read_index(study_dir, as_frame: bool = True):
    """A study's index.csv as a DataFrame (pandas installed and as_frame) or a numpy structured array."""
    import numpy as np

    path = Path(study_dir) / INDEX_NAME
    if not path.is_file():
        raise OrchestratorError(f"no {INDEX_NAME} in {study_dir}; run the study first (orchestrator study STUDY.toml)")
    if as_frame:
        try:
            import pandas as pd

            return pd.read_csv(path)
        except ImportError:
            pass
    return np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8")


def _toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    return repr(value)


def _describe(point: dict) -> str:
    return ", ".join(f"{k}={v}" for k, v in point.items())


def _plain(value):
    return value.item() if hasattr(value, "item") else value


def _bar(total: int, done: int, enabled: bool, name: str):
    if not enabled:
        return None
    from tqdm import tqdm

    return tqdm(total=total, initial=done, desc=f"study {name}", unit="run")
