"""A new process kind is one folder and one registry line (docs/architecture.md): a toy kind written into a temporary
folder and registered with the line a kind adds to orchestrator/kinds/__init__.py, then loaded from a case file, run
on the reference engine, verified by a suite of its own, compared with its units and picture, and asked for the
command it contributes, through the same code paths as every kind.

The toy: a ball falling from rest for duration s under gravity g; the reference engine runs it as a child Python
that integrates it with explicit Euler, and the kind measures the fall height and speed against g t^2 / 2 and g t.
"""

from __future__ import annotations

import math
import re
import sys
import textwrap
from pathlib import Path

import h5py
import pytest

import orchestrator.kinds as registry
from orchestrator.case import load_case
from orchestrator.cli import main
from orchestrator.errors import CaseError, OrchestratorError
from orchestrator.kinds import _LOADED, _REGISTRY, engines_for_kind, kind_names
from orchestrator.run import run_case
from paths import REPO, CASES

#: The one line a kind adds to orchestrator/kinds/__init__.py (here with the toy's package name).
REGISTRY_LINE = 'register("toy_fall", "toykind")'

#: What any kind needs to run and be analysed: its declaration, case model, scene builder, measure and analyze, and
#: one adapter per engine (a real engine's adapter also renders a template, templates/<engine>.*.j2).
MINIMAL = {
    "__init__.py": '''
        """A ball falling from rest under gravity (a toy kind: every capability a kind can declare)."""

        from orchestrator.kinds.base import Kind, Verification

        KIND = Kind(
            name="toy_fall",
            description="a ball falling from rest; height and speed against g t^2 / 2 and g t",
            case_model="toykind.case:ToyCase",
            build_scene="toykind.scene:build",
            measure="toykind.analysis:measure",
            analyze="toykind.analysis:analyze",
            adapters={"reference": "toykind.reference:ToyReference"},
            quantities="toykind.analysis:QUANTITIES",
            expected="toykind.analysis:expected",
            compare_picture="toykind.pictures:plot_heights",
            verification=Verification(
                suite="toy", check="toykind.verification:check_run", units="toykind.analysis:QUANTITIES",
                picture="toykind.pictures:plot_suite", cases="toykind:scenes",
                description="the falling ball against g t^2 / 2 and g t"),
            commands={"fall-time": "toykind.commands.fall_time:COMMAND"},
        )
    ''',
    "case.py": '''
        """The toy's case files: [fall] and the [[expected]] checks."""

        from typing import Literal

        from pydantic import Field

        from orchestrator.case.common import CaseMeta, Frozen, Numerics


        class Fall(Frozen):
            gravity: float = Field(9.81, gt=0, description="m/s^2")
            duration: float = Field(gt=0, le=10, description="s")
            steps: int = Field(1000, ge=1, le=10**6)


        class Check(Frozen):
            quantity: Literal["fall_height", "fall_speed"]
            tolerance: float = Field(gt=0, lt=1, description="relative error accepted, -")


        class ToyCase(Frozen):
            case: CaseMeta
            fall: Fall
            numerics: Numerics = Numerics()
            expected: tuple[Check, ...] = ()
    ''',
    "scene.py": '''
        """The toy's scene: the case and its time step."""

        from dataclasses import dataclass


        @dataclass(frozen=True)
        class ToyScene:
            case: object
            timestep: float
            n_particles: int = 1


        def build(case):
            return ToyScene(case, case.fall.duration / case.fall.steps)
    ''',
    "reference.py": '''
        """The toy on the reference engine: explicit Euler in a child Python."""

        import json

        import numpy as np

        from orchestrator.engines.base import Result, Series
        from orchestrator.kinds.base import Adapter

        CHILD = (
            "import json, numpy as np\\n"
            "spec = json.load(open('fall.json'))\\n"
            "dt, z, v, rows = spec['dt'], 0.0, 0.0, []\\n"
            "for k in range(spec['steps']):\\n"
            "    v -= spec['g'] * dt; z += v * dt; rows.append((dt * (k + 1), z))\\n"
            "np.savetxt('fall.txt', rows)\\n"
            "print(f\\"PROGRESS step={spec['steps']} of {spec['steps']} phase=fall\\", flush=True)\\n"
        )


        class ToyReference(Adapter):
            engine = "reference"

            def write_input(self, profile, scene, workdir):
                fall = scene.case.fall
                (workdir / "fall.json").write_text(json.dumps({"dt": scene.timestep, "steps": fall.steps,
                                                              "g": fall.gravity}))

            def command(self, profile, scene, workdir):
                return [profile.python, "-c", CHILD], {}

            def planned_steps(self, profile, scene):
                return 10**9  # a long run, but this adapter has no timing probe: the run starts without one

            def read_output(self, profile, scene, workdir):
                rows = np.loadtxt(workdir / "fall.txt", ndmin=2)
                result = Result(attrs={"n_steps": len(rows)}, time=rows[:, 0])
                result.series["height"] = Series(rows[:, 1], "m", "height below the start")
                return result
    ''',
    "analysis.py": '''
        """What the toy measures (m, m/s), what its case predicts, and `orchestrator analyze` of a run."""

        QUANTITIES = {"fall_height": ("m", "distance fallen at the end of the run"),
                      "fall_speed": ("m/s", "speed at the end of the run")}


        def measure(case, result):
            time, height = result.time, result.series["height"].values
            return {"fall_height": float(-height[-1]),
                    "fall_speed": float((height[-2] - height[-1]) / (time[-1] - time[-2]))}


        def expected(case):
            g, t = case.fall.gravity, case.fall.duration
            return {"fall_height": 0.5 * g * t**2, "fall_speed": g * t}


        def analyze(run_dir, run, case, render):
            for name, value in run.get("measured", {}).get("attrs", {}).items():
                print(f"{name} {value:.6g} {QUANTITIES[name][0]}")
            return {}
    ''',
}
#: The capabilities: a verification suite (its check, its picture, its scenes), the compare picture and a command.
CAPABILITIES = {
    "verification.py": '''
        """The toy's part of `verify toy`: one row per [[expected]] check."""

        from toykind.analysis import expected


        def check_run(case, engine, run):
            measured = run.get("measured", {}).get("attrs", {})
            exact = expected(case)
            rows = []
            for check in case.expected:
                value = float(measured[check.quantity]) if check.quantity in measured else None
                want = exact[check.quantity]
                error = abs(value - want) / abs(want) if value is not None else None
                rows.append({"scene": case.case.name, "engine": engine, "quantity": check.quantity, "value": value,
                             "expected": want, "rel_error": error, "tolerance": check.tolerance,
                             "passed": error is not None and error <= check.tolerance, "source": "closed form",
                             "note": ""})
            series = run.get("series", {})
            return rows, {"time": series.get("time"), "height": series.get("height")}
    ''',
    "pictures.py": '''
        """The toy's pictures: the height against time of every engine (compare) and of every scene (verify)."""

        from orchestrator.plots import save_pyplot_figure


        def _heights(curves, path):
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt

            fig, ax = plt.subplots(figsize=(5, 3.5))
            for label, time, height in curves:
                if time is not None and height is not None:
                    ax.plot(time, height, label=label)
            ax.set_xlabel("time [s]")
            ax.set_ylabel("height [m]")
            ax.legend()
            return save_pyplot_figure(fig, path)


        def plot_heights(runs, case, path):
            return _heights([(label, run["series"].get("time"), run["series"].get("height")) for label, run in runs],
                            path)


        def plot_suite(runs, path):
            return _heights([(f"{r.scene} {r.engine}", r.picture.get("time"), r.picture.get("height")) for r in runs],
                            path)
    ''',
    "commands/__init__.py": '''
        """The commands the toy contributes."""
    ''',
    "commands/fall_time.py": '''
        """`orchestrator fall-time --height H`: the time to fall H from rest, s."""

        import math

        from orchestrator.errors import OrchestratorError
        from orchestrator.kinds.base import Command


        def add_arguments(parser):
            parser.add_argument("--height", type=float, required=True, help="height fallen, m")
            parser.add_argument("--gravity", type=float, default=9.81, help="m/s^2 (default 9.81)")


        def run(args):
            if not (args.height > 0 and args.gravity > 0):
                raise OrchestratorError("--height and --gravity: allowed: positive numbers")
            print(f"fall time {math.sqrt(2.0 * args.height / args.gravity):.9g} s")
            return 0


        COMMAND = Command(help="time to fall a height from rest, s",
                          description="fall-time: the time in s to fall --height m from rest, sqrt(2 H / g)",
                          add_arguments=add_arguments, run=run)
    ''',
    "scenes/fall_half_second.toml": '''
        [case]
        kind = "toy_fall"
        name = "fall_half_second"
        engine = "reference"

        [fall]
        duration = 0.5

        [[expected]]
        quantity = "fall_height"
        tolerance = 0.01

        [[expected]]
        quantity = "fall_speed"
        tolerance = 1e-9
    ''',
}
FILES = {**MINIMAL, **CAPABILITIES}
CASE = '[case]\nkind = "toy_fall"\nname = "toy"\nengine = "reference"\n[fall]\nduration = 0.5\n'


