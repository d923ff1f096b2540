"""SIGINT, SIGTERM and SIGHUP as one exception, Interrupted, that cannot be swallowed.

`orchestrator` is stopped by Ctrl-C (SIGINT), by `timeout`, a batch scheduler or `docker stop` (SIGTERM) and by a
closed terminal (SIGHUP). Each is turned into Interrupted (a KeyboardInterrupt), so the engine's process group is
stopped and run.h5 written with status ``terminated`` on every path that handles Ctrl-C. Some libraries catch
BaseException while they import (trimesh's import of scipy does), which would swallow the exception: the signal is
therefore also remembered, and `check()` raises it again at the next safe point. Inside `deferred()` (while run.h5
is written) a signal is only remembered and raised when the block ends.
"""

from __future__ import annotations

import contextlib
import signal
import threading

HANDLED = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)

_pending: int | None = None
_deferring = 0


class Interrupted(KeyboardInterrupt):
    """The orchestrator received signum; exit code 128 + signum."""

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum

    def __reduce__(self):  # raised in a pool worker, it crosses to the parent by pickle
        return (Interrupted, (self.signum,))

    @property
    def signal_name(self) -> str:
        """SIGINT, SIGTERM or SIGHUP."""
        return signal.Signals(self.signum).name

    @property
    def exit_code(self) -> int:
        """128 + the signal number (130 for Ctrl-C, 143 for SIGTERM, 129 for SIGHUP)."""
        return 128 + self.signum

    def describe(self) -> str:
        """'Ctrl-C (SIGINT)' or the signal's name."""
        return "Ctrl-C (SIGINT)" if self.signum == signal.SIGINT else self.signal_name


def _handler(signum, frame) -> None:
    global _pending
    if _pending is not None:
        return  # a second signal while the first is being acted on (cleanup, run.h5): absorbed, never a traceback
    _pending = signum
    if not _deferring:
        raise Interrupted(_pending)


@contextlib.contextmanager
def installed():
    """Handle HANDLED signals as Interrupted inside the block; restores the previous handlers after it."""
    global _pending
    _pending = None
    previous = {sig: signal.signal(sig, _handler) for sig in HANDLED}
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        _pending = None


def pending() -> int | None:
    """The first signal received and not yet acted on (None if none)."""
    return _pending


def check() -> None:
    """Raise Interrupted if a signal arrived (e.g. one a library's `except BaseException` swallowed)."""
    if _pending is not None and not _deferring:
        raise Interrupted(_pending)


@contextlib.contextmanager
def shielded():
    """Signals inside the block are remembered, not raised (e.g. while an engine is being stopped)."""
    global _deferring
    _deferring += 1
    try:
        yield
    finally:
        _deferring -= 1


@contextlib.contextmanager
def deferred():
    """Signals inside the block are remembered, not raised; Interrupted is raised when it ends without error."""
    with shielded():
        yield
    check()


_in_task = 0


def _worker_handler(signum, frame) -> None:
    if _in_task:
        _handler(signum, frame)
    # an idle pool worker: nothing to stop; the parent's pool shutdown ends it


def install_in_worker() -> None:
    """Initializer of a process pool's workers: a signal stops the task running in `task()` like a run in the
    main process (engine stopped, run.h5 written); an idle worker ignores it and ends when the pool shuts down
    (raising there, inside the pool's queue, could leave the queue's lock held and the pool hanging)."""
    global _pending
    _pending = None
    for sig in HANDLED:
        signal.signal(sig, _worker_handler)


@contextlib.contextmanager
def task():
    """A pool worker's unit of work: inside it a signal raises Interrupted (see install_in_worker)."""
    global _in_task
    _in_task += 1
    try:
        yield
    finally:
        _in_task -= 1


@contextlib.contextmanager
def time_limit(seconds: float | None, error: BaseException):
    """Raise `error` inside the block once `seconds` of wall time have passed (SIGALRM; no limit when seconds is
    None). For work in this process that a --timeout must bound (building a scene before the engine starts)."""
    if seconds is None or threading.current_thread() is not threading.main_thread():
        yield  # signal handlers can only be set from the main thread
        return

    def expired(signum, frame):
        raise error

    previous = signal.signal(signal.SIGALRM, expired)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
