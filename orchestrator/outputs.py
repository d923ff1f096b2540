"""The one output policy: every file a command writes goes through here.

A file is written to a temporary name beside its target and renamed over it, so a reader never sees half a file
and a failed write leaves the old one in place. Before anything is written the target is checked:

- it is a regular file or does not exist yet (never a FIFO, a device or a folder);
- it is not an input of the same command (``inputs``);
- it is not one of a run directory's own files (the marker, the lock, run.h5, case.toml) unless the caller is the
  run itself (``own_run_file=True``);
- a folder a command writes several files into (its ``--out``) is ours when it holds the marker file
  ``.orchestrator-run`` and nothing else; a folder that is not empty and has no marker is the user's and is refused.

An OSError while writing (a full disk, a read-only file system, permission denied) becomes one WriteError (exit 8)
that names the file and what went wrong; the temporary file is removed.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import errno
import io
import json
import os
import stat
import sys
from pathlib import Path

from orchestrator.errors import OrchestratorError
from orchestrator.humanize import check_out_dir, os_problem

MARKER = ".orchestrator-run"
LOCK = ".orchestrator.lock"
RUN_FILE = "run.h5"
CASE_FILE = "case.toml"
#: A run directory's own files: nothing but the run itself writes them.
RUN_FILES = (MARKER, LOCK, RUN_FILE, CASE_FILE)


class WriteError(OrchestratorError):
    """An output could not be written: full disk, read-only file system, permission (exit 8)."""

    exit_code = 8


def is_ours(folder) -> bool:
    """True when folder holds our marker file (the only proof that a folder is a run or output folder of ours)."""
    return (Path(folder) / MARKER).is_file()


def _shown(path) -> str:
    text = str(path)
    return text if len(text) <= 120 else text[:60] + "..." + text[-40:]


def claim_folder(path, option: str = "--out", command: str = "") -> Path:
    """Make path an output folder of ours (created with its parents, the marker written) and return it.

    Refused (OrchestratorError, exit 2) when path is a file or device, cannot be created, or is a non-empty folder
    without our marker: the user's files are never written over or mixed with ours.
    """
    path = check_out_dir(path, option)
    if path.is_dir() and not is_ours(path):
        try:
            occupied = any(path.iterdir())
        except OSError as exc:
            raise OrchestratorError(f"{option} {_shown(path)}: cannot list the folder: {os_problem(exc)}") from None
        if occupied:
            raise OrchestratorError(
                f"{option} {_shown(path)} is not empty and is not an output folder of orchestrator (no {MARKER}); "
                "refusing to write into it: give a new or empty folder")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OrchestratorError(f"{option} {_shown(path)}: cannot create the folder: {os_problem(exc)}") from None
    if not is_ours(path):
        info = {"created": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
                "command": command or " ".join(sys.argv[:2])}
        write_text(path / MARKER, json.dumps(info) + "\n", option, own_run_file=True)
    return path


def check_target(path, option: str = "output", inputs=(), own_run_file: bool = False, suffix: str = "") -> Path:
    """Refuse an output path (OrchestratorError, exit 2) that is not a regular file or a new name in a folder we
    can write, is one of `inputs`, is a run directory's own file (RUN_FILES, unless own_run_file), or does not end
    in `suffix` (e.g. '.png') when one is required. Returns the path."""
    path = Path(path)
    if str(path).strip() == "" or path.name in ("", ".", ".."):
        raise OrchestratorError(f"{option} {_shown(path)!r}: give the path of a file")
    if suffix and path.suffix.lower() != suffix:
        raise OrchestratorError(f"{option} {_shown(path)}: the file must end in {suffix}")
    check_out_dir(path.parent if str(path.parent) else Path("."), option)
    try:
        info = os.stat(path)
    except FileNotFoundError:
        info = None
    except OSError as exc:
        raise OrchestratorError(f"{option} {_shown(path)}: {os_problem(exc)}") from None
    if info is not None and not stat.S_ISREG(info.st_mode):
        what = "a folder" if stat.S_ISDIR(info.st_mode) else "a FIFO, device or socket"
        raise OrchestratorError(f"{option} {_shown(path)} is {what}, not a regular file; give the path of a file")
    if not own_run_file and path.name in RUN_FILES and (path.name in (MARKER, LOCK) or is_ours(path.parent)):
        raise OrchestratorError(f"{option} {_shown(path)} is a file of the run in {_shown(path.parent)}; refusing to "
                                "replace it: give another file name")
    for source in inputs:
        if source is not None and _same_file(path, Path(source)):
            raise OrchestratorError(f"{option} {_shown(path)} is also an input of this command ({_shown(source)}); "
                                    "refusing to replace it: give another file name")
    return path


def _same_file(a: Path, b: Path) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.abspath(a) == os.path.abspath(b)


@contextlib.contextmanager
def atomic(path, option: str = "output", inputs=(), own_run_file: bool = False, suffix: str = ""):
    """Context manager yielding a temporary path beside path (same folder, made if missing) to write into; when the
    block ends without error the temporary file replaces path. An OSError inside the block or at the rename becomes a
    WriteError naming path; the temporary file never stays behind."""
    path = check_target(path, option, inputs, own_run_file, suffix)
    tmp = path.with_name(f".{path.name[:200]}.{os.getpid()}.tmp")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        yield tmp
        os.replace(tmp, path)
    except OSError as exc:
        _discard(tmp)
        raise WriteError(f"cannot write {_shown(path)} ({option}): {os_problem(exc)}"
                         + _space_hint(path, exc)) from None
    except BaseException:
        _discard(tmp)
        raise


def _discard(tmp: Path) -> None:
    with contextlib.suppress(OSError):
        tmp.unlink()


def _space_hint(path: Path, exc: OSError) -> str:
    if getattr(exc, "errno", None) in (errno.ENOSPC, errno.EDQUOT):
        return "; free some space on that device, or write elsewhere"
    return ""


def write_bytes(path, data: bytes, option: str = "output", inputs=(), own_run_file: bool = False,
                suffix: str = "") -> Path:
    """Write data to path through `atomic` (checks, temporary name, rename; WriteError on OSError). Returns path."""
    with atomic(path, option, inputs, own_run_file, suffix) as tmp:
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
    return Path(path)


def write_text(path, text: str, option: str = "output", inputs=(), own_run_file: bool = False,
               suffix: str = "") -> Path:
    """write_bytes of text encoded as UTF-8."""
    return write_bytes(path, text.encode("utf-8"), option, inputs, own_run_file, suffix)


def save_figure(fig, path, option: str = "picture", dpi: int = 110, inputs=(), layout: bool = True) -> Path:
    """Lay out a matplotlib figure (layout=True: tight_layout), render it as PNG (dpi in dots per inch) and write
    it to path through write_bytes; the figure is closed either way. The path must end in .png."""
    import matplotlib.pyplot as plt

    try:
        check_target(path, option, inputs, suffix=".png")
        if layout:
            fig.tight_layout()
        buffer = io.BytesIO()
        fig.savefig(buffer, format="png", dpi=dpi)
    finally:
        plt.close(fig)
    return write_bytes(path, buffer.getvalue(), option, inputs, suffix=".png")


def free_bytes(folder) -> int | None:
    """Bytes an unprivileged writer may still use on the file system holding folder (None if unknown)."""
    try:
        info = os.statvfs(folder)
    except OSError:
        return None
    return info.f_bavail * info.f_frsize
