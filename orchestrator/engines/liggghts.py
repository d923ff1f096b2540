"""LIGGGHTS as a program: LIGGGHTS is found as ``$ORCHESTRATOR_LIGGGHTS`` or ``liggghts`` on
PATH and run as ``liggghts -in DECK -log none``; with more than one MPI rank
(``--mpi N`` on ``orchestrator run``, or ``$ORCHESTRATOR_LIGGGHTS_MPI``) as
``mpirun -np N [--allow-run-as-root] liggghts ...`` with Debian's OpenMPI
(``$ORCHESTRATOR_MPIRUN`` or ``mpirun`` on PATH). No run listens on the
network (LOCAL_MPI_ENV, network_namespace): one rank runs as an isolated MPI
singleton with shared-memory transports only; mpirun, whose out-of-band
channel binds every interface whatever OpenMPI 4.1 is told, runs in a network
namespace of its own that holds only loopback (when the kernel allows user
namespaces). ``ORCHESTRATOR_MPI_LOCAL=0`` turns both off (multi-node MPI); a
variable the user exported wins over ours. LIGGGHTS writes its screen
output through C stdio, which a pipe buffers in 4 kB blocks; the command runs
it under ``stdbuf -oL`` so the progress lines arrive as they are printed.

The files LIGGGHTS reads and writes are in liggghts_files.py; the kinds' decks and parsers in
orchestrator/kinds/<kind>/liggghts.py.
"""

from __future__ import annotations

import functools
import os
import re
import shutil
import subprocess
from functools import cached_property

from orchestrator.engines.base import Engine
from orchestrator.processes import run_probe
from orchestrator.errors import EngineNotFound, OrchestratorError

#: Largest number of MPI ranks accepted (a typo guard, not a machine limit).
MAX_MPI_RANKS = 1024
#: OpenMPI 4.1 (Debian 12) kept on this machine: ranks exchange data through shared memory only (btl
#: self,vader with pml ob1: no TCP, UCX or OFI transport, which would listen on every interface), and what
#: mpirun says out of band goes over loopback. Debian's LIGGGHTS is an MPI program even on one rank.
LOCAL_MPI_ENV = {"OMPI_MCA_btl": "self,vader", "OMPI_MCA_pml": "ob1", "OMPI_MCA_btl_tcp_if_include": "lo",
                 "OMPI_MCA_oob_tcp_if_include": "lo"}
#: One rank without mpirun is an MPI singleton, which forks an orted listening on every interface unless isolated.
SINGLETON_ENV = {"OMPI_MCA_ess_singleton_isolated": "1"}
#: Set to 0 to run OpenMPI as configured (multi-node: hostfile, TCP interfaces), without LOCAL_MPI_ENV and the
#: network namespace.
LOCAL_SWITCH = "ORCHESTRATOR_MPI_LOCAL"


