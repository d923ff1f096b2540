"""Child processes that never outlive us: an engine's whole session is stopped, short probes are bounded.

Every program we start runs in a session of its own (``start_new_session``). Stopping it stops every process of
that session, not only its process group: an engine's shell that put a child in the background and exited leaves
that child in the session, and it is found there and stopped too.
"""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import time

#: Wall-time bound of a short probe (an engine's --version, its help banner), s; lowered by probe_bound().
PROBE_TIMEOUT_S = 30.0


def session_members(sid: int, outside_group: bool = False) -> list[int]:
    """Pids of the processes in session sid (from /proc; [] where /proc does not tell); outside_group: only those
    that left the session leader's process group (a signal to the group does not reach them)."""
    members = []
    try:
        entries = os.listdir("/proc")
    except OSError:
        return members
    for entry in entries:
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat", "rb") as fh:
                fields = fh.read().rsplit(b")", 1)[1].split()
        except (OSError, IndexError):
            continue
        # after the command: state, ppid, pgrp, session; a zombie is dead already (its parent reaps it)
        if len(fields) > 3 and int(fields[3]) == sid and fields[0] != b"Z":
            if not (outside_group and int(fields[2]) == sid):
                members.append(int(entry))
    return members


def _signal_session(sid: int, sig: int) -> int:
    """Send sig to the process group sid and to every process of session sid outside that group (each process gets
    it once: an engine that saves a checkpoint on SIGTERM must not be interrupted by a second one); returns how
    many were reached."""
    alive = 0
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(sid, sig)
        alive += 1
    for pid in session_members(sid, outside_group=True):
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.kill(pid, sig)
            alive += 1
    return alive


def stop_session(proc: subprocess.Popen, grace_s: float = 5.0) -> None:
    """SIGTERM every process of proc's session (proc was started with start_new_session), SIGKILL what is left
    after grace_s seconds; reaps proc."""
    sid = proc.pid
    if not _signal_session(sid, signal.SIGTERM):
        proc.poll()
        return
    deadline = time.monotonic() + grace_s
    while time.monotonic() < deadline:
        proc.poll()
        if proc.returncode is not None and not session_members(sid):
            return
        time.sleep(0.05)
    _signal_session(sid, signal.SIGKILL)
    with contextlib.suppress(subprocess.TimeoutExpired):
        proc.wait(grace_s)


def leftovers(proc: subprocess.Popen) -> None:
    """After proc ended: stop whatever it left running in its session (children it put in the background)."""
    if session_members(proc.pid):
        stop_session(proc, grace_s=2.0)


@contextlib.contextmanager
def probe_bound(timeout_s: float | None):
    """Inside the block short probes take at most timeout_s seconds (when it is below PROBE_TIMEOUT_S): a run's
    --timeout bounds its engine's version probe too."""
    global PROBE_TIMEOUT_S
    saved = PROBE_TIMEOUT_S
    if timeout_s is not None:
        PROBE_TIMEOUT_S = min(saved, timeout_s)
    try:
        yield
    finally:
        PROBE_TIMEOUT_S = saved


def run_probe(command: list[str], env: dict[str, str] | None = None, cwd=None) -> subprocess.CompletedProcess:
    """Run a short command (text output captured, no input) in a session of its own, at most PROBE_TIMEOUT_S
    seconds; on timeout or a signal its whole session is stopped and subprocess.TimeoutExpired (or the
    KeyboardInterrupt) is raised. OSError when it cannot start."""
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL,
                            text=True, errors="replace", env=env, cwd=cwd, start_new_session=True)
    try:
        out, err = proc.communicate(timeout=PROBE_TIMEOUT_S)
    except BaseException:
        stop_session(proc, grace_s=1.0)
        with contextlib.suppress(Exception):
            proc.communicate(timeout=1.0)
        raise
    leftovers(proc)
    return subprocess.CompletedProcess(command, proc.returncode, out, err)
