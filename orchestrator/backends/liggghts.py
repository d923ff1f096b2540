"""LIGGGHTS backend: the impact and drag-finishing scenes as Jinja-rendered
LIGGGHTS-PUBLIC 3.8 input decks (templates/liggghts/).

Profile: LIGGGHTS is found as ``$ORCHESTRATOR_LIGGGHTS`` or ``liggghts`` on
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

Template: the backend writes the scene as LIGGGHTS reads it (a ``read_data``
file with the particles, ASCII STL meshes), renders the deck, and parses
what the deck wrote into output/ back into the Result names Yade's runs
use. How the paper's contact law maps onto LIGGGHTS's ``model hertz
tangential history`` is in liggghts_physics.py; the scene kinds are in
liggghts_impact.py and liggghts_drag.py.
"""

from __future__ import annotations

import functools
import os
import re
import shutil
import subprocess
from functools import cached_property
from pathlib import Path

import numpy as np

from ..errors import EngineNotFound, OrchestratorError, ReadError
from ..templating import render
from .base import ExecutableBackend, Result

TEMPLATES = {"drag_finishing": "liggghts/drag_finishing.in.j2", "impact": "liggghts/impact.in.j2"}
DECK_NAME = {"drag_finishing": "drag_finishing.in", "impact": "impact.in"}
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


class LiggghtsProfile:
    """Where LIGGGHTS (and mpirun) are on this machine and how to start them."""

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
            out = subprocess.run([self.executable, "-log", "none", "-h"], capture_output=True, text=True, timeout=60,
                                 stdin=subprocess.DEVNULL, env={**os.environ, **mpi_environment(1)}).stdout
        except (OSError, subprocess.SubprocessError):
            return ""
        return out.splitlines()[0] if out else ""

    def version(self) -> str:
        """LIGGGHTS's version, e.g. 'PUBLIC 3.8.0' ('unknown' if the banner cannot be read)."""
        m = re.search(r"Version LIGGGHTS-(\S+) ([0-9][0-9.]*)", self.banner)
        return f"{m.group(1)} {m.group(2)}" if m else "unknown"

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


