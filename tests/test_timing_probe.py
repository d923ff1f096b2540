"""The timing probe before a long run (orchestrator.run._run_probe): its estimate is announced and kept as the run's,
a probe that fails is named in a warning (the run goes on), and the ejector drill's probe runs from any working
directory (its deck directory is absolute: the probe process runs inside it)."""

from __future__ import annotations

import sys
from pathlib import Path

from orchestrator.run import _run_probe


class FakeBackend:
    """probe_command runs a Python one-liner in the probe directory."""

    def __init__(self, code: str):
        self.code = code

    def probe_command(self, scene, workdir: Path):
        return [sys.executable, "-c", self.code], {}


def test_a_probe_that_reports_gives_its_estimate(tmp_path):
    seen = []
    code = "print('TIMING s_per_step=0.25 planned_steps=400 estimate_s=100', flush=True)"
    timing = _run_probe(FakeBackend(code), None, tmp_path, seen.append)
    assert timing is not None and timing.estimate_s == 100.0 and timing.planned_steps == 400
    assert seen == [timing]


def test_a_failed_probe_is_named_and_the_run_goes_on(tmp_path, capsys):
    seen = []
    code = "import sys; print('error: the probe deck is broken', flush=True); sys.exit(3)"
    assert _run_probe(FakeBackend(code), None, tmp_path, seen.append) is None
    err = capsys.readouterr().err
    assert "warning: the timing probe gave no estimate" in err and "the probe deck is broken" in err
    assert str(tmp_path / "probe" / "engine.log") in err and not seen


def test_the_drill_probe_deck_dir_is_absolute(tmp_path, monkeypatch):
    """A run directory given relative to the working directory (orchestrator run's default 'runs/...'): the probe's
    command names its deck directory absolutely (the probe process's cwd is that directory already)."""
    from orchestrator.case import load_case
    from orchestrator.kinds import bind, build_scene

    case = load_case(Path(__file__).parents[1] / "cases" / "ejector_drill_canini.toml", preset="flow_exit_quick").model
    scene = build_scene(case)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "run" / "probe").mkdir(parents=True)

    class Engine:
        threads, executable = 1, "sph"

        @staticmethod
        def environment(wait):
            return {}

    command, _ = bind("ejector_drill", "sph", scene).adapter.probe_command(Engine, scene, Path("run/probe"))
    deck_dir = Path(command[command.index("--deck-dir") + 1])
    assert deck_dir.is_absolute() and deck_dir == tmp_path / "run" / "probe"
    assert (deck_dir / "deck.json").is_file() and (deck_dir / "particles.h5").is_file()
