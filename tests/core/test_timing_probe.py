"""The timing probe before a long run (orchestrator.run._run_probe): its estimate is announced and kept as the run's,
a probe that fails is named in a warning (the run goes on), and the ejector drill's probe runs from any working
directory (its deck directory is absolute: the probe process runs inside it)."""

from __future__ import annotations

import sys
from pathlib import Path

from orchestrator.run import _run_probe
from paths import CASES


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

    case = load_case(CASES / "ejector_drill_canini.toml", preset="flow_exit_quick").model
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
    # the scene fills from its prefill: the start state is probed too (probe.START)
    assert (deck_dir / "start" / "deck.json").is_file() and (deck_dir / "start" / "particles.h5").is_file()


def test_a_filled_start_probes_its_end_state_only(tmp_path):
    from orchestrator.case import load_case
    from orchestrator.kinds import build_scene
    from orchestrator.drill.probe import write_probe

    case = load_case(CASES / "ejector_drill_canini.toml",
                     preset="flow_exit_filled_quick").model
    info = write_probe(build_scene(case), tmp_path, 1, 10)
    assert (tmp_path / "deck.json").is_file() and not (tmp_path / "start").exists()
    assert info["planned_steps"] == case.planned_steps


def _fake_sph(tmp_path) -> str:
    """An 'sph executable' that writes out.h5 with 100 steps at the s/step its deck.json names ('cost')."""
    script = tmp_path / "fake_sph"
    script.write_text(f"#!{sys.executable}\nimport json, h5py\ncost = json.load(open('deck.json'))['cost']\n"
                      "with h5py.File('out.h5', 'w') as h5:\n    h5.attrs['wall_time_s'] = 100 * cost\n"
                      "    h5.attrs['n_steps'] = 100\n")
    script.chmod(0o755)
    return str(script)


def test_the_estimate_is_the_planned_steps_at_the_mean_of_the_start_and_end_states(tmp_path):
    """A filling run's step cost grows from its start state's to its end state's (linearly with the inflow): the
    estimate is the planned steps at their mean, the bound the dearer one throughout. Without a start deck the end's
    cost is scaled by the particle counts."""
    from orchestrator.drill.probe import estimate

    import json

    (tmp_path / "start").mkdir()
    (tmp_path / "deck.json").write_text(json.dumps({"cost": 0.2}))
    (tmp_path / "start" / "deck.json").write_text(json.dumps({"cost": 0.05}))
    per_end, per_start, typical, upper = estimate(tmp_path, _fake_sph(tmp_path), 1000, 10, 20)
    assert (per_end, per_start) == (0.2, 0.05)
    assert abs(typical - 125.0) < 1e-9 and abs(upper - 200.0) < 1e-9
    (tmp_path / "start" / "deck.json").unlink()
    per_end, per_start, typical, upper = estimate(tmp_path, _fake_sph(tmp_path), 1000, 10, 20)
    assert per_start is None and abs(typical - 150.0) < 1e-9 and abs(upper - 200.0) < 1e-9


def test_the_probe_command_line_names_bad_input(tmp_path, capsys):
    """No case, an unknown case file or preset, --deck-dir without --planned: one error line and exit code 2."""
    import pytest

    from orchestrator.drill.probe import main

    case = str(CASES / "ejector_drill_canini.toml")
    assert main([str(tmp_path / "nosuch.toml")]) == 2
    assert "case file not found" in capsys.readouterr().err
    assert main([case, "--preset", "nope", "--dir", str(tmp_path / "p")]) == 2
    assert "unknown preset 'nope'" in capsys.readouterr().err
    for argv, words in (([], "name a case file"), (["--deck-dir", str(tmp_path)], "--deck-dir needs --planned")):
        with pytest.raises(SystemExit) as stop:
            main(argv)
        assert stop.value.code == 2 and words in capsys.readouterr().err
