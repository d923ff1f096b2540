"""Yade as a program: Yade is found through its launcher (``yade`` on PATH, or
``$ORCHESTRATOR_YADE``). The script is run by the launcher's own python with
Yade's module directory on PYTHONPATH (Yade's "library mode"): unlike
``yade -n -x script.py`` this opens no TCP ports (the launcher starts a
python prompt on :9000+ and an XMLRPC server on :21000+), so parallel runs
cannot collide, and it starts faster. If the launcher cannot be read, the
backend falls back to ``yade -n -x -j N script.py``.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from functools import cached_property
from pathlib import Path

from orchestrator.engines.base import Engine
from orchestrator.processes import run_probe


class Yade(Engine):
    """Where Yade is on this machine and how to start it."""

    name = "yade"
    label, env_var, not_found = "Yade", "ORCHESTRATOR_YADE", "no 'yade' on PATH"

    def __init__(self, executable: str | None = None, threads: int = 1):
        self.executable = executable or os.environ.get("ORCHESTRATOR_YADE") or shutil.which("yade")
        self.threads = threads

    @cached_property
    def launcher(self) -> dict:
        """Interpreter, module directory and version read from the launcher script (no engine start)."""
        info = {"python": None, "module_dir": None, "version": None}
        if not self.executable:
            return info
        try:
            text = Path(self.executable).read_text(errors="replace")[:20000]
        except OSError:
            return info
        shebang = text.splitlines()[0] if text else ""
        if shebang.startswith("#!") and "python" in shebang:
            info["python"] = shebang[2:].strip().split()[0]
        m = re.search(r"sys\.path\.insert\(\s*\d+\s*,\s*'([^']+)'\s*\)", text)
        if m and Path(m.group(1)).is_dir():
            info["module_dir"] = m.group(1)
        m = re.search(r"features,version,debugbuild=.*?,\s*'([^']+)'\s*,", text)
        if m:
            info["version"] = m.group(1)
        return info

    def version(self) -> str:
        """Yade's version, e.g. '2023.02a'."""
        if self.launcher["version"]:
            return self.launcher["version"]

        try:
            out = run_probe([self.executable, "--version"]).stdout
        except (OSError, subprocess.SubprocessError):
            return "unknown"
        m = re.search(r"Yade version:\s*(\S+)", out)
        return m.group(1) if m else "unknown"

    def command(self, script: str) -> tuple[list[str], dict[str, str]]:
        """Command line and environment that run a Yade script headless."""
        env = {"OMP_NUM_THREADS": str(self.threads), "OMP_WAIT_POLICY": "PASSIVE", "DISPLAY": ""}
        info = self.launcher
        if info["python"] and info["module_dir"] and Path(info["python"]).exists():
            env["PYTHONPATH"] = info["module_dir"]
            return [info["python"], "-u", script], env
        return [self.executable, "-n", "-x", "-j", str(self.threads), script], env

    def install_hint(self) -> str:
        """How to install Yade."""
        return "install it with 'sudo apt-get install yade' (Debian 12 / Ubuntu), or run 'make demo'"

    def run_command(self, script: str, workdir: Path) -> tuple[list[str], dict[str, str]]:
        """command(script) with Yade's scratch directory inside the run (workdir/tmp), not in /tmp."""
        command, env = self.command(script)
        scratch = Path(workdir) / "tmp"
        scratch.mkdir(exist_ok=True)
        return command, {**env, "TMPDIR": str(scratch.resolve())}