class Liggghts(Engine):
    """Where LIGGGHTS (and mpirun) are on this machine and how to start them."""

    name = "liggghts"
    label, env_var, not_found = "LIGGGHTS", "ORCHESTRATOR_LIGGGHTS", "no 'liggghts' on PATH"

    def __init__(self, executable: str | None = None, threads: int = 1, mpi_ranks: int | None = None,
                 mpirun: str | None = None):
        self.executable = executable or os.environ.get("ORCHESTRATOR_LIGGGHTS") or shutil.which("liggghts")
        self.threads = threads
        self.mpi_ranks = _ranks(mpi_ranks if mpi_ranks is not None else os.environ.get("ORCHESTRATOR_LIGGGHTS_MPI", 1))
        self.mpirun = mpirun or os.environ.get("ORCHESTRATOR_MPIRUN") or shutil.which("mpirun")

    @cached_property
    def banner(self) -> str:
        """First line LIGGGHTS prints ('LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0, ...)'), '' if it cannot run."""
        try:
            # -log none: with only -h LIGGGHTS leaves a log.liggghts in the working directory
            out = run_probe([self.executable, "-log", "none", "-h"], env={**os.environ, **mpi_environment(1)}).stdout
        except (OSError, subprocess.SubprocessError):
            return ""
        return out.splitlines()[0] if out else ""

    def version(self) -> str:
        """LIGGGHTS's version, e.g. 'PUBLIC 3.8.0' ('unknown' if the banner cannot be read)."""
        m = re.search(r"Version LIGGGHTS-(\S+) ([0-9][0-9.]*)", self.banner)
        return f"{m.group(1)} {m.group(2)}" if m else "unknown"

    def install_hint(self) -> str:
        """How to install LIGGGHTS."""
        return "install it with 'sudo apt-get install liggghts' (Debian 12 / Ubuntu), or set ORCHESTRATOR_LIGGGHTS"

    def command(self, deck: str) -> tuple[list[str], dict[str, str]]:
        """Command line and environment that run a deck (under mpirun with more than one rank), listening
        on no network interface unless ORCHESTRATOR_MPI_LOCAL=0."""
        env = {"OMP_NUM_THREADS": str(self.threads), "OMP_WAIT_POLICY": "PASSIVE", **mpi_environment(self.mpi_ranks)}
        local = os.environ.get(LOCAL_SWITCH, "1").strip() != "0"
        engine = [self.executable, "-in", deck, "-log", "none", "-echo", "none"]
        stdbuf = shutil.which("stdbuf")
        if stdbuf:
            engine = [stdbuf, "-oL", "-eL"] + engine
        if self.mpi_ranks == 1:
            return engine, env
        if not self.mpirun:
            raise EngineNotFound(f"{self.mpi_ranks} MPI ranks asked, but there is no 'mpirun' on PATH "
                                 "(install it with 'sudo apt-get install openmpi-bin', or set ORCHESTRATOR_MPIRUN)")
        # ranks that wait yield the core instead of polling: on a shared or busy machine polling made a
        # 2-rank run of the tiny bowl 5 times slower (92 s against 19 s)
        env["OMPI_MCA_mpi_yield_when_idle"] = "1"
        namespace = network_namespace() if local else []
        prefix = namespace + [self.mpirun, "-np", str(self.mpi_ranks)]
        if namespace or (hasattr(os, "geteuid") and os.geteuid() == 0):
            prefix.append("--allow-run-as-root")  # OpenMPI refuses root (which a user is in the namespace)
        if self.mpi_ranks > (os.cpu_count() or 1):
            prefix.append("--oversubscribe")
        # no pinning: the ranks share the machine with other work, let the kernel place them
        prefix += ["--bind-to", "none"]
        return prefix + engine, env


def mpi_environment(ranks: int) -> dict[str, str]:
    """The OpenMPI variables that keep a run of `ranks` ranks off the network (LOCAL_MPI_ENV, and SINGLETON_ENV for
    one rank), less those the user exported; {} with ORCHESTRATOR_MPI_LOCAL=0."""
    if os.environ.get(LOCAL_SWITCH, "1").strip() == "0":
        return {}
    chosen = {**LOCAL_MPI_ENV, **(SINGLETON_ENV if ranks == 1 else {})}
    return {k: v for k, v in chosen.items() if k not in os.environ}


@functools.cache
def network_namespace() -> list[str]:
    """Command prefix that runs a program in a new user and network namespace with only loopback up (listeners
    there are out of every outside interface's reach), or [] where unshare, ip or user namespaces are missing."""
    unshare = shutil.which("unshare")
    ip = shutil.which("ip") or shutil.which("ip", path="/usr/sbin:/sbin:/usr/bin:/bin")
    if not (unshare and ip):
        return []
    prefix = [unshare, "--user", "--map-root-user", "--net", "sh", "-c", '"$0" link set lo up && exec "$@"', ip]
    try:
        ok = subprocess.run(prefix + ["true"], capture_output=True, timeout=30, stdin=subprocess.DEVNULL)
    except (OSError, subprocess.SubprocessError):
        return []
    return prefix if ok.returncode == 0 else []


def _ranks(value) -> int:
    try:
        ranks = int(value)
    except (TypeError, ValueError):
        raise OrchestratorError(f"MPI ranks = {value!r} is not a whole number; allowed: 1 to {MAX_MPI_RANKS} "
                                "(--mpi N or ORCHESTRATOR_LIGGGHTS_MPI)") from None
    if not 1 <= ranks <= MAX_MPI_RANKS:
        raise OrchestratorError(f"MPI ranks = {ranks}; allowed: 1 to {MAX_MPI_RANKS} (--mpi N or "
                                "ORCHESTRATOR_LIGGGHTS_MPI)")
    return ranks
