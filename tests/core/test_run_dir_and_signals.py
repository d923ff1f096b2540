"""Run directories are never shared, clobbered or mixed; SIGINT, SIGTERM and SIGHUP stop a run cleanly.

In-process tests use the reference DEM engine (pure Python, always installed); the real-signal tests run
`python -m orchestrator` as a subprocess on the sph executable and are skipped without it.
"""

from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import pytest

from orchestrator import signals
from orchestrator.cli import main
from orchestrator.rundir import LOCK, MARKER, RunDirectory
from paths import CASES, VERIFICATION

SPHERE_PLANE = VERIFICATION / "chung_ooi_test2_sphere_plane.toml"
DAM_BREAK = CASES / "sph" / "dam_break_2d.toml"
needs_sph = pytest.mark.sph


def _run_reference(out: Path, *extra: str) -> int:
    return main(["run", str(SPHERE_PLANE), "--engine", "reference", "--out", str(out), "--no-progress", *extra])


def _tree(path: Path) -> dict[str, bytes]:
    return {str(p.relative_to(path)): p.read_bytes() for p in sorted(path.rglob("*")) if p.is_file()}


def test_a_locked_run_directory_is_refused_at_once_naming_the_other_run(tmp_path, capsys):
    out = tmp_path / "run"
    with RunDirectory(out):  # another run holds it
        start = time.monotonic()
        code = _run_reference(out)
        elapsed = time.monotonic() - start
    err = capsys.readouterr().err
    assert code == 2 and elapsed < 5.0
    assert err.count("error:") == 1 and "in use by another run" in err and f"pid {os.getpid()}" in err
    assert not (out / "run.h5").exists()
    assert _run_reference(out) == 0  # released: the next run goes ahead
    with h5py.File(out / "run.h5") as h5:
        assert h5.attrs["status"] == "ok" and "normal_force" in h5["series"]


@pytest.mark.parametrize("where", ["cwd", "folder"])
def test_a_users_folder_is_never_written_into(tmp_path, capsys, monkeypatch, where):
    users = tmp_path / "mine"
    users.mkdir()
    (users / "case.toml").write_text("my own case\n")
    (users / "notes").mkdir()
    (users / "notes" / "a.txt").write_text("keep me\n")
    before = _tree(users)
    if where == "cwd":
        monkeypatch.chdir(users)
        out = "."
    else:
        out = str(users)
    for extra in ((), ("--force",)):
        code = main(["run", str(SPHERE_PLANE), "--engine", "reference", "--out", out, "--no-progress", *extra])
        err = capsys.readouterr().err
        assert code == 2 and "not a run directory of orchestrator" in err and "Traceback" not in err
        assert _tree(users) == before


def test_empty_out_and_a_file_as_out_are_refused(tmp_path, capsys):
    assert main(["run", str(SPHERE_PLANE), "--engine", "reference", "--out", "", "--no-progress"]) == 2
    assert "--out is empty" in capsys.readouterr().err
    target = tmp_path / "file.txt"
    target.write_text("x")
    assert _run_reference(target) == 2
    assert "is a file, not a folder" in capsys.readouterr().err
    assert target.read_text() == "x"


def test_force_removes_the_old_run_before_the_engine_starts(tmp_path, capsys, monkeypatch):
    """A forced rerun whose engine takes no step must not carry the old run's samples or numbers."""
    out = tmp_path / "run"
    assert _run_reference(out) == 0
    with h5py.File(out / "run.h5") as h5:
        assert h5.attrs["n_steps"] > 100 and len(h5["series"]["time"]) > 10
    assert _run_reference(out) == 2  # without --force: refused, kept
    assert "already holds a run" in capsys.readouterr().err

    from orchestrator.kinds.impact.reference import ReferenceImpact

    monkeypatch.setattr(ReferenceImpact, "command", lambda self, profile, scene, workdir: (["false"], {}))
    code = _run_reference(out, "--force")
    assert code == 4
    with h5py.File(out / "run.h5") as h5:
        assert h5.attrs["status"] == "failed"
        assert h5.attrs["n_steps"] == 0
        assert "series" not in h5 or "time" not in h5["series"] or len(h5["series"]["time"]) == 0
        assert not h5["measured"].attrs.keys() if "measured" in h5 else True
    assert not (out / "output").exists() or not any((out / "output").iterdir())
    assert (out / MARKER).is_file() and (out / LOCK).is_file()


