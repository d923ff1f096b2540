"""A new process kind is one folder and one registry line (docs/architecture.md): a toy kind written into a temporary
folder, registered, loaded from a case file and run on the reference engine like any kind, end to end."""

from __future__ import annotations

import sys
import textwrap

import h5py
import pytest

from orchestrator.case import load_case
from orchestrator.errors import CaseError, OrchestratorError
from orchestrator.kinds import _LOADED, _REGISTRY, engines_for_kind, kind_names, register
from orchestrator.run import run_case

#: The toy: a ball falling from rest for duration s under gravity g; the reference "engine" integrates it with
#: explicit Euler in a child process and the kind measures the fall height against g t^2 / 2.
FILES = {
    "__init__.py": '''
        from orchestrator.kinds.base import Kind

        KIND = Kind(name="toy_fall", case_model="toykind.case:ToyCase", build_scene="toykind.scene:build",
                    measure="toykind.analysis:measure", analyze="toykind.analysis:analyze",
                    adapters={"reference": "toykind.reference:ToyReference"})
    ''',
    "case.py": '''
        from pydantic import Field

        from orchestrator.case.common import CaseMeta, Frozen, Numerics


        class Fall(Frozen):
            gravity: float = Field(9.81, gt=0, description="m/s^2")
            duration: float = Field(gt=0, le=10, description="s")
            steps: int = Field(1000, ge=1, le=10**6)


        class ToyCase(Frozen):
            case: CaseMeta
            fall: Fall
            numerics: Numerics = Numerics()
    ''',
    "scene.py": '''
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
        def measure(case, result):
            return {"fall_height": float(-result.series["height"].values[-1]),
                    "closed_form": 0.5 * case.fall.gravity * case.fall.duration ** 2}


        def analyze(run_dir, run, case, render):
            return {}
    ''',
}


@pytest.fixture
def toy_kind(tmp_path, monkeypatch):
    """The toy kind's folder on sys.path and registered as 'toy_fall'; unregistered afterwards."""
    package = tmp_path / "toykind"
    package.mkdir()
    for name, text in FILES.items():
        (package / name).write_text(textwrap.dedent(text))
    monkeypatch.syspath_prepend(str(tmp_path))
    register("toy_fall", "toykind")
    yield tmp_path
    _REGISTRY.pop("toy_fall", None)
    _LOADED.pop("toy_fall", None)
    for module in [m for m in sys.modules if m == "toykind" or m.startswith("toykind.")]:
        del sys.modules[module]


def test_a_kind_from_a_folder_runs_on_the_reference_engine(toy_kind):
    case_file = toy_kind / "fall.toml"
    case_file.write_text('[case]\nkind = "toy_fall"\nname = "toy"\nengine = "reference"\n[fall]\nduration = 0.5\n')
    assert "toy_fall" in kind_names() and engines_for_kind("toy_fall") == ["reference"]
    summary = run_case(load_case(case_file), out_dir=toy_kind / "run", progress=False)
    assert summary.status == "ok" and summary.n_steps == 1000
    # explicit Euler overshoots g t^2 / 2 by g t dt / 2: 0.5 * 9.81 * 0.5 * 5e-4 = 1.23e-3 m on 1.226 m
    height, exact = summary.measured["fall_height"], summary.measured["closed_form"]
    assert exact == pytest.approx(1.22625)
    assert height - exact == pytest.approx(0.5 * 9.81 * 0.5 * 5e-4, rel=1e-6)
    with h5py.File(toy_kind / "run" / "run.h5") as h5:
        assert h5.attrs["case_kind"] == "toy_fall" and h5.attrs["engine"] == "reference"
        assert len(h5["series"]["height"]) == 1000


def test_the_registry_names_what_a_kind_does_not_run(toy_kind):
    case_file = toy_kind / "fall.toml"
    case_file.write_text('[case]\nkind = "toy_fall"\nname = "toy"\nengine = "yade"\n[fall]\nduration = 0.5\n')
    with pytest.raises(CaseError, match="case.engine = 'yade' does not run toy_fall cases; allowed: reference"):
        load_case(case_file)
    case_file.write_text('[case]\nkind = "toy_fall"\nname = "toy"\nengine = "reference"\n[fall]\nduration = 0.5\n')
    with pytest.raises(OrchestratorError, match="the sph engine does not run toy_fall cases; use --engine reference"):
        run_case(load_case(case_file), engine="sph", out_dir=toy_kind / "run2", progress=False)
