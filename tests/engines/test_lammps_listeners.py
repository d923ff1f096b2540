"""No LAMMPS run listens on the network: the quick Couette scene on one rank and on two under MPICH's launcher,
watched as the LIGGGHTS and Yade runs are (tests/engines/test_no_listeners.py samples the run's listening sockets)."""

from __future__ import annotations


import pytest

from test_no_listeners import _run_and_watch
from paths import VERIFICATION

CASE = VERIFICATION / "sph_couette_morris1997.toml"


@pytest.mark.lammps
@pytest.mark.parametrize("ranks", [1, 2])
def test_a_lammps_run_listens_on_no_port(ranks, tmp_path, monkeypatch):
    monkeypatch.delenv("ORCHESTRATOR_MPI_LOCAL", raising=False)
    result, seen, samples = _run_and_watch(
        ["run", str(CASE), "--engine", "lammps", "--mpi", str(ranks), "--out", str(tmp_path / "run"),
         "--set", "simulation.duration=0.1", "--no-progress"])
    assert result.returncode == 0, result.stderr
    assert samples >= 5
    assert not seen, f"listening sockets during a {ranks}-rank LAMMPS run: {sorted(seen)}"