def test_a_measurement_that_fails_keeps_the_run(tmp_path, capsys, monkeypatch):
    """A bug in a kind's analysis measures nothing: run.h5 is written with the engine's output and one warning
    names the traceback's file; `analyze` measures the run again with the mended code."""
    import orchestrator.measure

    def broken(case, result):
        raise ImportError("cannot import name 'moved'")

    monkeypatch.setattr(orchestrator.measure, "measure", broken)
    out = tmp_path / "run"
    assert _run_reference(out) == 0
    err = capsys.readouterr().err
    assert err.count("warning: measuring the run failed (ImportError: cannot import name 'moved'") == 1
    log = Path(err.split("traceback in ")[1].split(")")[0])
    assert "ImportError" in log.read_text()
    log.unlink()
    with h5py.File(out / "run.h5") as h5:
        assert h5.attrs["status"] == "ok" and "normal_force" in h5["series"]
        assert "measured" not in h5 or not h5["measured"].attrs.keys()
    monkeypatch.undo()
    assert main(["analyze", str(out), "--no-render"]) == 0
    assert "max_normal_force             11370" in capsys.readouterr().out  # measured again by the mended analysis


def test_a_swallowed_signal_is_raised_again_at_the_next_check():
    with signals.installed():
        try:
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(0.1)
        except BaseException:  # what a library's `except BaseException` does during an import
            pass
        with pytest.raises(signals.Interrupted) as caught:
            signals.check()
        assert caught.value.signum == signal.SIGTERM and caught.value.exit_code == 143
    signals.check()  # outside the block the signal is forgotten


@pytest.mark.parametrize("where", ["_parser", "_command"])
def test_a_signal_that_breaks_an_import_ends_with_its_exit_code_not_an_internal_error(monkeypatch, capsys, where):
    """A C extension that is interrupted while it initialises raises ImportError('initialization failed') from
    the signal (scipy's does): while the command's parser is built and inside a command, that is the signal's exit
    code and message, never a traceback or 'internal error'."""
    import orchestrator.cli as cli

    def broken_import(*args):
        try:
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(1)
        except KeyboardInterrupt as exc:
            raise ImportError("initialization failed") from exc
        raise AssertionError("the signal did not arrive")

    if where == "_parser":
        monkeypatch.setattr(cli, "_parser", broken_import)
    else:
        class Parser:
            def parse_args(self, argv):
                return argparse.Namespace(command="doctor", func=broken_import)

        monkeypatch.setattr(cli, "_parser", Parser)
    assert main(["doctor"]) == 143
    err = capsys.readouterr().err
    assert "stopped by SIGTERM" in err and "internal error" not in err and "Traceback" not in err


def test_a_signal_while_run_h5_is_written_is_raised_after_it():
    with signals.installed():
        with pytest.raises(signals.Interrupted):
            with signals.deferred():
                os.kill(os.getpid(), signal.SIGHUP)
                time.sleep(0.05)
                finished = True  # the block runs to its end
        assert finished


# ---- real signals to a real run (sph executable) ----

def _start(out: Path, duration: float = 2.0) -> subprocess.Popen:
    env = {**os.environ, "OMP_WAIT_POLICY": "PASSIVE"}
    return subprocess.Popen(
        [sys.executable, "-m", "orchestrator", "run", str(DAM_BREAK), "--preset", "tiny", "--set",
         f"simulation.duration={duration}", "--out", str(out), "--no-progress"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env, start_new_session=True)


def _engine_pids(out: Path) -> list[int]:
    """Processes whose working directory is the run directory (the engine)."""
    pids = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                if Path(os.readlink(entry / "cwd")) == out.resolve():
                    pids.append(int(entry.name))
            except OSError:
                continue
    return pids


def _wait_for_engine(out: Path, proc: subprocess.Popen, timeout: float = 60.0) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if (out / "engine.log").is_file() and (out / "engine.log").stat().st_size > 0 and _engine_pids(out):
            return
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.05)
    raise AssertionError("the engine did not start")