@pytest.fixture
def toy_kind(tmp_path, monkeypatch):
    """The toy's folder (FILES) on sys.path and REGISTRY_LINE run as orchestrator/kinds/__init__.py runs its lines;
    unregistered afterwards."""
    for name, text in FILES.items():
        path = tmp_path / "toykind" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(textwrap.dedent(text).lstrip())
    monkeypatch.syspath_prepend(str(tmp_path))
    exec(REGISTRY_LINE, vars(registry))
    yield tmp_path
    _REGISTRY.pop("toy_fall", None)
    _LOADED.pop("toy_fall", None)
    for module in [m for m in sys.modules if m == "toykind" or m.startswith("toykind.")]:
        del sys.modules[module]


def test_the_toy_is_its_folder_and_one_registry_line():
    """The edit set: files inside the kind's folder only, and one line in the registry; nothing of the package,
    its packaging or its cases names the toy (the generic code needed no edit for it)."""
    assert all(not Path(name).is_absolute() and ".." not in Path(name).parts for name in FILES)
    assert "\n" not in REGISTRY_LINE and REGISTRY_LINE.startswith("register(")
    before = dict(_REGISTRY)
    exec(REGISTRY_LINE, vars(registry))
    try:
        assert {k: v for k, v in _REGISTRY.items() if before.get(k) != v} == {"toy_fall": "toykind"}
    finally:
        _REGISTRY.pop("toy_fall", None)
    shared = [*(REPO / "orchestrator").rglob("*.py"), *(CASES).rglob("*.toml"), REPO / "pyproject.toml"]
    assert not [p for p in shared if p.is_file() and re.search(r"toy_fall|toykind", p.read_text())]


