"""`orchestrator verify <suite>`: the verification scenes of a suite on its engines, checked against closed forms,
series solutions and measurements.

A suite is what the kinds declare (kinds.base.Verification, as pytest's plug-ins implement its hooks): each kind
that takes part names the suite, how a run of one of its scenes becomes check rows (the one row format of
workflows.base.ROW_KEYS) and the units of the checked quantities; the kind that owns the suite adds its picture,
its description, its default timeout and, if any, the case key a time-step sweep varies. This module loops over
the kinds and names none. A suite's scenes are the case files of its kinds in the shipped cases/<folder>, or in a
folder of the owning kind's package (Verification.cases; --cases another folder); each runs on every installed
engine of its kind (or the requested ones), one run per scene and engine (or per point of the scene's own sweep),
in parallel; a run that ends unstable or failed gives failing rows with the reason.
"""

from __future__ import annotations

import importlib.util
import math
import os
from dataclasses import dataclass
from pathlib import Path

from orchestrator.case import load_case
from orchestrator.case.loader import read_toml_file, shipped_cases
from orchestrator.engines import engine_names, get_engine
from orchestrator.errors import CaseError, EngineNotFound, OrchestratorError
from orchestrator.humanize import stamped_dir
from orchestrator.kinds import get_kind, kind_names
from orchestrator.kinds.base import Adapter, Verification, unit_in
from orchestrator.run import run_case
from orchestrator.runh5 import read_run
from orchestrator.workflows.base import CheckedRun, Workflow
from orchestrator.workflows.base import format_table as base_table


@dataclass(frozen=True)
class Suite:
    """A verification suite: its name, the kinds that take part ({kind: Verification}) and the owner's
    declaration (picture, description, timeout_s, timestep_key, cases)."""

    name: str
    members: dict[str, Verification]
    owner: str

    @property
    def declared(self) -> Verification:
        """The owner's Verification."""
        return self.members[self.owner]

    def engines(self) -> list[str]:
        """Every engine that runs one of the suite's kinds, sorted (installed or not)."""
        return sorted({engine for kind in self.members for engine in get_kind(kind).engines()})

    def unit_of(self, quantity: str) -> str:
        """SI unit of a checked quantity ('u_profile(t=0.1 s)' -> 'm/s'; '' when no kind says)."""
        for verification in self.members.values():
            unit = unit_in(verification.units.load(), quantity)
            if unit:
                return unit
        return ""


def suites() -> dict[str, Suite]:
    """Every suite the registered kinds declare, by name (sorted). A suite must have exactly one owner."""
    members: dict[str, dict[str, Verification]] = {}
    for name in kind_names():
        verification = get_kind(name).verification
        if verification is not None:
            members.setdefault(verification.suite, {})[name] = verification
    out = {}
    for suite, kinds in sorted(members.items()):
        owners = [kind for kind, v in kinds.items() if v.owns_suite]
        if len(owners) != 1:
            raise OrchestratorError(f"the verification suite {suite!r} needs exactly one kind that owns it (gives its "
                                    f"picture); owners: {', '.join(owners) or 'none'}")
        out[suite] = Suite(suite, kinds, owners[0])
    return out


def get_suite(name: str) -> Suite:
    """The suite registered under name (OrchestratorError naming the suites otherwise)."""
    known = suites()
    if name not in known:
        raise OrchestratorError(f"unknown verification suite {name!r}; allowed: {', '.join(known)}")
    return known[name]


def suite_cases(declared: Verification) -> Path:
    """The folder of a suite's scenes (Verification.cases): cases/<folder> shipped with the package, or the folder
    of a 'package:folder' reference inside that importable package (OrchestratorError when it has none)."""
    package, sep, folder = declared.cases.rpartition(":")
    if not sep:
        return shipped_cases(folder)
    spec = importlib.util.find_spec(package)
    if spec is None or not spec.submodule_search_locations:
        raise OrchestratorError(f"the scenes of the verification suite {declared.suite!r} ({declared.cases}): "
                                f"{package} is not an importable package")
    return Path(list(spec.submodule_search_locations)[0]) / folder


