"""The output policy (orchestrator/outputs.py) through the commands: no command destroys a user's file, a run's own
files or its inputs; a full disk, a FIFO, a second signal or an engine's background child never crash, hang or
leak; counts are bounded before anything is built. Each test ends with the promised exit code, exactly one
'error:' line, no traceback, and the user's files byte-identical."""

from __future__ import annotations

import errno
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from orchestrator import outputs
from orchestrator.cli import main
from orchestrator.errors import OrchestratorError
from orchestrator.humanize import stamped_dir
from orchestrator.processes import probe_bound, run_probe, session_members
from orchestrator.runner import execute
from paths import CASES, DATA

DAM = CASES / "sph" / "dam_break_2d.toml"
UCM = CASES / "rheometry" / "ucm_one_mode.toml"
MODULI = CASES / "rheometry" / "mf20_synthetic_moduli.csv"


def snapshot(folder: Path) -> dict:
    """{relative path: bytes} of every file under folder (what must stay byte-identical)."""
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def refused(capsys, argv, code=2) -> str:
    """Run the CLI; assert the exit code, one 'error:' line and no traceback; return the error text."""
    assert main(argv) == code
    err = capsys.readouterr().err
    assert err.count("error:") == 1, err
    assert "Traceback" not in err and "internal error" not in err, err
    return err


@pytest.fixture
def foreign(tmp_path) -> Path:
    """A user's folder: a run.h5 of its own, notes, a sub-folder."""
    d = tmp_path / "X"
    (d / "sub").mkdir(parents=True)
    (d / "run.h5").write_text("x\n")
    (d / "notes.txt").write_text("p\n")
    (d / "sub" / "t.tex").write_text("p\n")
    (d / "rheometry.png").write_text("mine\n")
    return d


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory) -> Path:
    """A finished sph run directory (the 2D dam break's first 20 ms, about 5 s)."""
    from orchestrator.engines import get_engine

    if not get_engine("sph").available():
        pytest.skip("the sph executable is not built (make sph)")
    run = tmp_path_factory.mktemp("runs") / "db"
    assert main(["run", str(DAM), "--preset", "tiny", "--out", str(run)]) == 0
    return run


# ---------------------------------------------------------------- data destroyed

@pytest.mark.sph  # the run is refused at its folder, after the engine is found
@pytest.mark.parametrize("force", [[], ["--force"]])
def test_run_never_empties_a_users_folder_that_holds_a_run_h5(capsys, foreign, force):
    before = snapshot(foreign)
    err = refused(capsys, ["run", str(DAM), "--preset", "tiny", "--out", str(foreign), *force])
    assert "not a run directory of orchestrator" in err
    assert snapshot(foreign) == before
    assert not (foreign / outputs.LOCK).exists()


@pytest.mark.sph
@pytest.mark.parametrize("name", ["run.h5", "case.toml", ".orchestrator-run"])
def test_analyze_summary_never_replaces_a_runs_own_file(capsys, tiny_run, name):
    before = snapshot(tiny_run)
    err = refused(capsys, ["analyze", str(tiny_run), "--summary", str(tiny_run / name)])
    assert name in err
    after = snapshot(tiny_run)
    assert {k: v for k, v in after.items() if not k.endswith(".png")} == \
        {k: v for k, v in before.items() if not k.endswith(".png")}


@pytest.mark.sph
def test_analyze_summary_to_a_fifo_is_refused_without_blocking(capsys, tiny_run, tmp_path):
    fifo = tmp_path / "summary.json"
    os.mkfifo(fifo)
    start = time.monotonic()
    err = refused(capsys, ["analyze", str(tiny_run), "--summary", str(fifo)])
    assert "not a regular file" in err and time.monotonic() - start < 30