def test_a_kind_from_a_folder_runs_on_the_reference_engine(toy_kind):
    case_file = toy_kind / "fall.toml"
    case_file.write_text(CASE)
    assert "toy_fall" in kind_names() and engines_for_kind("toy_fall") == ["reference"]
    summary = run_case(load_case(case_file), out_dir=toy_kind / "run", progress=False)
    assert summary.status == "ok" and summary.n_steps == 1000
    # explicit Euler overshoots g t^2 / 2 by g t dt / 2: 0.5 * 9.81 * 0.5 * 5e-4 = 1.23e-3 m on 1.226 m
    height, exact = summary.measured["fall_height"], 0.5 * 9.81 * 0.5**2
    assert height - exact == pytest.approx(0.5 * 9.81 * 0.5 * 5e-4, rel=1e-6)
    assert summary.measured["fall_speed"] == pytest.approx(9.81 * 0.5, rel=1e-9)  # Euler's speed is exact
    with h5py.File(toy_kind / "run" / "run.h5") as h5:
        assert h5.attrs["case_kind"] == "toy_fall" and h5.attrs["engine"] == "reference"
        assert len(h5["series"]["height"]) == 1000


def test_the_registry_names_what_a_kind_does_not_run(toy_kind):
    case_file = toy_kind / "fall.toml"
    case_file.write_text(CASE.replace('engine = "reference"', 'engine = "yade"'))
    with pytest.raises(CaseError, match="case.engine = 'yade' does not run toy_fall cases; allowed: reference"):
        load_case(case_file)
    case_file.write_text(CASE)
    with pytest.raises(OrchestratorError, match="the sph engine does not run toy_fall cases; use --engine reference"):
        run_case(load_case(case_file), engine="sph", out_dir=toy_kind / "run2", progress=False)


