"""Start an engine as a subprocess in its run directory: log to a file, show
progress with an ETA, report timing estimates, enforce a timeout, never leave the engine running."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from orchestrator import signals
from orchestrator.processes import leftovers, stop_session
from orchestrator.engines.base import Progress, Timing, parse_progress_line

LOG_NAME = "engine.log"


@dataclass
class Execution:
    """How an engine process ended."""

    returncode: int | None
    timed_out: bool
    interrupted: bool
    wall_time_s: float
    timing: Timing | None
    log_path: Path
    last_progress: Progress | None = None
    peak_memory_bytes: int | None = None  # the engine's peak resident memory (peak_memory), None where unmeasured

    def log_tail(self, lines: int = 40) -> str:
        """The last lines of the engine's log."""
        return tail(self.log_path, lines)


def tail(path: Path, lines: int = 40) -> str:
    """Last `lines` lines of a text file ('' if it does not exist)."""
    try:
        with open(path, "rb") as fh:
            fh.seek(0, os.SEEK_END)
            size = fh.tell()
            fh.seek(max(0, size - 64 * 1024))
            text = fh.read().decode(errors="replace")
    except OSError:
        return ""
    return "\n".join(text.splitlines()[-lines:])


def peak_memory(pid: int) -> int | None:
    """Peak resident memory of process pid and its descendants so far, bytes: the sum of their high-water marks
    (VmHWM in /proc/PID/status; one process: exactly its peak). None where /proc does not tell (not Linux, gone)."""
    total, seen, todo = 0, set(), [pid]
    while todo:
        current = todo.pop()
        if current in seen:
            continue
        seen.add(current)
        try:
            with open(f"/proc/{current}/status", "rb") as fh:
                for line in fh:
                    if line.startswith(b"VmHWM:"):
                        total += int(line.split()[1]) * 1024  # kB
                        break
            with open(f"/proc/{current}/task/{current}/children", "rb") as fh:
                todo.extend(int(child) for child in fh.read().split())
        except (OSError, ValueError):
            if current == pid:
                return None
    return total


class _Bar:
    """A tqdm bar on stderr when it is a terminal; plain lines otherwise (quiet when disabled)."""

    def __init__(self, label: str, enabled: bool):
        self.enabled = enabled
        self.label = label
        self.bar = None
        self.last_plain = 0.0
        self.start = time.monotonic()

    def update(self, progress: Progress) -> None:
        if not self.enabled:
            return
        if sys.stderr.isatty():
            from tqdm import tqdm

            if self.bar is None:
                self.bar = tqdm(total=progress.total, desc=self.label, unit="step", unit_scale=True, dynamic_ncols=True)
            if self.bar.total != progress.total:
                self.bar.total = progress.total
            self.bar.set_postfix_str(progress.label, refresh=False)
            self.bar.n = progress.done
            self.bar.refresh()
        elif time.monotonic() - self.last_plain > 30.0:
            self.last_plain = time.monotonic()
            fraction = progress.done / max(1, progress.total)
            eta = ""
            if fraction > 0:
                remaining = (time.monotonic() - self.start) * (1.0 - fraction) / fraction
                eta = f", ETA {remaining / 60:.1f} min" if remaining >= 60 else f", ETA {remaining:.0f} s"
            print(f"{self.label}: {100 * fraction:5.1f} % ({progress.label}{eta})", file=sys.stderr, flush=True)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def execute(command: list[str], env: dict[str, str], workdir: Path, timeout_s: float | None = None,
            progress: bool = True, label: str = "engine", on_timing=None) -> Execution:
    """Run command in workdir with env added, logging stdout+stderr to workdir/engine.log.

    Progress and timing lines (see backends.base.parse_progress_line) drive a
    progress bar; on_timing(Timing) is called once when the engine reports its
    timing probe. The engine is killed (its whole process group) on timeout,
    Ctrl-C, SIGTERM or SIGHUP (signals.Interrupted); the KeyboardInterrupt is
    re-raised after the kill with the Execution (interrupted set) as its
    `execution` attribute. The engine's peak memory (peak_memory) is sampled
    with each poll (every 0.2 s).
    """
    workdir = Path(workdir)
    log_path = workdir / LOG_NAME
    full_env = {**os.environ, **env}
    start = time.monotonic()
    bar = _Bar(label, progress)
    timing = None
    last_progress = None
    signals.check()  # a signal that a library swallowed earlier stops the run before the engine starts
    with signals.shielded(), open(log_path, "wb") as log:
        proc = subprocess.Popen(command, cwd=workdir, env=full_env, stdout=log, stderr=subprocess.STDOUT,
                                stdin=subprocess.DEVNULL, start_new_session=True)
    timed_out = False
    peak = None
    try:
        with open(log_path, "rb") as reader:
            pending = b""
            while True:
                signals.check()
                sample = peak_memory(proc.pid)  # before poll: a process that has exited no longer reports
                peak = max(peak or 0, sample) if sample is not None else peak
                returncode = proc.poll()
                chunk = reader.read()
                if chunk:
                    pending += chunk
                    *lines, pending = pending.split(b"\n")
                    for raw in lines:
                        parsed = parse_progress_line(raw.decode(errors="replace"))
                        if isinstance(parsed, Progress):
                            last_progress = parsed
                            bar.update(parsed)
                        elif isinstance(parsed, Timing):
                            timing = parsed
                            if on_timing is not None:
                                on_timing(parsed)
                if returncode is not None:
                    break
                if timeout_s is not None and time.monotonic() - start > timeout_s:
                    timed_out = True
                    _kill(proc)
                    break
                time.sleep(0.2)
    except KeyboardInterrupt as exc:
        with signals.shielded():  # a second signal must not leave the engine running
            _kill(proc)
            bar.close()
        exc.execution = Execution(proc.returncode, False, True, time.monotonic() - start, timing, log_path,
                                  last_progress, peak)
        raise
    bar.close()
    leftovers(proc)  # what the engine put in the background and left running
    return Execution(proc.returncode, timed_out, False, time.monotonic() - start, timing, log_path, last_progress,
                     peak)


def _kill(proc: subprocess.Popen) -> None:
    """SIGTERM every process of the engine's session, then SIGKILL what is left after 5 s."""
    stop_session(proc, grace_s=5.0)