@pytest.mark.parametrize("argv", [
    ["rheometry", str(UCM), "--frequencies", "1"],
    ["compare", str(DAM), "--engines", "sph", "--preset", "tiny"],
    ["bench", "sph"],
])
def test_commands_refuse_a_users_nonempty_out_folder(capsys, foreign, argv):
    before = snapshot(foreign)
    err = refused(capsys, [*argv, "--out", str(foreign)])
    assert "not an output folder of orchestrator" in err
    assert snapshot(foreign) == before


@pytest.mark.sph
def test_export_refuses_a_users_nonempty_out_folder(capsys, tiny_run, foreign):
    before = snapshot(foreign)
    refused(capsys, ["export", str(tiny_run), "--out", str(foreign)])
    assert snapshot(foreign) == before


def test_calibrate_never_writes_over_its_own_input(capsys, tmp_path):
    data = tmp_path / "c.csv"
    data.write_bytes(MODULI.read_bytes())
    err = refused(capsys, ["calibrate", "maxwell", "--csv", str(data), "--modes", "2", "--out", str(data),
                           "--force"])
    assert "input of this command" in err
    assert data.read_bytes() == MODULI.read_bytes()


# ---------------------------------------------------------------- faults

def test_a_full_disk_while_writing_is_one_clean_error(tmp_path, monkeypatch):
    target = tmp_path / "out.txt"
    target.write_text("old\n")

    class Full:
        def __init__(self, *a):
            pass

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            return False

        def write(self, data):
            raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(outputs.os, "fdopen", Full)
    with pytest.raises(outputs.WriteError, match="no space left on the device") as info:
        outputs.write_text(target, "new\n", "--out")
    assert info.value.exit_code == 8
    assert target.read_text() == "old\n"
    assert [p.name for p in tmp_path.iterdir()] == ["out.txt"]  # no temporary file stays


@pytest.mark.sph
def test_run_h5_on_a_full_disk_keeps_the_engines_output(capsys, tmp_path, monkeypatch):
    import orchestrator.runh5 as runh5

    monkeypatch.setattr(runh5, "free_bytes", lambda folder: 1000)
    run = tmp_path / "full"
    err = refused(capsys, ["run", str(DAM), "--preset", "tiny", "--out", str(run)], code=8)
    assert "the engine's own output is kept in" in err and "out.h5" in err
    assert (run / "out.h5").stat().st_size > 100_000 and not (run / "run.h5").exists()
    assert not [p for p in run.iterdir() if p.name.endswith(".tmp")]


@pytest.mark.sph
@pytest.mark.skipif(os.geteuid() != 0, reason="mounting a small tmpfs needs root")
def test_run_on_a_real_full_tmpfs(tmp_path):
    mount = tmp_path / "small"
    mount.mkdir()
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=450k", "tmpfs", str(mount)]).returncode != 0:
        pytest.skip("this machine does not let root mount a tmpfs")
    try:
        proc = subprocess.run([sys.executable, "-m", "orchestrator", "run", str(DAM), "--preset", "tiny", "--out",
                               str(mount / "run")], capture_output=True, text=True, timeout=300)
        assert proc.returncode == 8, proc.stderr
        assert proc.stderr.count("error:") == 1 and "Traceback" not in proc.stderr
        assert (mount / "run" / "out.h5").stat().st_size > 100_000
    finally:
        subprocess.run(["umount", str(mount)])


def test_verify_skips_no_fifo_and_never_blocks_on_one(capsys, tmp_path):
    cases = tmp_path / "cases"
    cases.mkdir()
    os.mkfifo(cases / "x.toml")
    start = time.monotonic()
    err = refused(capsys, ["verify", "dem", "--cases", str(cases), "--out", str(tmp_path / "out")])
    assert "not a regular file" in err and time.monotonic() - start < 30


# ---------------------------------------------------------------- signals and processes

