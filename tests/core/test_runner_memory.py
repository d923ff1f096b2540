"""The engine's peak memory (runner.peak_memory, Execution.peak_memory_bytes): the high-water marks that Linux keeps
per process (VmHWM), summed over the engine's process tree, sampled while the engine runs."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from orchestrator.runner import execute, peak_memory

MiB = 2**20
# Allocates and touches 300 MiB, lets it go, then sleeps: the peak stays in VmHWM after the memory is freed.
HOG = "import time; b = bytearray(300 * 2**20); del b; print('freed', flush=True); time.sleep({sleep})"

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc is Linux's")


def _wait_for(proc, text: str) -> None:
    assert proc.stdout.readline().strip() == text


def test_peak_memory_of_one_process_is_its_high_water_mark():
    baseline = peak_memory(os.getpid())
    assert baseline is not None and baseline > 10 * MiB  # this interpreter
    proc = subprocess.Popen([sys.executable, "-c", HOG.format(sleep=5)], stdout=subprocess.PIPE, text=True)
    try:
        _wait_for(proc, "freed")
        peak = peak_memory(proc.pid)
        assert 300 * MiB < peak < 400 * MiB  # the bytearray and the interpreter, though freed now
    finally:
        proc.kill(), proc.wait()
    assert peak_memory(proc.pid) is None  # gone


def test_peak_memory_sums_the_process_tree():
    # a shell (small) whose child holds the 300 MiB peak: the engine started under a wrapper, as mpirun starts ranks
    child = f"{sys.executable} -c \"{HOG.format(sleep=5)}\""
    proc = subprocess.Popen(["sh", "-c", child + "; true"], stdout=subprocess.PIPE, text=True, start_new_session=True)
    try:
        _wait_for(proc, "freed")
        assert peak_memory(proc.pid) > 300 * MiB
    finally:
        os.killpg(proc.pid, signal.SIGKILL), proc.wait()


def test_execute_records_the_engines_peak(tmp_path):
    start = time.monotonic()
    execution = execute([sys.executable, "-c", HOG.format(sleep=0.8)], {}, tmp_path, progress=False)
    assert execution.returncode == 0 and time.monotonic() - start < 30
    assert 300 * MiB < execution.peak_memory_bytes < 400 * MiB
