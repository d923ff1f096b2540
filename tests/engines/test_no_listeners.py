"""No run listens on the network: a tiny impact on LIGGGHTS (one MPI rank, and two under mpirun) and on Yade,
sampling every 10 ms the listening TCP sockets (/proc/net/tcp and tcp6, state 0A) held by the run's processes
(the orchestrator and everything it started). Ours only, so that other work on the machine cannot fail the test.

OpenMPI 4.1 left alone opens listeners on 0.0.0.0 and [::] even for one rank (the singleton's orted, the TCP
transport); orchestrator/engines/liggghts.py keeps it to shared memory and puts mpirun into a network namespace.
"""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from orchestrator.engines import get_engine

from orchestrator.engines.liggghts import network_namespace
from paths import VERIFICATION

CASE = VERIFICATION / "chung_ooi_test1_sphere_sphere.toml"
LISTEN = "0A"


def _listening() -> dict[int, str]:
    """inode -> 'address:port' of every listening TCP socket in this network namespace."""
    out = {}
    for name, width in (("tcp", 8), ("tcp6", 32)):
        try:
            lines = Path(f"/proc/net/{name}").read_text().splitlines()[1:]
        except OSError:
            continue
        for line in lines:
            fields = line.split()
            if fields[3] != LISTEN:
                continue
            address, port = fields[1].split(":")
            raw = b"".join(bytes.fromhex(address[k:k + 8])[::-1] for k in range(0, width, 8))  # host-order words
            host = socket.inet_ntop(socket.AF_INET if width == 8 else socket.AF_INET6, raw)
            out[int(fields[9])] = f"{host}:{int(port, 16)}"
    return out


def _tree(root: int) -> set[int]:
    """root and its descendants (from /proc/*/stat)."""
    parents = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                stat = (entry / "stat").read_text()
            except OSError:
                continue
            parents[int(entry.name)] = int(stat.rsplit(")", 1)[1].split()[1])
    tree, grown = {root}, True
    while grown:
        more = {pid for pid, parent in parents.items() if parent in tree} - tree
        tree |= more
        grown = bool(more)
    return tree


def _sockets(pids: set[int]) -> dict[int, int]:
    """socket inode -> pid for the open file descriptors of pids."""
    out = {}
    for pid in pids:
        try:
            fds = os.listdir(f"/proc/{pid}/fd")
        except OSError:
            continue
        for fd in fds:
            try:
                target = os.readlink(f"/proc/{pid}/fd/{fd}")
            except OSError:
                continue
            if target.startswith("socket:["):
                out[int(target[8:-1])] = pid
    return out


def _run_and_watch(args: list[str]) -> tuple[subprocess.CompletedProcess, set[str], int]:
    """Run the orchestrator CLI; (its result, the listeners its processes held at any sample, samples taken)."""
    seen: set[str] = set()
    samples = 0
    proc = subprocess.Popen([sys.executable, "-m", "orchestrator", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env={**os.environ, "OMP_WAIT_POLICY": "PASSIVE"})
    done = threading.Event()

    def watch():
        nonlocal samples
        while not done.is_set():
            owners = _sockets(_tree(proc.pid))
            for inode, address in _listening().items():
                if inode in owners:
                    comm = Path(f"/proc/{owners[inode]}/comm")
                    seen.add(f"{address} ({comm.read_text().strip() if comm.exists() else owners[inode]})")
            samples += 1
            time.sleep(0.01)

    watcher = threading.Thread(target=watch, daemon=True)
    watcher.start()
    try:
        stdout, stderr = proc.communicate(timeout=600)
    finally:
        done.set()
        watcher.join()
    return subprocess.CompletedProcess(proc.args, proc.returncode, stdout, stderr), seen, samples


def test_the_watcher_sees_a_listener(tmp_path):
    """The sampling itself works: a child that listens on 127.0.0.1 is seen."""
    code = ("import socket, time; s = socket.socket(); s.bind(('127.0.0.1', 0)); s.listen(); time.sleep(0.5)")
    seen: set[str] = set()
    proc = subprocess.Popen([sys.executable, "-c", code])
    try:
        deadline = time.time() + 10
        while not seen and time.time() < deadline and proc.poll() is None:
            owners = _sockets(_tree(proc.pid))
            seen |= {address for inode, address in _listening().items() if inode in owners}
            time.sleep(0.01)
    finally:
        proc.wait(timeout=30)
    assert any(address.startswith("127.0.0.1:") for address in seen)


@pytest.mark.liggghts
@pytest.mark.liggghts
@pytest.mark.parametrize("ranks", [1, 2])
def test_a_liggghts_run_listens_on_no_port(ranks, tmp_path, monkeypatch):
    monkeypatch.delenv("ORCHESTRATOR_MPI_LOCAL", raising=False)
    if ranks > 1 and not get_engine("liggghts").mpirun:
        pytest.skip("no mpirun (apt-get install openmpi-bin)")
    if ranks > 1 and not network_namespace():
        pytest.skip("no user namespaces (unshare -rn): mpirun's out-of-band channel binds every interface "
                    "in OpenMPI 4.1 whatever it is told")
    result, seen, samples = _run_and_watch(
        ["run", str(CASE), "--engine", "liggghts", "--mpi", str(ranks), "--out", str(tmp_path / "run"),
         "--set", "simulation.duration=6e-4", "--no-progress"])
    assert result.returncode == 0, result.stderr
    assert samples >= 5
    assert not seen, f"listening sockets during a {ranks}-rank LIGGGHTS run: {sorted(seen)}"


@pytest.mark.yade
@pytest.mark.yade
def test_a_yade_run_listens_on_no_port(tmp_path):
    result, seen, samples = _run_and_watch(["run", str(CASE), "--engine", "yade", "--out", str(tmp_path / "run"),
                                            "--no-progress"])
    assert result.returncode == 0, result.stderr
    assert samples >= 5
    assert not seen, f"listening sockets during a Yade run: {sorted(seen)}"
