"""Numbers, exit codes and file-system problems told for people."""

from __future__ import annotations

import datetime as _dt
import errno
import os
import re
import signal
from pathlib import Path

from orchestrator.errors import OrchestratorError


def duration(seconds: float) -> str:
    """A wall time in s, min, h, days or years, e.g. '20.3 h'."""
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    if seconds < 3 * 86400:
        return f"{seconds / 3600:.1f} h"
    if seconds < 3 * 365 * 86400:
        return f"{seconds / 86400:.1f} days"
    return f"{seconds / (365 * 86400):.0f} years"


def byte_size(count: float) -> str:
    """A number of bytes in B, KiB, MiB, GiB, TiB or PiB, e.g. '3.2 GiB' (beyond PiB in PiB)."""
    size = float(count)
    for unit in ("B", "KiB", "MiB", "GiB", "TiB"):
        if abs(size) < 1024.0:
            return f"{size:.3g} {unit}"
        size /= 1024.0
    return f"{size:.3g} PiB"


def describe_returncode(code: int) -> str:
    """How a process ended, from its return code: 'exited with code 3', or for a negative code (killed by a
    signal, as subprocess reports it) 'was killed by signal 9 (SIGKILL: Killed)'."""
    if code is None:
        return "is still running"
    if code >= 0:
        return f"exited with code {code}"
    number = -code
    try:
        name = signal.Signals(number).name
    except ValueError:
        return f"was killed by signal {number}"
    meaning = signal.strsignal(number) or ""
    hint = {signal.SIGKILL: "; often the kernel's out-of-memory killer, or kill -9",
            signal.SIGSEGV: "; a crash of the engine"}.get(number, "")
    return f"was killed by signal {number} ({name}{': ' + meaning if meaning else ''}{hint})"


#: errno -> what it means for a folder we want to write into.
_OS_REASONS = {
    errno.EACCES: "permission denied",
    errno.EPERM: "permission denied",
    errno.EROFS: "the file system is read-only",
    errno.ENAMETOOLONG: "a name in the path is longer than the file system allows",
    errno.ENOTDIR: "a part of the path is a file, not a folder",
    errno.ENOSPC: "no space left on the device",
    errno.EEXIST: "a file of that name exists",
    errno.ELOOP: "too many symbolic links",
}


def os_problem(exc: OSError) -> str:
    """What an OSError means, in a few words (e.g. 'permission denied')."""
    return _OS_REASONS.get(exc.errno, exc.strerror or str(exc))


def check_out_dir(path, option: str = "--out") -> Path:
    """Check that `path` can be (or already is) a folder we may write into, without creating anything.

    Raises OrchestratorError (exit 2) naming the option and the path when it is empty, names a file or a
    device, has a name longer than the file system allows (NAME_MAX, usually 255 bytes), or lies in a
    folder that cannot be written. Returns the path.
    """

    text = str(path)
    if text.strip() == "":
        raise OrchestratorError(f"{option} is empty; give the path of a folder")
    path = Path(path)
    shown = text if len(text) <= 120 else text[:60] + "..." + text[-40:]
    for part in path.parts:
        size = len(os.fsencode(part))
        if size > _name_max(path):
            raise OrchestratorError(f"{option} {shown}: the name {part[:30]!r}... is {size} bytes long; allowed: "
                                    f"at most {_name_max(path)} bytes per name on this file system")
    if len(os.fsencode(text)) >= 4096:
        raise OrchestratorError(f"{option} {shown}: the path is {len(os.fsencode(text))} bytes long; allowed: "
                                "less than 4096 bytes")
    existing = path
    while True:
        try:
            existing.stat()
            break
        except FileNotFoundError:
            existing = existing.parent
        except OSError as exc:
            raise OrchestratorError(f"{option} {shown}: {os_problem(exc)}") from None
    if not existing.is_dir():
        kind = "a file" if existing.is_file() else "a device or special file"
        what = f"is {kind}" if existing == path else f"lies under {existing}, which is {kind}"
        raise OrchestratorError(f"{option} {shown} {what}, not a folder; give a new or existing folder")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise OrchestratorError(f"{option} {shown}: cannot write into {existing} (permission denied or read-only); "
                                "give a folder you can write to")
    return path


#: Characters of a case name kept in a folder name made from it (file systems allow 255 bytes per name).
STAMPED_NAME_MAX = 100


def stamped_dir(name: str, root=Path("runs")) -> Path:
    """root/<name>-<UTC timestamp, seconds>, with -2, -3 ... appended when that exists (the path of a new folder,
    not created): how every command names the folder it makes when no --out is given. The name keeps letters,
    digits and ._+- (other runs of characters become _) and at most STAMPED_NAME_MAX characters."""
    stamp = _dt.datetime.now(_dt.timezone.utc).strftime("%Y%m%dT%H%M%S")
    name = re.sub(r"[^A-Za-z0-9._+-]+", "_", name).strip("._") or "run"
    base = Path(root) / f"{name[:STAMPED_NAME_MAX]}-{stamp}"
    path, n = base, 1
    while path.exists():
        n += 1
        path = base.with_name(f"{base.name}-{n}")
    return path


def make_out_dir(path, option: str = "--out") -> Path:
    """check_out_dir, then create the folder (and its parents); an OSError becomes an OrchestratorError."""

    path = check_out_dir(path, option)
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OrchestratorError(f"{option} {path}: cannot create the folder: {os_problem(exc)}") from None
    return path


def _name_max(path: Path) -> int:
    """NAME_MAX of the file system holding the nearest existing folder of path (255 if unknown)."""
    folder = Path(os.path.abspath(path))
    while True:
        try:
            return int(os.pathconf(folder, "PC_NAME_MAX"))
        except (OSError, ValueError):
            if folder.parent == folder:
                return 255
            folder = folder.parent
