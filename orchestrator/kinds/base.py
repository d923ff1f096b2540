"""What a process kind is: its case model, scene builder, analysis and the adapters of the engines that run it.

A kind lives in one folder, orchestrator/kinds/<kind>/, whose __init__ defines ``KIND = Kind(...)``; the folder holds
the case model (case.py), the scene builder (scene.py), its quantities and analysis, one adapter module per engine
that runs it with that engine's template beside it (templates/<engine>.*.j2), and its verification scenes. Which
engines run a kind is answered by ``Kind.adapters`` alone.

An Adapter is stateless: every method receives the engine (its profile: executable, threads, MPI ranks, see
orchestrator.engines) and the scene, and keeps nothing between calls.
"""

from __future__ import annotations

import abc
import importlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

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

    def check_scene(self, engine, scene) -> None:
        """Raise OrchestratorError for a scene this engine cannot run (before anything is written)."""

    @abc.abstractmethod
    def write_input(self, engine, scene, workdir: Path) -> None:
        """Write every input file the engine needs into workdir."""

    @abc.abstractmethod
    def command(self, engine, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        """The command line and the extra environment that run the engine in workdir."""

    @abc.abstractmethod
    def read_output(self, engine, scene, workdir: Path):
        """Parse what the engine wrote (complete or partial) into an engines.base.Result."""

    def planned_steps(self, engine, scene) -> int:
        """Upper bound of the run's time steps (0: unknown, no timing probe)."""
        return 0

    def wants_probe(self, engine, scene) -> bool:
        """True when the run is long enough to start with a timing probe: by default, more than PROBE_ABOVE_STEPS
        planned steps (an adapter whose cost lies in its particles rather than its steps says otherwise)."""
        return self.planned_steps(engine, scene) > PROBE_ABOVE_STEPS

    def probe_command(self, engine, scene, workdir: Path, steps: int = 200) -> tuple[list[str], dict[str, str]]:
        """Command of a timing probe (a few steps on a dense lattice) in workdir; only asked when planned_steps is
        large."""
        raise OrchestratorError(f"{self.engine} has no timing probe for this kind")

    def resume_input(self, engine, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
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


def _load(spec: str):
    """'package.module:Name' -> the object (imported on first use)."""
    module, _, name = spec.partition(":")
    return getattr(importlib.import_module(module), name)


@dataclass(frozen=True)
class Kind:
    """A process kind (see the module docstring). Callables are 'module:name' strings, imported on first use.

    name: case.kind in case files; case_model: the pydantic model of its case files; build_scene(case) -> scene;
    measure(case, result) -> {quantity: SI value}; analyze(run_dir, run, case, render) -> {name: path} (prints the
    kind's table, draws its pictures); adapters: engine name -> 'module:AdapterClass'; refusals: engine name ->
    'module:function(scene) -> message' for engines that have no adapter but can say why (e.g. the reference DEM and
    a drag-finishing bowl); description: one line for help texts; study_pictures: 'module:function(rows, quantity,
    reference, tolerance) -> [{"title": str, "note": str, "png": bytes}]' drawing the kind's sections of a study
    report (rows: the study's index rows, run_dir pointing at each run; quantity: the compared column; reference:
    the reference row or None; tolerance: relative error accepted), empty when the kind has none.
    """

    name: str
    case_model: str
    build_scene: str
    measure: str
    analyze: str
    adapters: dict[str, str]
    refusals: dict[str, str] = field(default_factory=dict)
    description: str = ""
    study_pictures: str = ""

    def engines(self) -> list[str]:
        """Names of the engines that run this kind (those with an adapter), sorted."""
        return sorted(self.adapters)

    def model(self):
        """The case model class."""
        return _load(self.case_model)

    def scene(self, case):
        """The scene built from a validated case model."""
        return _load(self.build_scene)(case)

    def measured(self, case, result) -> dict[str, float]:
        """The case's measured quantities from a Result (SI units)."""
        return _load(self.measure)(case, result)

    def analysis(self, run_dir, run: dict, case, render: bool) -> dict:
        """Print the kind's comparison of a stored run and draw its pictures; returns {name: path}."""
        return _load(self.analyze)(run_dir, run, case, render)

    def draw_study_pictures(self, rows: list[dict], quantity: str, reference: dict | None,
                            tolerance: float) -> list[dict]:
        """The kind's sections of a study report (see study_pictures); [] when it declares none."""
        return _load(self.study_pictures)(rows, quantity, reference, tolerance) if self.study_pictures else []

    def adapter(self, engine: str, scene=None) -> Adapter:
        """The adapter of engine for this kind; OrchestratorError (naming the engines that do run it) otherwise."""
        if engine in self.adapters:
            return _load(self.adapters[engine])()
        if scene is not None and engine in self.refusals:
            raise OrchestratorError(_load(self.refusals[engine])(scene))
        raise OrchestratorError(f"the {engine} engine does not run {self.name} cases; use --engine "
                                f"{' or '.join(self.engines())}")


@dataclass(frozen=True)
class Bound:
    """An adapter bound to an engine: the adapter's steps with the engine filled in (what run.py drives)."""

    engine: Any
    adapter: Adapter

    def check_scene(self, scene) -> None:
        """See Adapter.check_scene."""
        self.adapter.check_scene(self.engine, scene)

    def write_input(self, scene, workdir: Path) -> None:
        """See Adapter.write_input."""
        self.adapter.write_input(self.engine, scene, Path(workdir))

    def command(self, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        """See Adapter.command."""
        return self.adapter.command(self.engine, scene, Path(workdir))

    def read_output(self, scene, workdir: Path):
        """See Adapter.read_output."""
        return self.adapter.read_output(self.engine, scene, Path(workdir))

    def planned_steps(self, scene) -> int:
        """See Adapter.planned_steps."""
        return self.adapter.planned_steps(self.engine, scene)

    def wants_probe(self, scene) -> bool:
        """See Adapter.wants_probe (False when the adapter has no probe)."""
        return self.adapter.probes and self.adapter.wants_probe(self.engine, scene)

    def probe_command(self, scene, workdir: Path, steps: int = 200):
        """See Adapter.probe_command."""
        return self.adapter.probe_command(self.engine, scene, Path(workdir), steps)

    def resume_input(self, scene, workdir: Path):
        """See Adapter.resume_input."""
        return self.adapter.resume_input(self.engine, scene, Path(workdir))