def test_a_second_signal_during_cleanup_is_absorbed(tmp_path):
    script = textwrap.dedent("""
        import os, signal, sys
        from orchestrator import signals
        with signals.installed():
            try:
                os.kill(os.getpid(), signal.SIGTERM)
            except signals.Interrupted as exc:
                os.kill(os.getpid(), signal.SIGTERM)  # a second one while the first is acted on
                print("handled", exc.exit_code)
        print("left cleanly")
    """)
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["handled", "143", "left", "cleanly"] and "Traceback" not in proc.stderr


def test_an_engines_background_child_is_stopped_with_it(tmp_path):
    execution = execute(["sh", "-c", "sleep 300 & echo $! > child.pid; echo started"], {}, tmp_path,
                        progress=False)
    assert execution.returncode == 0
    child = int((tmp_path / "child.pid").read_text())
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and _alive(child):
        time.sleep(0.1)
    assert not _alive(child)


def test_a_version_probe_is_bounded_and_stops_its_tree(tmp_path):
    start = time.monotonic()
    with probe_bound(1.0), pytest.raises(subprocess.TimeoutExpired):
        run_probe(["sh", "-c", f"sleep 300 & echo $! > {tmp_path}/child.pid; sleep 300"])
    assert time.monotonic() - start < 15
    child = int((tmp_path / "child.pid").read_text())
    assert not _alive(child)


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat", "rb") as fh:
            return fh.read().rsplit(b")", 1)[1].split()[0] != b"Z"
    except OSError:
        return False


def test_session_members_finds_this_session():
    assert os.getpid() in session_members(os.getsid(0))


# ---------------------------------------------------------------- bounds and wrong answers

@pytest.mark.parametrize("args, words", [
    (["--modes", "99999999999999999999"], "--modes"),
    (["--modes", "2", "--png", "x.exe"], "must end in .png"),
    (["--modes", "2", "--png", "/dev/full"], "must end in .png"),
])
def test_calibrate_bounds_and_pictures(capsys, args, words, tmp_path):
    err = refused(capsys, ["calibrate", "maxwell", "--csv", str(MODULI), *args])
    assert words in err


def test_calibrate_png_that_is_a_folder(capsys, tmp_path):
    folder = tmp_path / "p.png"
    folder.mkdir()
    err = refused(capsys, ["calibrate", "maxwell", "--csv", str(MODULI), "--modes", "2", "--png", str(folder)])
    assert "is a folder" in err


@pytest.mark.parametrize("value", ["5e-324", "1e308"])
def test_calibrate_refuses_moduli_beyond_the_range(capsys, tmp_path, value):
    data = tmp_path / "m.csv"
    data.write_text(f"omega_rad_s,G_storage_Pa,G_loss_Pa\n1,{value},1\n2,2,2\n3,3,3\n")
    err = refused(capsys, ["calibrate", "maxwell", "--csv", str(data), "--modes", "1"])
    assert "G_storage_Pa" in err and "allowed" in err


def test_calibrate_refuses_too_many_rows(capsys, tmp_path):
    data = tmp_path / "m.csv"
    rows = "".join(f"{w},{w},{w}\n" for w in range(1, 2 + 2001))
    data.write_text("omega_rad_s,G_storage_Pa,G_loss_Pa\n" + rows)
    err = refused(capsys, ["calibrate", "maxwell", "--csv", str(data), "--modes", "1"])
    assert "at most 2000" in err


@pytest.mark.parametrize("argv", [
    ["rheometry", str(UCM), "--frequencies", "1e-30"],
    ["rheometry", str(UCM), "--frequencies", "1e30"],
    ["rheometry", str(UCM), "--set", "numerics.quasi_static=1e9"],
])
def test_internally_built_cases_name_their_key(capsys, tmp_path, argv):
    err = refused(capsys, [*argv, "--out", str(tmp_path / "r")])
    assert "allowed" in err and "validation error" not in err


def test_a_long_case_name_makes_a_folder_name_the_file_system_takes():
    path = stamped_dir("n" * 5000 + "/../x")
    assert len(path.name) < 200 and "/" not in path.name and ".." not in path.name


