"""CLI behaviour that needs no engine: missing engine, doctor, help speed, export/analyze of a non-run."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from paths import TINY_BOWL



def cli(*args, env=None, cwd=None):
    return subprocess.run([sys.executable, "-m", "orchestrator", *args], capture_output=True, text=True,
                          timeout=120, env={**os.environ, **(env or {})}, cwd=cwd)


def test_missing_engine_is_named_with_what_to_do(tmp_path):
    proc = cli("run", str(TINY_BOWL), "--out", str(tmp_path / "r"), env={"ORCHESTRATOR_YADE": "/nonexistent/yade"})
    assert proc.returncode == 3
    assert proc.stderr.startswith("error: Yade is not installed") and "apt-get install yade" in proc.stderr
    assert "Traceback" not in proc.stderr
    assert not (tmp_path / "r" / "run.h5").exists()


def test_doctor_reports_missing_engine(tmp_path):
    proc = cli("doctor", "--json", env={"ORCHESTRATOR_YADE": "/nonexistent/yade"})
    rows = {row["engine"]: row for row in json.loads(proc.stdout)}
    assert rows["yade"]["found"] is False and "apt-get install yade" in rows["yade"]["hint"]


def test_existing_run_is_not_overwritten_without_force(tmp_path):
    run_dir = tmp_path / "r"
    run_dir.mkdir()
    (run_dir / "run.h5").write_bytes(b"x")
    proc = cli("run", str(TINY_BOWL), "--out", str(run_dir))
    assert proc.returncode == 2 and "--force" in proc.stderr
    assert (run_dir / "run.h5").read_bytes() == b"x"


def test_export_and_analyze_need_a_run(tmp_path):
    for command in ("export", "analyze"):
        proc = cli(command, str(tmp_path))
        assert proc.returncode == 6 and proc.stderr.startswith("error:") and "run.h5" in proc.stderr
        assert "Traceback" not in proc.stderr


COMMANDS = ("run", "analyze", "study", "status", "report", "verify", "calibrate", "network-sensitivity", "rheometry",
            "compare", "bench", "doctor", "export")


def test_help_lists_every_command():
    import re

    proc = cli("--help")
    assert sorted(re.findall(r"^    ([\w-]+)", proc.stdout, re.M)) == sorted(COMMANDS)


@pytest.mark.parametrize("command", COMMANDS)
def test_every_command_has_its_help(command, capsys):
    from orchestrator.cli import main

    with pytest.raises(SystemExit) as stopped:
        main([command, "--help"])
    out = capsys.readouterr().out
    assert stopped.value.code == 0 and out.startswith(f"usage: orchestrator {command}")
    assert len(out.splitlines()) > 4  # the options, each explained


def test_every_command_has_its_module_and_function():
    """One module per command (issue 12 item 4): each registers its parsers with a function to run, and no
    function of the command line is over 150 lines."""
    import argparse
    import ast
    import pkgutil

    import orchestrator.cli as cli

    sub = next(a for a in cli._parser()._actions if isinstance(a, argparse._SubParsersAction))
    assert list(sub.choices) == list(COMMANDS)
    assert all(callable(parser.get_default("func")) for parser in sub.choices.values())
    for info in pkgutil.iter_modules(cli.__path__):
        path = Path(cli.__path__[0]) / f"{info.name}.py"
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                assert node.end_lineno - node.lineno < 150, f"{path.name}: {node.name}"