def scene_files(suite: Suite, directory: Path | None = None) -> list[Path]:
    """The suite's scenes in directory (default the suite's own, suite_cases): the case files of its kinds, sorted
    by name. The owner's kind must have some; the other kinds' are optional."""
    directory = Path(directory) if directory is not None else suite_cases(suite.declared)
    if not directory.is_dir():
        what = "does not exist" if not directory.exists() else "is not a directory"
        raise OrchestratorError(f"--cases {directory} {what}; give a directory of case files (*.toml), e.g. "
                                "cases/verification")
    files = {kind: [] for kind in suite.members}
    for path in sorted(directory.glob("*.toml")):
        try:  # read_toml_file refuses FIFOs, devices and oversized files before reading anything
            meta = read_toml_file(path, "case").get("case", {})
            file_kind = meta.get("kind") if isinstance(meta, dict) else suite.owner
        except CaseError:
            file_kind = suite.owner  # let the case loader report what is wrong with it
        if file_kind in files:
            files[file_kind].append(path)
    if not files[suite.owner]:
        raise OrchestratorError(f"no {suite.owner} case files (*.toml) in {directory}")
    return sorted((path for paths in files.values() for path in paths), key=lambda path: path.name)


def check_engines(suite: Suite, requested=None) -> list[str]:
    """The requested engine names, each registered and running the suite's scenes (OrchestratorError otherwise),
    duplicates dropped; None: the suite's default engines, else all of its engines (which of them are installed is
    asked when the runs start)."""
    engines = suite.engines()
    if not requested:
        return list(suite.declared.default_engines) or engines
    for name in requested:
        if name not in engine_names():
            raise OrchestratorError(f"unknown engine {name!r}; allowed: {', '.join(engine_names())}")
        if name not in engines:
            where = (f"the {engines[0]} engine only" if len(engines) == 1 else f"the engines {', '.join(engines)}")
            raise OrchestratorError(f"{name} does not run {suite.name.upper()} verification scenes; verify "
                                    f"{suite.name} runs on {where}")
    return list(dict.fromkeys(requested))


def installed(names: list[str], requested: bool) -> list[str]:
    """The installed engines of names: all of them must be when they were requested (EngineNotFound names the
    first missing one), and at least one otherwise."""
    if requested:
        for name in names:
            get_engine(name).check_available()
        return names
    found = [name for name in names if get_engine(name).available()]
    if not found:
        get_engine(names[0]).check_available()
    return found


def scene_runs(path: Path, overrides=(), preset: str | None = None) -> list[tuple[str, tuple[str, ...]]]:
    """(run folder, overrides) of each run of a scene: one in folder <stem>, or those its kind's runs says (e.g.
    one per frequency of a sweep), with the given overrides first."""
    model = load_case(path, preset=preset, overrides=overrides).model
    runs = get_kind(model.case.kind).verification.runs
    own = runs(model, path.stem) if runs is not None else [(path.stem, ())]
    return [(folder, (*overrides, *extra)) for folder, extra in own]


def run_scene(case_file: Path, engine: str, out_dir: Path, overrides=(), timeout_s: float | None = 600.0,
              preset: str | None = None) -> CheckedRun:
    """Run one verification scene on one engine and check it with its kind's check (never raises for a failed
    run: its rows fail, with the reason as their note)."""
    loaded = load_case(case_file, preset=preset, overrides=overrides)
    run_dir = Path(out_dir)
    status, message, wall = "ok", "", math.nan
    try:
        wall = run_case(loaded, engine=engine, out_dir=run_dir, timeout_s=timeout_s, progress=False,
                        force=True).wall_time_s
    except EngineNotFound:
        raise
    except OrchestratorError as exc:
        status = exc.summary.status if exc.summary is not None else "failed"
        message = str(exc).split("\n")[0]
        wall = exc.summary.wall_time_s if exc.summary is not None else math.nan
    result = CheckedRun(loaded.name, engine, status, message, run_dir, wall_time_s=wall)
    try:
        run = read_run(run_dir)
    except OrchestratorError:
        run = {"attrs": {}}
    check = get_kind(loaded.kind).verification.check
    try:
        result.rows, result.picture = check(loaded.model, engine, run)
    except (KeyError, IndexError, ValueError) as exc:  # a run that stopped too early to measure
        result.rows = [{"scene": loaded.name, "engine": engine, "quantity": "run", "value": None, "expected": None,
                        "rel_error": None, "tolerance": None, "passed": False, "source": "",
                        "note": f"cannot evaluate the checks: {type(exc).__name__}: {exc}"}]
    for row in result.rows:
        row["engine"] = engine
        if status != "ok":
            row["passed"], row["note"] = False, f"run {status}: {message}"
    return result


def accepting_engines(model) -> list[str]:
    """The engines of the model's kind whose adapter runs this scene: an adapter's check_scene may refuse one
    (physics the engine lacks); that pair is left out of the suite rather than run to a refusal."""
    kind = get_kind(model.case.kind)
    accepted, scene = [], None
    for engine in kind.engines():
        adapter = kind.adapter(engine)
        if type(adapter).check_scene is not Adapter.check_scene:
            scene = kind.build_scene(model) if scene is None else scene
            try:
                adapter.check_scene(get_engine(engine), scene)
            except OrchestratorError:
                continue
        accepted.append(engine)
    return accepted