def test_check_target_refuses_devices_and_folders(tmp_path):
    with pytest.raises(OrchestratorError, match="not a regular file"):
        outputs.check_target("/dev/null", "--out")
    with pytest.raises(OrchestratorError, match="is a folder"):
        outputs.check_target(tmp_path, "--out")
    assert outputs.check_target(tmp_path / "new.json", "--out") == tmp_path / "new.json"


STL_FACET = "solid t\nfacet normal 0 0 1\nouter loop\nvertex {a}\nvertex {b}\nvertex {c}\nendloop\nendfacet\nendsolid t\n"


@pytest.mark.parametrize("vertices, words", [
    (("0 0 0", "1e300 0 0", "0 1 0"), "beyond 1e+30 m"),
    (("0 0 0", "0 0 0", "0 0 0"), "degenerate"),
])
def test_meshes_are_checked_before_any_scene_is_built(capsys, tmp_path, vertices, words):
    mesh = tmp_path / "m.stl"
    mesh.write_text(STL_FACET.format(a=vertices[0], b=vertices[1], c=vertices[2]))
    channel = DATA / "sph_channel_3d.toml"
    err = refused(capsys, ["run", str(channel), "--set", f'walls.2.file="{mesh}"', "--out", str(tmp_path / "r")])
    assert "walls[2].file" in err and words in err
    assert not (tmp_path / "r").exists()


@pytest.mark.sph
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_pool_workers_stop_quietly_on_a_signal(tmp_path, sig):
    proc = subprocess.Popen([sys.executable, "-m", "orchestrator", "rheometry", str(UCM), "--frequencies", "0.5",
                             "1", "2", "4", "--workers", "2", "--out", str(tmp_path / "r")],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and not list((tmp_path / "r").glob("omega_*/engine.log")):
        time.sleep(0.1)
    proc.send_signal(sig)
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 128 + sig, err
    assert "Traceback" not in err and err.count("error:") == 1, err


@pytest.mark.sph
def test_resume_of_a_truncated_output_is_an_unreadable_output(capsys, tiny_run, tmp_path):
    import shutil

    run = tmp_path / "run"
    shutil.copytree(tiny_run, run)
    data = (run / "out.h5").read_bytes()
    (run / "out.h5").write_bytes(data[: len(data) // 2])
    err = refused(capsys, ["run", "--resume", str(run), "--until", "0.04"], code=6)
    assert "truncated" in err and (run / "out.h5").stat().st_size == len(data) // 2


@pytest.mark.sph
def test_building_a_scene_counts_against_the_timeout(capsys, tmp_path):
    drill = CASES / "ejector_drill_canini.toml"
    start = time.monotonic()
    err = refused(capsys, ["run", str(drill), "--preset", "flow_exit_quick", "--set", "scene.inlet_distance=10",
                           "--timeout", "2", "--out", str(tmp_path / "r")], code=5)
    assert "building the scene" in err and time.monotonic() - start < 60
    assert not (tmp_path / "r").exists()


def test_a_stop_signals_each_process_of_the_session_once(tmp_path):
    """The group gets the signal once, and only processes that left the group get it again one by one: a script
    that saves a checkpoint on SIGTERM (Yade's) is not interrupted by a second one."""
    script = tmp_path / "count.py"
    script.write_text("import signal, sys, time\nn = []\n"
                      "signal.signal(signal.SIGTERM, lambda *a: n.append(1))\n"
                      "t = time.time()\nwhile time.time() - t < 3: time.sleep(0.05)\n"
                      f"open({str(tmp_path / 'n.txt')!r}, 'w').write(str(len(n)))\n")
    proc = subprocess.Popen([sys.executable, str(script)], start_new_session=True)
    time.sleep(0.5)
    from orchestrator.processes import stop_session

    stop_session(proc, grace_s=10.0)
    assert (tmp_path / "n.txt").read_text() == "1"
