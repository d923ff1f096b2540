"""SPH backend: our engines/sph executable, run as ``sph deck.json``.

Profile: the executable is $ORCHESTRATOR_SPH, else <repo>/engines/sph/build/sph
(a source checkout after ``make sph``), else ``sph`` on PATH; its version
comes from ``sph --version``.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from functools import cached_property
from pathlib import Path

from ..errors import EngineNotFound
from .base import Backend

#: The executable built in a source checkout by `make sph`.
BUILT_EXECUTABLE = Path(__file__).resolve().parent.parent.parent / "engines" / "sph" / "build" / "sph"


class SphProfile:
    """Where the sph executable is on this machine and how to start it."""

    def __init__(self, executable: str | None = None, threads: int = 1):
        self.executable = executable or os.environ.get("ORCHESTRATOR_SPH") or _default_executable()
        self.threads = threads

    @cached_property
    def version(self) -> str:
        """The executable's version, e.g. 'sph 0.1.0' -> '0.1.0'."""
        try:
            out = subprocess.run([self.executable, "--version"], capture_output=True, text=True, timeout=30)
        except (OSError, subprocess.TimeoutExpired):
            return "unknown"
        words = (out.stdout or out.stderr).split()
        return words[-1] if words else "unknown"

    def environment(self) -> dict[str, str]:
        """Environment of a run: its threads, and passive OpenMP waiting (the machine may be shared)."""
        return {"OMP_NUM_THREADS": str(self.threads), "OMP_WAIT_POLICY": "PASSIVE"}


def _default_executable() -> str | None:
    if BUILT_EXECUTABLE.is_file():
        return str(BUILT_EXECUTABLE)
    return shutil.which("sph")


class SphBackend(Backend):
    """Template (templates/sph/deck.json.j2 and HDF5 inputs) plus profile (SphProfile)."""

    name = "sph"
    case_kinds = ("sph_flow",)

    def __init__(self, executable: str | None = None, threads: int = 1):
        self.profile = SphProfile(executable, threads)

    def available(self) -> bool:
        return bool(self.profile.executable) and Path(self.profile.executable).is_file()

    def version(self) -> str:
        return self.profile.version

    def where(self) -> str:
        return self.profile.executable or ""

    def install_hint(self) -> str:
        return "build it with 'make sph' (needs g++, cmake, libeigen3-dev, libhdf5-dev, nlohmann-json3-dev)"

    def check_available(self) -> None:
        """Raise EngineNotFound, with what to do, when the executable is missing."""
        if not self.available():
            env = os.environ.get("ORCHESTRATOR_SPH")
            where = f"ORCHESTRATOR_SPH={env} does not exist" if env else \
                f"neither {BUILT_EXECUTABLE} nor 'sph' on PATH"
            raise EngineNotFound(f"the sph executable is not installed ({where}); {self.install_hint()}")

    def template_files(self, kind: str) -> list[Path]:
        from ..templating import template_root

        return [template_root() / "sph" / "deck.json.j2"]

    def write_input(self, scene, workdir: Path) -> None:
        raise NotImplementedError

    def command(self, workdir: Path) -> tuple[list[str], dict[str, str]]:
        return [self.profile.executable, "deck.json"], self.profile.environment()

    def read_output(self, scene, workdir: Path):
        raise NotImplementedError