def verification(suite: Suite, engines=None, cases_dir=None, overrides=(), timeout_s: float | None = None,
                 preset: str | None = None, only=None) -> Workflow:
    """The Workflow of every scene of the suite (or those whose stem is in `only`) on every engine that runs its
    kind, run directories <folder>/<run folder>/<engine> (<folder>/<run folder> when the suite has one engine).

    engines: names (default: every installed engine of the suite); overrides: --set strings applied to every
    scene (e.g. numerics.timestep_factor=0.1); timeout_s: wall-time limit of each run, s (default the suite's).
    """
    files = [path for path in scene_files(suite, cases_dir) if not only or path.stem in only]
    timeout_s = suite.declared.timeout_s if timeout_s is None else timeout_s
    names = check_engines(suite, engines)
    planned: list[tuple[Path, str, tuple, list[str]]] = []  # scene, run folder, overrides, its kind's engines
    per_engine = len(suite.engines()) > 1

    def prepare():
        planned.clear()
        for path in files:  # every run validates before anything runs
            for folder, extra in scene_runs(path, overrides, preset):
                model = load_case(path, preset=preset, overrides=extra).model
                if not getattr(model, "expected", None):
                    raise OrchestratorError(f"{path}: {model.case.name} has no [[expected]] rows: nothing to check")
                planned.append((path, folder, extra, accepting_engines(model)))

    def jobs(folder: Path):
        ready = installed(names, bool(engines))  # after the folder: a bad --out is named first
        out = []
        for path, name, extra, kind_engines in planned:
            for engine in (e for e in ready if e in kind_engines):
                where = folder / name / engine if per_engine else folder / name
                out.append((run_scene, (path, engine, where, extra, timeout_s, preset)))
        return out

    return Workflow(f"verify-{suite.name}", jobs, prepare)


def run_verification(suite: str, engines=None, out_dir=None, cases_dir=None, overrides=(), workers: int | None = None,
                     timeout_s: float | None = None, on_done=None, only=None, preset: str | None = None
                     ) -> list[CheckedRun]:
    """Run the suite's verification (see there) into out_dir; workers: parallel runs (default: the number of
    cores); on_done(run, done, total) as each run ends. Returns the CheckedRuns in the order scene x engine."""
    workflow = verification(get_suite(suite), engines, cases_dir, overrides, timeout_s, preset, only)
    return with_sweep_checks(workflow.run(out_dir, workers, on_done)[1])


def with_sweep_checks(runs: list[CheckedRun]) -> list[CheckedRun]:
    """The runs, then one CheckedRun '<scene> over its sweep' per scene and engine whose kind has a sweep_check
    (kinds.base.Verification), with the rows that need every run of the sweep (e.g. the crater's speed exponent);
    its wall time is the sweep's."""
    groups: dict[tuple[str, str], list[CheckedRun]] = {}
    for run in runs:
        groups.setdefault((run.scene, run.engine), []).append(run)
    extra = []
    for (scene, engine), group in groups.items():
        written = group[0].run_dir / "case.toml"
        if len(group) < 2 or not written.is_file():  # a run that wrote no case failed in its own rows
            continue
        loaded = load_case(written)
        check = get_kind(loaded.kind).verification.sweep_check
        if check is None:
            continue
        rows = check(loaded.model, engine, group)
        for row in rows:
            row["engine"] = engine
        status = "ok" if all(run.status == "ok" for run in group) else "failed"
        folder = Path(os.path.commonpath([run.run_dir for run in group]))
        extra.append(CheckedRun(f"{scene} over its sweep", engine, status, "", folder, rows,
                                wall_time_s=sum(run.wall_time_s for run in group)))
    return runs + extra


def default_out_dir(suite: str, root: Path = Path("runs")) -> Path:
    """runs/verify-<suite>-<UTC timestamp> (humanize.stamped_dir)."""
    return stamped_dir(f"verify-{suite}", root)


def draw(suite: str, runs: list[CheckedRun], path: Path) -> Path:
    """The suite's picture of the runs (its owner's Verification.picture) at path."""
    return get_suite(suite).declared.picture(runs, Path(path))


def format_table(runs: list[CheckedRun], suite: str) -> str:
    """workflows.base.format_table with the units of the suite's kinds."""
    return base_table(runs, get_suite(suite).unit_of)