def test_the_command_line_lists_and_runs_the_kinds_command(toy_kind, capsys):
    with pytest.raises(SystemExit) as stop:
        main(["--help"])
    assert stop.value.code == 0
    assert re.search(r"^\s+fall-time\s+time to fall a height from rest, s$", capsys.readouterr().out, re.M)
    assert main(["fall-time", "--height", "1.0"]) == 0
    said = re.fullmatch(r"fall time (\S+) s\n", capsys.readouterr().out)
    assert float(said.group(1)) == pytest.approx(math.sqrt(2.0 / 9.81), rel=1e-8)
    assert main(["fall-time", "--height", "-1"]) == 2
    assert capsys.readouterr().err.startswith("error: --height")


def test_verify_runs_the_kinds_suite(toy_kind, capsys):
    import json

    out = toy_kind / "verify"
    assert main(["verify", "toy", "--out", str(out), "--workers", "1", "--json"]) == 0
    rows = {row["quantity"]: row for row in json.loads(capsys.readouterr().out)}
    assert set(rows) == {"fall_height", "fall_speed"}
    height, speed = rows["fall_height"], rows["fall_speed"]
    assert height["scene"] == "fall_half_second" and height["engine"] == "reference" and height["passed"]
    assert height["expected"] == pytest.approx(1.22625, rel=1e-12)
    assert height["rel_error"] == pytest.approx(0.5 * 9.81 * 0.5 * 5e-4 / 1.22625, rel=1e-5)  # 1.0e-3
    assert speed["value"] == pytest.approx(4.905, rel=1e-9) and speed["passed"]
    assert (out / "verify_toy.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_compare_shows_the_kinds_units_and_draws_its_picture(toy_kind, capsys):
    case_file = toy_kind / "fall.toml"
    case_file.write_text(CASE)
    out = toy_kind / "compare"
    assert main(["compare", str(case_file), "--engines", "reference", "--out", str(out), "--no-progress"]) == 0
    text = capsys.readouterr().out
    rows = {line.split()[0]: line.split() for line in text.splitlines() if line.startswith("fall_")}
    assert rows["fall_height"][1] == "[m]" and rows["fall_speed"][1] == "[m/s]"
    assert float(rows["fall_height"][2]) == pytest.approx(1.22748, rel=1e-5)  # the reference engine's value
    assert float(rows["fall_height"][-1]) == pytest.approx(1.22625, rel=1e-6)  # the kind's expected column
    assert f"picture      {out / 'compare_forces.png'}" in text
    assert (out / "compare_forces.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_docs_count_the_files_of_a_new_kind():
    """docs/architecture.md states the toy's counts: the files a kind needs and those its capabilities add."""
    text = (REPO / "docs" / "architecture.md").read_text()
    found = re.search(r"A new kind is (\d+) files and 1 line .*? its capabilities add (\d+) more", text, re.S)
    assert found, "docs/architecture.md: the sentence 'A new kind is N files and 1 line ... its capabilities add M more'"
    assert (int(found.group(1)), int(found.group(2))) == (len(MINIMAL), len(CAPABILITIES))


@pytest.mark.parametrize("name", kind_names())
def test_every_kind_measures_and_analyzes_in_its_analysis_module(name):
    """As the toy: Kind.measure and Kind.analyze are functions of the kind's module named analysis."""
    kind = registry.get_kind(name)
    assert kind.measure.spec.split(":")[0].endswith(".analysis"), kind.measure.spec
    assert kind.analyze.spec.split(":")[0].endswith(".analysis"), kind.analyze.spec
