"""A study file (TOML): one case, engines, and a sweep of case parameters.

    [study]
    name = "stiffness"
    case = "../drag_finishing_uhlmann2015.toml"   # relative to the study file
    preset = "quick"                              # optional
    engines = ["yade"]
    timeout = 3600                                # s per run, optional
    mpi_ranks = 2                                 # MPI ranks per run (lammps, liggghts), optional
    description = "..."                           # shown in the report, optional

    [sweep]
    mode = "grid"            # grid: every combination; zip: i-th values together; list: explicit runs
    [sweep.parameters]
    "numerics.stiffness_scale" = [1e-3, 1e-4]
    "numerics.timestep_factor" = [0.1, 0.3]

    # mode = "list":
    # [[sweep.runs]]
    # "media.count" = 500
"""

from __future__ import annotations

import itertools
import math
from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from orchestrator.case.loader import format_validation_error, read_toml_file
from orchestrator.errors import CaseError

#: Most runs one study may plan: every point is loaded, validated and hashed before the first run starts, so a
#: larger sweep is refused before anything is built (split it into several studies).
MAX_STUDY_POINTS = 10_000


class _Frozen(BaseModel):
    model_config = ConfigDict(frozen=True, extra="forbid", allow_inf_nan=False)


class StudyMeta(_Frozen):
    """The [study] table."""

    name: str = Field(min_length=1, pattern=r"^[A-Za-z0-9_.-]+$")
    case: Path = Field(description="case file, relative to the study file")
    preset: str | None = None
    engines: tuple[str, ...] = Field(("yade",), min_length=1)
    timeout: float | None = Field(None, gt=0, description="wall-time limit per run, s")
    mpi_ranks: int | None = Field(None, ge=1, description="MPI ranks per run (engines that run under MPI: lammps, "
                                  "liggghts); default: the engine's own (1, or $ORCHESTRATOR_<ENGINE>_MPI)")
    description: str = Field("", description="what the study does and how it departs from the case (shown in the report)")


class Sweep(_Frozen):
    """The [sweep] table: which case values vary, and how they combine."""

    mode: Literal["grid", "zip", "list"] = "grid"
    parameters: dict[str, list[Any]] = Field(default_factory=dict)
    runs: list[dict[str, Any]] = Field(default_factory=list)

    @model_validator(mode="after")
    def _shape(self):
        if self.mode == "list":
            if not self.runs:
                raise ValueError("sweep.runs is empty; allowed: one or more [[sweep.runs]] tables of KEY = VALUE")
            if self.parameters:
                raise ValueError("sweep.parameters goes with mode grid or zip, not list; use [[sweep.runs]]")
            return self
        if self.runs:
            raise ValueError(f"sweep.runs goes with mode = \"list\", not {self.mode!r}")
        if not self.parameters:
            raise ValueError("sweep.parameters is empty; allowed: \"a.b\" = [value, ...] for each varied case value")
        for key, values in self.parameters.items():
            if not values:
                raise ValueError(f"sweep.parameters.\"{key}\" is an empty list; give at least one value")
        if self.mode == "zip":
            lengths = {key: len(v) for key, v in self.parameters.items()}
            if len(set(lengths.values())) > 1:
                raise ValueError(f"mode = \"zip\" needs lists of equal length; got {lengths}")
        return self

    def size(self) -> int:
        """The number of runs the sweep describes (computed without building them)."""
        if self.mode == "list":
            return len(self.runs)
        lengths = [len(values) for values in self.parameters.values()]
        return lengths[0] if self.mode == "zip" else math.prod(lengths)

    def check_size(self) -> None:
        """Raise CaseError naming MAX_STUDY_POINTS and the sweep's axes when it describes more runs."""
        size = self.size()
        if size <= MAX_STUDY_POINTS:
            return
        if self.mode == "list":
            axes = f"{size:,} [[sweep.runs]] tables"
        else:
            joiner = " x " if self.mode == "grid" else " zipped with "
            axes = f"mode {self.mode}: " + joiner.join(f"{key} ({len(values):,} values)"
                                                       for key, values in self.parameters.items())
        raise CaseError(f"the sweep has {size:,} runs ({axes}); a study holds at most {MAX_STUDY_POINTS:,} "
                        "(MAX_STUDY_POINTS): split it into smaller studies")

    def points(self) -> list[dict[str, Any]]:
        """Each run's overrides {dotted key: value}, in a stable order (CaseError beyond MAX_STUDY_POINTS)."""
        self.check_size()
        if self.mode == "list":
            return [dict(run) for run in self.runs]
        keys = list(self.parameters)
        if self.mode == "zip":
            return [dict(zip(keys, values)) for values in zip(*self.parameters.values())]
        return [dict(zip(keys, values)) for values in itertools.product(*self.parameters.values())]


class StudySpec(_Frozen):
    """A validated study file."""

    study: StudyMeta
    sweep: Sweep


def load_study_spec(path: str | Path) -> tuple[StudySpec, Path]:
    """Read and validate a study file; returns (spec, absolute case path). Raises CaseError with clear messages."""

    path = Path(path)
    raw = read_toml_file(path, "study")
    try:
        spec = StudySpec.model_validate(raw)
    except ValidationError as exc:
        raise CaseError(f"{path}: invalid study\n" + format_validation_error(exc, StudySpec)) from None
    try:
        spec.sweep.check_size()
    except CaseError as exc:
        raise CaseError(f"{path}: {exc}") from None
    case_path = spec.study.case if spec.study.case.is_absolute() else path.parent / spec.study.case
    if case_path.is_dir():
        raise CaseError(f"{path}: study.case = {str(spec.study.case)!r}: {case_path} is a directory; give a case file")
    if not case_path.is_file():
        raise CaseError(f"{path}: study.case = {str(spec.study.case)!r}: case file not found at {case_path}")
    return spec, case_path.resolve()
