"""The reference engine: our numpy solvers (orchestrator.reference) run as a child python process, like any engine
(so the runner's log, timeout and Ctrl-C apply). Always installed: it is part of the package."""

from __future__ import annotations

import sys
from pathlib import Path

from orchestrator import __version__
from orchestrator.engines.base import Engine

#: Refuse scenes whose estimated run time is longer than this, s.
MAX_WALL_TIME_S = 3600.0
#: Cost model of the reference DEM (reference.dem.simulate) measured on this machine: per step, s, and per sphere and
#: step, s.
STEP_COST_S, SPHERE_STEP_COST_S = 160e-6, 0.45e-6


class Reference(Engine):
    """The python that runs the reference solvers (this interpreter unless given)."""

    name = "reference"
    label = "the reference engine"

    def __init__(self, executable: str | None = None, threads: int = 1):
        self.python = executable or sys.executable
        self.executable = self.python
        self.threads = threads

    def available(self) -> bool:
        """Always: the reference is part of the package."""
        return True

    def version(self) -> str:
        """orchestrator-<version>."""

        return f"orchestrator-{__version__}"

    def where(self) -> str:
        """The directory of the reference solvers."""
        return str(Path(__file__).resolve().parent.parent / "reference")

    def install_hint(self) -> str:
        """Nothing to install."""
        return "it is part of the orchestrator package"

    def check_available(self) -> None:
        """Always available."""
