"""The LAMMPS profile (orchestrator/engines/lammps.py): finding it, its version and packages from `lmp -h`, MPI ranks
through MPICH's launcher kept off the network, bad input; and, with the wheel installed, doctor's line."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from orchestrator.engines import get_engine
from orchestrator.engines.lammps import LOCAL_MPICH_ENV, Lammps
from orchestrator.errors import EngineNotFound, OrchestratorError

#: What the wheel's `lmp -h` prints, cut to the lines the profile reads.
HELP = """
Large-scale Atomic/Molecular Massively Parallel Simulator - 22 Jul 2025 - Update 4
Git info (HEAD / stable_22Jul2025_update4)

Usage example: lmp -var t 300 -echo screen -in in.alloy

Installed packages:

AMOEBA ASPHERE GRANULAR KSPACE
MACHDYN MOLECULE RIGID SPH

List of individual style options included in this LAMMPS executable
"""


@pytest.fixture
def fake_lmp(tmp_path):
    """An executable that prints HELP for -h, beside a libmpi.so.12 (as the wheel's layout has it)."""
    lib = tmp_path / "venv" / "lib"
    binary = lib / "python3.11" / "site-packages" / "lammps" / "lmp"
    binary.parent.mkdir(parents=True)
    (lib / "libmpi.so.12").write_bytes(b"")
    (tmp_path / "help.txt").write_text(HELP)
    binary.write_text(f"#!/bin/sh\ncat {tmp_path / 'help.txt'}\n")
    binary.chmod(0o755)
    return binary


def test_version_packages_and_library_folder(fake_lmp, monkeypatch):
    monkeypatch.delenv("LD_LIBRARY_PATH", raising=False)
    engine = Lammps(executable=str(fake_lmp))
    assert engine.available()
    assert engine.version() == "22 Jul 2025 Update 4"
    assert engine.packages() == ["AMOEBA", "ASPHERE", "GRANULAR", "KSPACE", "MACHDYN", "MOLECULE", "RIGID", "SPH"]
    assert engine.features() == "SPH MACHDYN GRANULAR RIGID"
    assert engine.library_dir() == str((fake_lmp.parents[3]).resolve())
    assert engine.environment()["LD_LIBRARY_PATH"] == engine.library_dir()


def test_a_build_without_a_package_says_so(tmp_path):
    script = tmp_path / "lmp"
    script.write_text("#!/bin/sh\nprintf 'Simulator - 2 Aug 2023\\n\\nInstalled packages:\\n\\nSPH RIGID\\n\\n'\n")
    script.chmod(0o755)
    engine = Lammps(executable=str(script))
    assert engine.version() == "2 Aug 2023"
    assert engine.features() == "missing MACHDYN GRANULAR"


def test_missing_executable_names_the_hint(tmp_path, monkeypatch):
    monkeypatch.setenv("ORCHESTRATOR_LAMMPS", str(tmp_path / "nope"))
    engine = get_engine("lammps")
    assert not engine.available()
    with pytest.raises(EngineNotFound, match="make lammps"):
        engine.check_available()


@pytest.mark.parametrize("ranks", [0, -2, "two", 100000])
def test_bad_rank_counts(ranks):
    with pytest.raises(OrchestratorError, match="MPI ranks"):
        get_engine("lammps", mpi_ranks=ranks)


def test_one_rank_runs_without_a_launcher_on_shared_memory(fake_lmp, monkeypatch):
    monkeypatch.delenv("ORCHESTRATOR_MPI_LOCAL", raising=False)
    for key in LOCAL_MPICH_ENV:
        monkeypatch.delenv(key, raising=False)
    command, env = Lammps(executable=str(fake_lmp), threads=2).command("in.lammps")
    assert command[:3] == [str(fake_lmp), "-in", "in.lammps"]
    assert command[-5:] == ["-sf", "omp", "-pk", "omp", "2"]
    assert env["FI_PROVIDER"] == "shm" and env["MPIR_CVAR_CH4_NETMOD"] == "ofi" and env["OMP_NUM_THREADS"] == "2"


def test_ranks_start_under_the_forking_launcher(fake_lmp, tmp_path, monkeypatch):
    monkeypatch.delenv("ORCHESTRATOR_MPI_LOCAL", raising=False)
    mpiexec = tmp_path / "bin" / "mpiexec"
    mpiexec.parent.mkdir()
    for name in ("mpiexec", "mpiexec.gforker"):
        (mpiexec.parent / name).write_text("#!/bin/sh\n")
    command, _ = Lammps(executable=str(fake_lmp), mpi_ranks=2, mpiexec=str(mpiexec)).command("in.lammps")
    assert command[:3] == [str(mpiexec.parent / "mpiexec.gforker"), "-n", "2"]
    assert command[3] == str(fake_lmp)


def test_multi_node_uses_hydra_with_the_hostfile(fake_lmp, tmp_path, monkeypatch):
    monkeypatch.setenv("ORCHESTRATOR_MPI_LOCAL", "0")
    monkeypatch.setenv("ORCHESTRATOR_LAMMPS_HOSTFILE", str(tmp_path / "hosts"))
    for key in LOCAL_MPICH_ENV:
        monkeypatch.delenv(key, raising=False)
    command, env = Lammps(executable=str(fake_lmp), mpi_ranks=8, mpiexec="/opt/mpich/bin/mpiexec").command("d")
    assert command[:5] == ["/opt/mpich/bin/mpiexec", "-f", str(tmp_path / "hosts"), "-n", "8"]
    assert "FI_PROVIDER" not in env


def test_no_launcher_for_ranks_is_engine_not_found(fake_lmp, monkeypatch):
    engine = Lammps(executable=str(fake_lmp), mpi_ranks=2)
    engine.mpiexec = None
    with pytest.raises(EngineNotFound, match="mpiexec"):
        engine.command("in.lammps")


@pytest.mark.lammps
def test_doctor_lists_lammps_with_its_packages():
    proc = subprocess.run([sys.executable, "-m", "orchestrator", "doctor", "--json"], capture_output=True, text=True,
                          timeout=120)
    row = next(r for r in json.loads(proc.stdout) if r["engine"] == "lammps")
    assert row["found"] and row["version"] not in ("", "unknown")
    assert row["features"] == "SPH MACHDYN GRANULAR RIGID"