class LiggghtsBackend(ExecutableBackend):
    """Template (decks under templates/liggghts/) plus profile (LiggghtsProfile)."""

    name = "liggghts"
    case_kinds = ("drag_finishing", "impact")
    label, env_var, not_found, templates = ("LIGGGHTS", "ORCHESTRATOR_LIGGGHTS", "no 'liggghts' on PATH",
                                            TEMPLATES)

    def __init__(self, executable: str | None = None, threads: int = 1, mpi_ranks: int | None = None):
        self.profile = LiggghtsProfile(executable, threads, mpi_ranks)
        self._kind = "drag_finishing"  # set by write_input; command() runs that kind's deck

    def version(self) -> str:
        return self.profile.version()

    def install_hint(self) -> str:
        return "install it with 'sudo apt-get install liggghts' (Debian 12 / Ubuntu), or set ORCHESTRATOR_LIGGGHTS"

    def check_scene(self, scene) -> None:
        """Raise OrchestratorError for what LIGGGHTS-PUBLIC 3.8 cannot run (before anything is written); every
        drag-finishing scene runs."""
        if scene.case.case.kind == "impact":
            from .liggghts_impact import check_impact_scene

            check_impact_scene(scene)

    # ---- input ----
    def render_context(self, scene) -> dict:
        """Plain values the template needs (SI units)."""
        if scene.case.case.kind == "impact":
            from .liggghts_impact import impact_context

            return impact_context(scene)
        from .liggghts_drag import drag_context

        return drag_context(scene)

    def write_input(self, scene, workdir: Path) -> None:
        kind = scene.case.case.kind
        self._kind = kind
        workdir = Path(workdir)
        (workdir / "output").mkdir(exist_ok=True)
        if kind == "impact":
            from .liggghts_impact import write_impact_files as write_files
        else:
            from .liggghts_drag import write_drag_files as write_files
        write_files(scene, workdir)
        (workdir / DECK_NAME[kind]).write_text(render(TEMPLATES[kind], self.render_context(scene)))

    def command(self, workdir: Path, kind: str | None = None) -> tuple[list[str], dict[str, str]]:
        return self.profile.command(DECK_NAME[kind or self._kind])

    def resume_input(self, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        """Write the deck that continues a stopped drag-finishing run from its last checkpoint
        (liggghts_resume); returns its command line and environment."""
        if scene.case.case.kind != "drag_finishing":
            raise OrchestratorError(f"only drag-finishing runs resume; this run is of kind {scene.case.case.kind}")
        from .liggghts_resume import write_resume_deck

        return self.profile.command(write_resume_deck(scene, Path(workdir)))

    def planned_steps(self, scene) -> int:
        """Upper bound of the run's time steps."""
        return int(self.render_context(scene)["planned_steps"])

    # ---- output ----
    def read_output(self, scene, workdir: Path) -> Result:
        if scene.case.case.kind == "impact":
            from .liggghts_impact import read_impact_output

            return read_impact_output(scene, Path(workdir))
        from .liggghts_drag import read_drag_output

        return read_drag_output(scene, Path(workdir))


# ---- files LIGGGHTS reads ----
def write_stl_ascii(path: Path, vertices: np.ndarray, faces: np.ndarray, name: str) -> None:
    """An ASCII STL (LIGGGHTS 3.8 reads no binary STL) with full double precision, m."""
    vertices = np.asarray(vertices, dtype=float)
    lines = [f"solid {name}"]
    for face in np.asarray(faces, dtype=np.int64):
        a, b, c = vertices[face]
        normal = np.cross(b - a, c - a)
        size = np.linalg.norm(normal)
        normal = normal / size if size > 0 else normal
        lines.append(" facet normal %r %r %r" % tuple(float(v) for v in normal))
        lines.append("  outer loop")
        lines.extend("   vertex %r %r %r" % tuple(float(v) for v in corner) for corner in (a, b, c))
        lines.append("  endloop")
        lines.append(" endfacet")
    lines.append(f"endsolid {name}")
    Path(path).write_text("\n".join(lines) + "\n")


def write_data_file(path: Path, box: np.ndarray, n_types: int, types: np.ndarray, radii: np.ndarray,
                    densities: np.ndarray, positions: np.ndarray, velocities: np.ndarray | None = None,
                    angular_velocities: np.ndarray | None = None) -> None:
    """A read_data file of granular atoms (ids from 1 in the scene's order); box (3, 2) m; SI units."""
    out = ["LIGGGHTS data file written by orchestrator (SI units)", "", f"{len(radii)} atoms",
           f"{n_types} atom types", ""]
    out += [f"{box[k, 0]!r} {box[k, 1]!r} {axis}lo {axis}hi" for k, axis in enumerate("xyz")]
    out += ["", "Atoms", ""]
    out += [f"{i + 1} {int(t)} {2.0 * float(r)!r} {float(rho)!r} {float(p[0])!r} {float(p[1])!r} {float(p[2])!r}"
            for i, (t, r, rho, p) in enumerate(zip(types, radii, densities, positions))]
    if velocities is not None:
        spins = np.zeros_like(velocities) if angular_velocities is None else angular_velocities
        out += ["", "Velocities", ""]
        out += [f"{i + 1} " + " ".join(repr(float(v)) for v in (*vel, *spin))
                for i, (vel, spin) in enumerate(zip(velocities, spins))]
    Path(path).write_text("\n".join(out) + "\n")


# ---- files LIGGGHTS writes ----
def read_dump(path: Path) -> list[tuple[int, list[str], np.ndarray]]:
    """A LAMMPS text dump (custom or local) as [(step, column names, rows (n, k))]; a cut-off last
    snapshot is dropped."""
    if not Path(path).is_file():
        return []
    snapshots = []
    text = Path(path).read_text()
    for block in text.split("ITEM: TIMESTEP\n")[1:]:
        lines = block.split("\n")
        try:
            step = int(lines[0])
            count = int(lines[2])
            header = next(k for k, line in enumerate(lines) if line.startswith("ITEM: ATOMS")
                          or line.startswith("ITEM: ENTRIES"))
        except (ValueError, IndexError, StopIteration):
            break
        columns = lines[header].split()[2:]
        body = lines[header + 1: header + 1 + count]
        if len(body) < count or (count and len(body[-1].split()) != len(columns)):
            break
        rows = np.array(" ".join(body).split(), dtype=float).reshape(count, len(columns)) if count else \
            np.zeros((0, len(columns)))
        snapshots.append((step, columns, rows))
    return snapshots


def read_table(path: Path, key: str | None = None) -> dict[str, np.ndarray]:
    """A whitespace table with a '# name name ...' title line (fix print output) as name -> column; rows
    cut off or not numeric are dropped, and with a key column only the first row of each key value is kept."""
    path = Path(path)
    if not path.is_file():
        return {}
    lines = path.read_text().splitlines()
    if not lines or not lines[0].startswith("#"):
        raise ReadError(f"{path} has no '# column ...' title line")
    names = lines[0][1:].split()
    rows = []
    for line in lines[1:]:
        parts = line.split()
        if len(parts) != len(names):
            continue
        try:
            rows.append([float(p) for p in parts])
        except ValueError:
            continue
    data = np.array(rows, dtype=float).reshape(-1, len(names))
    if key is not None and len(data):  # a row written twice at one step (a record at a phase change) counts once
        _, first = np.unique(data[:, names.index(key)], return_index=True)
        data = data[np.sort(first)]
    return {name: data[:, i] for i, name in enumerate(names)}


def engine_error(log_text: str) -> str:
    """The first 'ERROR' line of a LIGGGHTS log, without the source location ('' if none)."""
    for line in log_text.splitlines():
        if line.startswith("ERROR") or "ERROR on proc" in line:
            return re.sub(r"\s*\(\S+:\d+\)\s*$", "", line.split(":", 1)[1].strip() if ":" in line else line)
    return ""
