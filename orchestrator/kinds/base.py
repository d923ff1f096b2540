"""What a process kind is: its case model, scene builder, analysis and the adapters of the engines that run it.

A kind lives in one folder, orchestrator/kinds/<kind>/, whose __init__ defines ``KIND = Kind(...)``; the folder holds
the case model (case.py), the scene builder (scene.py), its quantities and analysis, one adapter module per engine
that runs it with that engine's template beside it (templates/<engine>.*.j2), and its verification scenes. Which
engines run a kind is answered by ``Kind.adapters`` alone.

Names, one per thing: an engine is named by its registry name (``engine``, a string: "sph", "yade"); its profile is
the object that knows the program on this machine (``profile``: executable, threads, MPI ranks; engines.get_engine);
an Adapter is how that engine runs this kind (its input files, command line and output parsing). An Adapter is
stateless: every method receives the profile and the scene and keeps nothing between calls. A BoundAdapter is an
adapter with its profile filled in (kinds.bind), what run.py drives.
"""

from __future__ import annotations

import abc
import importlib
from dataclasses import dataclass, field
from fnmatch import fnmatchcase
from pathlib import Path
from typing import Any, Callable

from orchestrator.errors import OrchestratorError


#: Runs planned longer than this many steps start with a timing probe (a few steps on a dense lattice) that estimates
#: the whole run's wall time (Adapter.wants_probe).
PROBE_ABOVE_STEPS = 200_000


