"""A run directory of ours: recognised by a marker, held by one run at a time, emptied by --force, resumed from what
its marker and case.toml say (resumable_run).

A run directory holds the engine's input and output, the resolved case and run.h5. Three rules keep runs from
hurting each other or the user's files:

- a folder that is not empty and holds no marker of ours (``.orchestrator-run``; a run.h5 or a lock file alone
  proves nothing) is the user's: it is refused, with or without --force, and nothing is written into it;
- a run holds an exclusive lock (``fcntl.flock`` on ``.orchestrator.lock``) from before it writes anything until
  run.h5 is written; a second run into the same folder fails at once naming the first (pid, start time, command);
- --force empties the directory (outputs of the old run included) under that lock, before the engine starts, so
  a new run.h5 never carries the old run's samples.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import fcntl
import json
import math
import os
import shutil
import sys
from pathlib import Path

from orchestrator.case import load_case
from orchestrator.errors import OrchestratorError
from orchestrator.humanize import check_out_dir, os_problem
from orchestrator.outputs import LOCK, MARKER, is_ours, write_text
from orchestrator.runh5 import RUN_FILE


class RunDirBusy(OrchestratorError):
    """Another run holds the directory's lock (exit 2)."""


class RunDirectory:
    """Context manager: create or take over a run directory and hold its lock while the run lasts.

    ``with RunDirectory(path, force) as run_dir:`` raises OrchestratorError (exit 2) when path is a file, cannot be
    created, is a non-empty folder of the user's, already holds a run (without force) or is locked by another run.
    """

    def __init__(self, path: str | Path, force: bool = False, resume: bool = False, info: dict | None = None):
        if str(path).strip() == "":
            raise OrchestratorError("--out is empty; give the path of a new or empty folder")
        self.path = Path(path)
        self.force = force
        self.resume = resume
        self.info = info or {}
        self._fd: int | None = None

    def __enter__(self) -> Path:
        path = self.path
        option = "--resume" if self.resume else "--out"
        check_out_dir(path, option)  # a file, a device, a name too long, a folder that cannot be written
        if self.resume and not (path.is_dir() and is_ours(path)):
            raise OrchestratorError(f"--resume {path}: not a run directory of orchestrator (no {MARKER})")
        if path.is_dir() and any(path.iterdir()) and not is_ours(path):
            raise OrchestratorError(
                f"{path} is not empty and is not a run directory of orchestrator (no {MARKER}); refusing to write "
                "into it, with or without --force: give a new or empty folder as --out"
            )
        try:
            path.mkdir(parents=True, exist_ok=True)
            self._fd = os.open(path / LOCK, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as exc:
            raise OrchestratorError(f"cannot create the run directory {path}: {os_problem(exc)}") from None
        try:
            fcntl.flock(self._fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = _read_holder(self._fd)
            self._release()
            raise RunDirBusy(f"{path} is in use by another run ({holder}); wait for it to end or choose another "
                             "--out") from None
        try:
            if (path / RUN_FILE).exists() and not (self.force or self.resume):
                raise OrchestratorError(f"{path} already holds a run ({RUN_FILE}); choose another --out, or pass "
                                        "--force to replace it")
            if self.force:
                self._empty()
            self._write_holder()
            if self.resume:
                info = {**run_info(path), "resumed": [*run_info(path).get("resumed", []), _now()]}
            else:
                info = {"created": _now(), **self.info}
            write_text(path / MARKER, json.dumps(info) + "\n", option, own_run_file=True)
        except OSError as exc:
            self._release()
            raise OrchestratorError(f"cannot write into the run directory {path}: {os_problem(exc)}") from None
        except BaseException:
            self._release()
            raise
        return path

    def __exit__(self, *exc_info) -> None:
        self._release()

    def _empty(self) -> None:
        """Remove everything but the lock: the old run's input, outputs and run.h5."""
        for entry in self.path.iterdir():
            if entry.name == LOCK:
                continue
            if entry.is_dir() and not entry.is_symlink():
                shutil.rmtree(entry)
            else:
                entry.unlink()

    def _write_holder(self) -> None:
        text = json.dumps({"pid": os.getpid(), "started": _now(), "command": " ".join(sys.argv)}) + "\n"
        os.ftruncate(self._fd, 0)
        os.pwrite(self._fd, text.encode(), 0)

    def _release(self) -> None:
        if self._fd is not None:
            os.close(self._fd)  # closing the descriptor releases the flock
            self._fd = None


def run_info(path: Path) -> dict:
    """What the run directory's marker says of its run (created, engine, preset, mpi_ranks, resumed); {} if none."""
    try:
        info = json.loads((Path(path) / MARKER).read_text())
    except (OSError, ValueError):
        return {}
    return info if isinstance(info, dict) else {}


def _read_holder(fd: int) -> str:
    """'pid N, started T, command C' from the lock file of the run that holds it."""
    try:
        info = json.loads(os.pread(fd, 4096, 0).decode() or "{}")
    except (OSError, ValueError, UnicodeDecodeError):
        info = {}
    if not info:
        return "its details are not written yet"
    return f"pid {info.get('pid')}, started {info.get('started')}, command: {info.get('command')}"


def _now() -> str:
    return _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")


def resumable_run(run_dir, until: float | None = None) -> tuple:
    """(LoadedCase, engine, MPI ranks) of the stopped run in run_dir, from its case.toml and its marker; with until
    (s, sph runs), the case's simulation.duration set to it, which must lie beyond the run's.

    Raises OrchestratorError when run_dir is not a run directory of ours, its case no longer validates, or until
    cannot extend it.
    """
    run_dir = Path(run_dir)
    info = run_info(run_dir)
    if not info.get("engine") or not (run_dir / "case.toml").is_file():
        raise OrchestratorError(f"--resume {run_dir}: not a run directory of orchestrator that can be resumed "
                                f"(needs {MARKER} naming the engine and case.toml)")
    loaded = load_case(run_dir / "case.toml")
    if until is not None:
        duration = (loaded.resolved.get("simulation") or {}).get("duration")
        if info["engine"] != "sph" or duration is None:
            raise OrchestratorError(f"--until: only sph runs (simulation.duration) run on; {run_dir} is a "
                                    f"{loaded.kind} run on {info['engine']}")
        if not (math.isfinite(until) and until > duration):
            raise OrchestratorError(f"--until {until:g}: allowed: a time in s after the run's simulation.duration "
                                    f"({duration:g} s)")
        loaded = load_case(run_dir / "case.toml", overrides=[f"simulation.duration={until!r}"])
    return dataclasses.replace(loaded, preset=info.get("preset") or None), info["engine"], info.get("mpi_ranks")
