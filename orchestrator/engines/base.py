"""What every engine shares: the Result an adapter reads back, the progress protocol, and the Engine profile base."""

from __future__ import annotations

import abc
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from orchestrator.errors import EngineNotFound


@dataclass
class Series:
    """A time series sampled at /series/time: values (n, ...) in `units`."""

    values: np.ndarray
    units: str
    description: str = ""


@dataclass
class Result:
    """What a backend read back from its engine, before it becomes run.h5.

    attrs: root attributes (n_steps, dt, ...); series: name -> Series;
    frames / contacts: lists of (time_s, {name: array}); meshes: name ->
    {"vertices", "faces", per-face fields}; events: one row per contact
    from first touch to separation (impact cases; columns in
    orchestrator.reference.dem_forces.EVENT_FIELDS); measured: the case's
    measured quantities (filled by the analysis).
    """

    status: str = "ok"
    message: str = ""
    attrs: dict[str, Any] = field(default_factory=dict)
    time: np.ndarray | None = None
    series: dict[str, Series] = field(default_factory=dict)
    frames: list[tuple[float, dict[str, np.ndarray]]] = field(default_factory=list)
    contacts: list[tuple[float, dict[str, np.ndarray]]] = field(default_factory=list)
    meshes: dict[str, dict[str, np.ndarray]] = field(default_factory=dict)
    events: dict[str, Series] = field(default_factory=dict)
    measured: dict[str, float] = field(default_factory=dict)


@dataclass(frozen=True)
class Progress:
    """A progress report parsed from an engine's log: steps done of planned."""

    done: int
    total: int
    label: str = ""


@dataclass(frozen=True)
class Timing:
    """The engine's own timing probe: estimated wall time of the whole run, s."""

    seconds_per_step: float
    planned_steps: int
    estimate_s: float


_PROGRESS = re.compile(r"^PROGRESS step=(\d+) of (\d+) phase=(\S+)")
_TIMING = re.compile(r"^TIMING s_per_step=(\S+) planned_steps=(\d+) estimate_s=(\S+)")


def parse_progress_line(line: str) -> Progress | Timing | None:
    """Read the PROGRESS / TIMING lines our templates print (one protocol for every engine)."""
    m = _PROGRESS.match(line)
    if m:
        return Progress(int(m.group(1)), int(m.group(2)), m.group(3))
    m = _TIMING.match(line)
    if m:
        return Timing(float(m.group(1)), int(m.group(2)), float(m.group(3)))
    return None


class Engine(abc.ABC):
    """An engine as a program on this machine (a profile): where it is, its version, how to install it.

    Subclasses set `name` (registry name), `label` (the engine's name in messages), `env_var` (the variable that
    overrides the executable's path) and `not_found` (where else it was looked for), and implement version() and
    install_hint(). How a kind's files become a run is the kinds' adapters' business (kinds.base.Adapter).
    """

    name = "engine"
    label = "the engine"
    env_var = ""
    not_found = ""
    executable: str | None = None
    threads: int = 1

    @abc.abstractmethod
    def version(self) -> str:
        """The engine's version string ('unknown' when it cannot say)."""

    @abc.abstractmethod
    def install_hint(self) -> str:
        """What a user does to install the engine."""

    def available(self) -> bool:
        """True when the engine's executable is installed."""
        return bool(self.executable) and Path(self.executable).is_file()

    def where(self) -> str:
        """Path of the engine's executable ('' when not found)."""
        return self.executable or ""

    def check_available(self) -> None:
        """Raise EngineNotFound, with what to do, when the executable is missing."""

        if not self.available():
            env = os.environ.get(self.env_var) if self.env_var else None
            where = f"{self.env_var}={env} does not exist" if env else self.not_found
            raise EngineNotFound(f"{self.label} is not installed ({where}); {self.install_hint()}")