@needs_sph
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP, signal.SIGINT])
def test_a_signal_mid_run_keeps_what_was_measured_and_leaves_no_engine(tmp_path, sig):
    out = tmp_path / "run"
    proc = _start(out)
    _wait_for_engine(out, proc)
    time.sleep(0.5)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 128 + sig, err
    assert err.count("error:") == 1 and "Traceback" not in err
    assert f"stopped by {'Ctrl-C (SIGINT)' if sig == signal.SIGINT else signal.Signals(sig).name}" in err
    assert "run.h5" in err and "records what was measured" in err
    with h5py.File(out / "run.h5") as h5:
        assert h5.attrs["status"] == "terminated"
        assert len(h5["series"]["time"]) >= 1 and h5.attrs["n_steps"] > 0
    assert _engine_pids(out) == []


def test_an_early_ctrl_c_is_never_swallowed(tmp_path):
    """Ctrl-C at any moment of the start-up (imports, scene, input) ends the command with 130, and the message
    says whether a run.h5 exists."""
    outcomes = []
    for delay in (0.2, 0.5, 0.8, 1.1):
        out = tmp_path / f"run-{delay}"
        proc = subprocess.Popen(
            [sys.executable, "-m", "orchestrator", "run", str(SPHERE_PLANE), "--engine", "reference",
             "--out", str(out), "--no-progress"],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
        time.sleep(delay)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=120)
        if proc.returncode == 0:  # it had already finished: that is fine, but then run.h5 is complete
            with h5py.File(out / "run.h5") as h5:
                assert h5.attrs["status"] == "ok"
            continue
        if proc.returncode == -signal.SIGINT:  # on a loaded machine: before the interpreter had its handler (or
            # after it gave it back on exit), so the default action ended it, as a shell shows Ctrl-C: nothing of
            # ours had started, or the run had finished
            assert "error:" not in err, err
            if (out / "run.h5").is_file():
                with h5py.File(out / "run.h5") as h5:
                    assert h5.attrs["status"] == "ok"
            continue
        assert proc.returncode == 130, err
        assert "Traceback" not in err and err.count("error:") == 1
        written = (out / "run.h5").is_file()
        assert ("records what was measured" in err) == written, err
        assert ("no run.h5 was written" in err) == (not written), err
        if written:  # cut short; or, on a loaded machine, the Ctrl-C came after the run had completed its run.h5
            with h5py.File(out / "run.h5") as h5:
                assert h5.attrs["status"] in ("terminated", "ok")
        outcomes.append(written)
    assert outcomes, "every run finished before its Ctrl-C"


def test_sigterm_to_a_study_stops_its_workers_engines_and_keeps_the_finished_runs(tmp_path):
    """SIGTERM to `orchestrator study` reaches the workers: every engine stops, the stopped runs keep a run.h5
    with status terminated, and the command exits 143 saying what is on disk."""
    study = tmp_path / "study.toml"
    study.write_text(
        "[study]\nname = \"stop_me\"\n"
        f"case = \"{SPHERE_PLANE}\"\nengines = [\"reference\"]\n\n"
        "[sweep]\nmode = \"grid\"\n[sweep.parameters]\n"
        "\"numerics.timestep_factor\" = [0.0004, 0.0005, 0.0006, 0.0007]\n")
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "orchestrator", "study", str(study), "--out", str(out),
                             "--workers", "2", "--no-progress"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and len(list(out.glob("*/engine.log"))) < 2:
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.1)
    time.sleep(1.0)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 143, err
    assert "Traceback" not in err and err.count("error:") == 1 and "stopped by SIGTERM" in err
    # what the message says is on disk: the index of finished runs, or that none had finished
    assert ("index.csv" in err) == (out / "index.csv").is_file() or "no run of the study had finished" in err
    statuses = []
    for run_dir in out.glob("*/"):
        assert _engine_pids(run_dir) == []
        if (run_dir / "run.h5").is_file():
            with h5py.File(run_dir / "run.h5") as h5:
                statuses.append(h5.attrs["status"])
    assert "terminated" in statuses
