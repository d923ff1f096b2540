"""The reference DEM as an engine: `orchestrator run CASE --engine reference`,
the same run.h5 names as Yade, and clear refusals of cases too big for it."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import tomllib

import pytest
import tomli_w

from orchestrator.kinds.impact.yade import read_impact_output
from orchestrator.case import load_case
from orchestrator.runh5 import read_run
from orchestrator.kinds import build_scene
from paths import CASES, VERIFICATION, DATA

TEST1 = VERIFICATION / "chung_ooi_test1_sphere_sphere.toml"
TEST2 = VERIFICATION / "chung_ooi_test2_sphere_plane.toml"
STORED_YADE = DATA / "yade_impact_output"


def cli(*args):
    return subprocess.run([sys.executable, "-m", "orchestrator", *map(str, args)], capture_output=True, text=True,
                          timeout=300)


@pytest.fixture(scope="module")
def test1_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("ref") / "test1"
    proc = cli("run", TEST1, "--engine", "reference", "--out", out, "--json", "--no-progress")
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout), read_run(out), out


def test_reference_runs_an_impact_case_from_the_command_line(test1_run):
    summary, run, _ = test1_run
    assert summary["status"] == "ok" and summary["engine"] == "reference" and summary["n_particles"] == 2
    assert run["attrs"]["engine_version"].startswith("orchestrator-")
    assert summary["measured"]["max_normal_force"] == pytest.approx(10696.9, rel=1e-3)
    assert run["measured"]["attrs"]["n_contacts"] == 1


def test_reference_fills_the_same_run_h5_names_as_yade(test1_run, tmp_path):
    _, run, _ = test1_run
    shutil.copytree(STORED_YADE, tmp_path / "output")
    yade = read_impact_output(build_scene(load_case(TEST2).model), tmp_path)
    assert set(run["series"]) - {"attrs"} == set(yade.series) | {"time"}
    assert set(run["events"]) - {"attrs"} == set(yade.events)
    for name, item in yade.series.items():
        assert run["series"][name].shape[1:] in ((), (3,), (2, 3)) and item.units


def test_sphere_sphere_force_series_is_the_law_at_the_recorded_states(test1_run):
    _, run, _ = test1_run
    peak = run["events"]["peak_normal_force"][0]
    # the recorded series (every 0.5 us) comes within 0.1 % of the per-step peak
    assert run["series"]["normal_force"].max() == pytest.approx(peak, rel=1e-3)
    assert run["series"]["normal_force"].max() <= peak * (1 + 1e-6)


def test_the_drag_finishing_case_is_refused_with_the_engine_to_use(tmp_path):
    proc = cli("run", CASES / "drag_finishing_uhlmann2015.toml", "--engine", "reference", "--out",
               tmp_path / "r")
    assert proc.returncode == 2 and proc.stderr.startswith("error:") and "Traceback" not in proc.stderr
    for words in ("cannot run drag_finishing_uhlmann2015", "too big", "1422 balls", "--engine yade"):
        assert words in proc.stderr
    assert not (tmp_path / "r").exists()


def test_too_many_spheres_are_refused(tmp_path):
    data = tomllib.loads(TEST1.read_text())
    data["spheres"] = [{"material": "glass", "radius": 0.001, "position": [0.003 * (k % 50), 0.003 * (k // 50), 0]}
                       for k in range(2001)]
    data["expected"] = []
    path = tmp_path / "big.toml"
    path.write_text(tomli_w.dumps(data))
    proc = cli("run", path, "--engine", "reference", "--out", tmp_path / "r")
    assert proc.returncode == 2 and "2001 spheres" in proc.stderr and "at most 2000" in proc.stderr
    assert "--engine yade" in proc.stderr and "Traceback" not in proc.stderr


def test_too_long_runs_are_refused_with_an_estimate(tmp_path):
    data = tomllib.loads(TEST1.read_text())
    data["spheres"] = [{"material": "glass", "radius": 0.001, "position": [0.003 * k, 0, 0]} for k in range(20)]
    data["simulation"]["duration"] = 5.0
    data["output"]["record_interval"] = 0.01
    data["expected"] = []
    path = tmp_path / "long.toml"
    path.write_text(tomli_w.dumps(data))
    proc = cli("run", path, "--engine", "reference", "--out", tmp_path / "r")
    assert proc.returncode == 2 and "would take the reference DEM about" in proc.stderr
    assert "numerics.timestep_factor" in proc.stderr and "--engine yade" in proc.stderr


def test_analyze_prints_the_checks_of_an_impact_run(test1_run):
    _, _, out = test1_run
    proc = cli("analyze", out)
    assert proc.returncode == 0, proc.stderr
    assert "check max_normal_force" in proc.stdout and "(hertz_max_force)" in proc.stdout
    assert proc.stdout.count(" pass") == 4 and (out / "forces.png").is_file()