class Adapter(abc.ABC):
    """How one engine runs one kind: input files, command line, output parsing (stateless).

    An abstract base: subclasses set ``engine`` (the engine's registry name) and ``templates`` (the template files this adapter renders,
    absolute paths; informative: the run identity hashes the rendered files) and implement write_input, command and
    read_output. The optional steps have safe defaults: no scene check, no timing probe (planned_steps 0), no resume.
    """

    engine = ""
    templates: tuple[Path, ...] = ()

    def check_scene(self, profile, scene) -> None:
        """Raise OrchestratorError for a scene this engine cannot run (before anything is written)."""

    @abc.abstractmethod
    def write_input(self, profile, scene, workdir: Path) -> None:
        """Write every input file the engine needs into workdir."""

    @abc.abstractmethod
    def command(self, profile, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        """The command line and the extra environment that run the engine in workdir."""

    @abc.abstractmethod
    def read_output(self, profile, scene, workdir: Path):
        """Parse what the engine wrote (complete or partial) into an engines.base.Result."""

    def planned_steps(self, profile, scene) -> int:
        """Upper bound of the run's time steps (0: unknown, no timing probe)."""
        return 0

    def wants_probe(self, profile, scene) -> bool:
        """True when the run is long enough to start with a timing probe: by default, more than PROBE_ABOVE_STEPS
        planned steps (an adapter whose cost lies in its particles rather than its steps says otherwise)."""
        return self.planned_steps(profile, scene) > PROBE_ABOVE_STEPS

    def probe_command(self, profile, scene, workdir: Path, steps: int = 200) -> tuple[list[str], dict[str, str]]:
        """Command of a timing probe (a few steps on a dense lattice) in workdir; only asked when planned_steps is
        large."""
        raise OrchestratorError(f"{self.engine} has no timing probe for this kind")

    def resume_input(self, profile, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        """Write the input that continues a stopped run in workdir from its last checkpoint; returns its command."""
        raise OrchestratorError(f"--resume: {self.engine} runs of {scene.case.case.kind} cases cannot be resumed from a "
                                "checkpoint; LIGGGHTS and Yade drag-finishing runs can (output.checkpoint_interval), and "
                                "sph runs from their last frame")

    @property
    def probes(self) -> bool:
        """True when probe_command is implemented (long runs then start with a timing probe)."""
        return type(self).probe_command is not Adapter.probe_command

    @property
    def resumable(self) -> bool:
        """True when resume_input is implemented."""
        return type(self).resume_input is not Adapter.resume_input


class Lazy:
    """A 'package.module:name' reference, imported on first use: call it (a function) or load() it (a class, a
    table). Kinds name their parts this way, so that nothing of a kind is imported until it is asked for."""

    __slots__ = ("spec",)

    def __init__(self, spec: str):
        if ":" not in spec:
            raise ValueError(f"{spec!r}: a lazy reference reads 'package.module:name'")
        self.spec = spec

    def load(self):
        """The object named (its module imported on first use)."""
        module, _, name = self.spec.partition(":")
        return getattr(importlib.import_module(module), name)

    def __call__(self, *args, **kwargs):
        return self.load()(*args, **kwargs)

    def __eq__(self, other) -> bool:
        return isinstance(other, Lazy) and other.spec == self.spec

    def __hash__(self) -> int:
        return hash(self.spec)

    def __repr__(self) -> str:
        return f"Lazy({self.spec!r})"


def lazy(spec):
    """A Lazy of a 'module:name' string (a Lazy as is; '' and None give None)."""
    if spec is None or spec == "":
        return None
    return spec if isinstance(spec, Lazy) else Lazy(spec)


@dataclass(frozen=True)
class Verification:
    """A kind's part of a verification suite, `orchestrator verify <suite>` (pytest's hooks are the model: the
    suite loops over the kinds that declare it and names none of them).

    suite: the suite's name; check: 'module:function(case, engine, run) -> (rows, picture)' (run: runh5.read_run's
    dict, {"attrs": {}} when the run left none; rows: check rows with workflows.base.ROW_KEYS plus source and note;
    picture: what the suite's picture draws of this run, a dict); units: 'module:TABLE' of the checked quantities,
    {name: unit or (unit, meaning)} (a row's quantity 'name(t=0.1 s)' or 'name[source]' takes name's);
    runs: 'module:function(case, stem) -> [(folder, overrides)]' when one scene runs several times (a frequency
    sweep), else one run in folder stem; sweep_check: 'module:function(case, engine, runs) -> rows', the rows that
    need every run of one scene's sweep on one engine (runs: its CheckedRuns in sweep order; e.g. how a crater grows
    with speed), shown as one more run of the scene. Suite-wide, given by the one kind that owns the suite: picture:
    'module:function(runs, path) -> path' (runs: workflows.base.CheckedRun with .picture); description: what the
    suite checks, for --help; timeout_s: each run's default wall-time limit, s; timestep_key: the case key that
    `verify <suite> --timestep-factors` sweeps ('' when the suite has none); cases: the folder of the scenes, a
    folder under cases/ (shipped with the package, e.g. 'verification') or 'package:folder', a folder inside an
    importable package (a kind's own folder, e.g. 'mykind:scenes'); default_engines: the engines the suite runs on
    when none is asked for (empty: every engine of its kinds; the others run with --engine, e.g. a cross-code
    check whose differences are explained in the docs).
    """

    suite: str
    check: Lazy | str
    units: Lazy | str
    runs: Lazy | str | None = None
    sweep_check: Lazy | str | None = None
    picture: Lazy | str | None = None
    description: str = ""
    timeout_s: float = 600.0
    timestep_key: str = ""
    cases: str = "verification"
    default_engines: tuple[str, ...] = ()

    def __post_init__(self):
        for name in ("check", "units", "runs", "sweep_check", "picture"):
            object.__setattr__(self, name, lazy(getattr(self, name)))

    @property
    def owns_suite(self) -> bool:
        """True for the kind that gives the suite's picture, description and defaults."""
        return self.picture is not None


@dataclass(frozen=True)
class Command:
    """A command a kind contributes to the command line: `orchestrator <name>`, or `orchestrator calibrate
    <parameter>` for a name 'calibrate <parameter>' (Kind.commands).

    help: one line for the list of commands; description: the command's --help text; add_arguments(parser): adds
    its positional arguments and options (for a calibration: to the calibrate parser, its own options only);
    run(args) -> exit code.
    """

    help: str
    description: str
    add_arguments: Callable
    run: Callable


def unit_in(table: dict, quantity: str) -> str:
    """The unit of quantity in a table {name or fnmatch pattern: unit or (unit, meaning)}: its own entry, else the
    entry of its base name ('u_profile(t=0.1 s)', 'surge_front_Z[paper]' -> 'u_profile', 'surge_front_Z'), else
    the first pattern that matches; '' when none does."""
    base = quantity.split("(")[0].split("[")[0]
    for name in (quantity, base):
        if name in table:
            entry = table[name]
            return entry if isinstance(entry, str) else entry[0]
    for pattern, entry in table.items():
        if any(c in pattern for c in "*?[") and (fnmatchcase(quantity, pattern) or fnmatchcase(base, pattern)):
            return entry if isinstance(entry, str) else entry[0]
    return ""


#: The parts of a Kind that are lazy references ('module:name' strings given, Lazy held).
LAZY_FIELDS = ("case_model", "build_scene", "measure", "analyze", "quantities", "expected", "references",
               "compare_picture", "study_pictures")


@dataclass(frozen=True)
class Kind:
    """A process kind (see the module docstring). Its parts are 'module:name' strings, held as Lazy references and
    imported on first use; a part that is a function is called under its own name (kind.build_scene(case)).

    name: case.kind in case files; case_model: the pydantic model class of its case files (kind.case_model.load());
    build_scene(case) -> scene; measure(case, result) -> {quantity: SI value}; analyze(run_dir, run, case, render)
    -> {name: path} (prints the kind's table, draws its pictures); adapters: engine name -> 'module:AdapterClass';
    refusals: engine name -> 'module:function(scene) -> message' for engines that have no adapter but can say why
    (e.g. the reference DEM and a drag-finishing bowl); description: one line for help texts.

    Capabilities, each optional (None: the kind has none), looped over by the generic layers (run, compare,
    verify, study, the command line), which name no kind:
    quantities: 'module:TABLE' of its measured quantities, {name or fnmatch pattern: (unit, meaning)} (compare's
    units; unit_in); expected(case) -> {quantity: value}: what the case predicts, e.g. closed forms (compare's
    expected column); references(case, runs) -> (title, header, cells, rows): the case's published values beside
    each engine's (runs: [(engine, measured)]; compare's table and its JSON 'references'); compare_picture(runs, case,
    path) -> path or None: the engines overlaid (runs: [(label, runh5.read_run dict)]; compare_forces.png);
    verification: its part of a suite (Verification); commands: name -> 'module:COMMAND' (a Command), the commands
    it contributes ('rheometry', 'calibrate maxwell'); study_pictures(rows, quantity, reference, tolerance) ->
    [{"title": str, "note": str, "png": bytes}]: the kind's sections of a study report (rows: the study's index
    rows, run_dir pointing at each run; quantity: the compared column; reference: the reference row or None;
    tolerance: relative error accepted); benches: engine name -> the module of the case builders that `orchestrator
    bench <engine>` runs (workflows.bench_scenes.bench_cases). Its limits (memory, steps, records) are its case
    model's validators.
    """

    name: str
    case_model: Lazy | str
    build_scene: Lazy | str
    measure: Lazy | str
    analyze: Lazy | str
    adapters: dict[str, str]
    refusals: dict[str, str] = field(default_factory=dict)
    description: str = ""
    quantities: Lazy | str | None = None
    expected: Lazy | str | None = None
    references: Lazy | str | None = None
    compare_picture: Lazy | str | None = None
    verification: Verification | None = None
    commands: dict[str, str] = field(default_factory=dict)
    study_pictures: Lazy | str | None = None
    benches: dict[str, str] = field(default_factory=dict)

    def __post_init__(self):
        for name in LAZY_FIELDS:
            object.__setattr__(self, name, lazy(getattr(self, name)))

    def engines(self) -> list[str]:
        """Names of the engines that run this kind (those with an adapter), sorted."""
        return sorted(self.adapters)

    def unit_of(self, quantity: str) -> str:
        """SI unit of one of its measured quantities ('' when the kind does not say)."""
        return unit_in(self.quantities.load(), quantity) if self.quantities is not None else ""

    def draw_study_pictures(self, rows: list[dict], quantity: str, reference: dict | None,
                            tolerance: float) -> list[dict]:
        """The kind's sections of a study report (see study_pictures); [] when it declares none."""
        return self.study_pictures(rows, quantity, reference, tolerance) if self.study_pictures else []

    def command(self, name: str) -> Command:
        """The Command the kind contributes under name (see commands)."""
        return Lazy(self.commands[name]).load()

    def adapter(self, engine: str, scene=None) -> Adapter:
        """The adapter of engine for this kind; OrchestratorError (naming the engines that do run it) otherwise."""
        if engine in self.adapters:
            return Lazy(self.adapters[engine]).load()()
        if scene is not None and engine in self.refusals:
            raise OrchestratorError(Lazy(self.refusals[engine])(scene))
        raise OrchestratorError(f"the {engine} engine does not run {self.name} cases; use --engine "
                                f"{' or '.join(self.engines())}")


@dataclass(frozen=True)
class BoundAdapter:
    """An adapter bound to an engine's profile: the adapter's steps with the profile filled in (what run.py drives;
    kinds.bind makes one)."""

    profile: Any
    adapter: Adapter

    def check_scene(self, scene) -> None:
        """See Adapter.check_scene."""
        self.adapter.check_scene(self.profile, scene)

    def write_input(self, scene, workdir: Path) -> None:
        """See Adapter.write_input."""
        self.adapter.write_input(self.profile, scene, Path(workdir))

    def command(self, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        """See Adapter.command."""
        return self.adapter.command(self.profile, scene, Path(workdir))

    def read_output(self, scene, workdir: Path):
        """See Adapter.read_output."""
        return self.adapter.read_output(self.profile, scene, Path(workdir))

    def planned_steps(self, scene) -> int:
        """See Adapter.planned_steps."""
        return self.adapter.planned_steps(self.profile, scene)

    def wants_probe(self, scene) -> bool:
        """See Adapter.wants_probe (False when the adapter has no probe)."""
        return self.adapter.probes and self.adapter.wants_probe(self.profile, scene)

    def probe_command(self, scene, workdir: Path, steps: int = 200):
        """See Adapter.probe_command."""
        return self.adapter.probe_command(self.profile, scene, Path(workdir), steps)

    def resume_input(self, scene, workdir: Path):
        """See Adapter.resume_input."""
        return self.adapter.resume_input(self.profile, scene, Path(workdir))


def print_run_measures(run_dir, run: dict, quantities: dict, width: int = 24) -> dict:
    """Print a run's header line (status, particles, steps, wall time s) and its measured quantities, names padded
    to `width` characters, with their units from quantities ({name: (unit, meaning)}); returns the measured
    quantities (SI)."""
    attrs = run["attrs"]
    measured = run.get("measured", {}).get("attrs", {})
    print(f"run {run_dir}: status {attrs['status']}, {attrs['n_particles']} particles, {attrs['n_steps']} steps, "
          f"{attrs['wall_time_s']:.1f} s")
    for name, value in measured.items():
        print(f"{name:<{width}} {value:.6g} {quantities.get(name, ('', ''))[0]}".rstrip())
    return measured
