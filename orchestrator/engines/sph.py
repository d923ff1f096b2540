"""The sph executable (engines/sph) as a program: $ORCHESTRATOR_SPH, else <repo>/engines/sph/build/sph (a source
checkout after ``make sph``), else ``sph`` on PATH; its version comes from ``sph --version``."""

from __future__ import annotations

import os
import shutil
import subprocess
from functools import cached_property
from pathlib import Path

from orchestrator.engines.base import Engine
from orchestrator.processes import run_probe

#: libgomp spin iterations before an idle thread sleeps, with numerics.thread_wait = "spin" (-): 10^4
#: measured best on 2 cores (2D dam break, 2 threads over 1: 10^3 1.70, 10^4 1.90, 10^5 1.69).
SPIN_COUNT = "10000"
#: The executable built in a source checkout by `make sph`.
BUILT_EXECUTABLE = Path(__file__).resolve().parent.parent.parent / "engines" / "sph" / "build" / "sph"


class Sph(Engine):
    """Where the sph executable is on this machine and how to start it."""

    name = "sph"
    label, env_var = "the sph executable", "ORCHESTRATOR_SPH"
    not_found = f"neither {BUILT_EXECUTABLE} nor 'sph' on PATH"

    def __init__(self, executable: str | None = None, threads: int = 1):
        self.executable = executable or os.environ.get("ORCHESTRATOR_SPH") or _default_executable()
        self.threads = threads

    def install_hint(self) -> str:
        """How to build the executable."""
        return "build it with 'make sph' (needs g++, cmake, libeigen3-dev, libhdf5-dev, nlohmann-json3-dev)"

    def version(self) -> str:
        """The executable's version (see _version)."""
        return self._version

    @cached_property
    def _version(self) -> str:
        """The executable's version, e.g. 'sph 0.1.0' -> '0.1.0' ('unknown' when it cannot say)."""
        if not self.executable:
            return "unknown"
        try:
            out = run_probe([self.executable, "--version"])
        except (OSError, subprocess.SubprocessError):
            return "unknown"
        words = (out.stdout or out.stderr).split()
        return words[-1] if words else "unknown"

    def environment(self, thread_wait: str = "passive") -> dict[str, str]:
        """Environment of a run: its threads and how idle threads wait (a case's numerics.thread_wait).

        passive: OMP_WAIT_POLICY=PASSIVE (sleep at once; the machine may be shared). spin:
        OMP_WAIT_POLICY=ACTIVE with GOMP_SPINCOUNT=SPIN_COUNT, a bounded spin (about 10 us) before
        sleeping, for cores of its own. The executable reads the policy too (its light loops stay
        serial on small scenes under passive waiting).
        """
        if thread_wait == "spin":
            return {"OMP_NUM_THREADS": str(self.threads), "OMP_WAIT_POLICY": "ACTIVE", "GOMP_SPINCOUNT": SPIN_COUNT}
        return {"OMP_NUM_THREADS": str(self.threads), "OMP_WAIT_POLICY": "PASSIVE"}


def _default_executable() -> str | None:
    if BUILT_EXECUTABLE.is_file():
        return str(BUILT_EXECUTABLE)
    return shutil.which("sph")


