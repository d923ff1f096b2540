"""`orchestrator compare` and the orchestrator's overhead per phase.

Engine-free: engine-list parsing, the spread and reference-band arithmetic on
made-up summaries, the overlay plot, overhead attributes of a reference-DEM run,
a missing Yade skipped with its install hint. With Yade (marked, skipped when
missing): Chung & Ooi test 2 on Yade and the reference agree within the
verification tolerance; the tiny drag-finishing bowl through compare, with
its overhead below the engine's wall time.
"""

import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

from orchestrator.case import load_case
from orchestrator.workflows.compare import Comparison, EngineRun, parse_engines, text_tables
from orchestrator.errors import OrchestratorError
from orchestrator.run import OVERHEAD_PHASES, PhaseClock, RunSummary, run_case
from paths import VERIFICATION, TINY_BOWL

IMPACT = VERIFICATION / "chung_ooi_test2_sphere_plane.toml"  # the cheapest scene: 1 sphere
PHASE_KEYS = [f"overhead_{name}_s" for name in OVERHEAD_PHASES]
yade_installed = pytest.mark.yade


def cli(*args, env=None):
    return subprocess.run([sys.executable, "-m", "orchestrator", *args], capture_output=True, text=True, timeout=300,
                          env={**os.environ, "OMP_WAIT_POLICY": "PASSIVE", **(env or {})})


def strict_json(text):
    """json.loads that refuses NaN / Infinity (not JSON; the CLI must print null)."""
    def refuse(name):
        raise ValueError(f"{name} in the JSON output")

    return json.loads(text, parse_constant=refuse)


def summary(engine, measured, wall=2.0, particles=10, steps=500, overhead=0.05):
    return RunSummary("ok", engine, "1.0", "case", wall, particles, steps, f"/nowhere/{engine}", measured=measured,
                      overhead_s=overhead, overhead_phases_s={name: overhead / len(OVERHEAD_PHASES)
                                                              for name in OVERHEAD_PHASES})


# ---------------------------------------------------------------- no engine


def test_engine_list_is_parsed_and_checked():
    assert parse_engines(" yade, reference ,yade") == ["yade", "reference"]
    with pytest.raises(OrchestratorError, match=r"unknown engine 'nosuch'; allowed: .*reference"):
        parse_engines("yade,nosuch")
    with pytest.raises(OrchestratorError, match="separated by commas"):
        parse_engines(" , ")


def test_unknown_engine_is_a_clear_error_before_anything_runs(tmp_path):
    proc = cli("compare", str(IMPACT), "--engines", "reference,nosuch", "--out", str(tmp_path / "c"))
    assert proc.returncode == 2
    assert proc.stderr.startswith("error: --engines: unknown engine 'nosuch'") and "Traceback" not in proc.stderr
    assert not (tmp_path / "c").exists()


def test_spread_speed_and_overhead_rows():
    case = load_case(IMPACT).model
    comparison = Comparison(case, None, Path("/nowhere"), [
        EngineRun("a", "ok", "", summary("a", {"max_normal_force": 100.0, "restitution": 0.9}, wall=4.0)),
        EngineRun("b", "ok", "", summary("b", {"max_normal_force": 104.0}, wall=0.5, steps=2000)),
        EngineRun("c", "skipped", "c is not installed"),
    ])
    rows = {row["quantity"]: row for row in comparison.quantity_rows()}
    force = rows["max_normal_force"]
    assert force["values"] == {"a": 100.0, "b": 104.0, "c": pytest.approx(math.nan, nan_ok=True)}
    assert force["spread"] == pytest.approx(4.0) and force["rel_spread"] == pytest.approx(4.0 / 102.0)
    assert force["unit"] == "N" and force["expected"] == pytest.approx(11369.9, rel=1e-4)  # Hertz closed form
    assert math.isnan(rows["restitution"]["spread"])  # one engine only: no spread
    engines = {row["engine"]: row for row in (run.row() for run in comparison.runs)}
    assert engines["a"]["particle_steps_per_s"] == pytest.approx(10 * 500 / 4.0)
    assert engines["b"]["particle_steps_per_s"] == pytest.approx(10 * 2000 / 0.5)
    assert engines["b"]["overhead_pct"] == pytest.approx(100 * 0.05 / 0.5)
    assert sum(engines["a"][key] for key in PHASE_KEYS) == pytest.approx(engines["a"]["overhead_s"])
    assert engines["c"]["status"] == "skipped" and math.isnan(engines["c"]["wall_time_s"])
    titles = [title for title, _, _ in text_tables(comparison)]
    assert titles[0].startswith("measured quantities") and titles[-1].startswith("orchestrator overhead by phase")
    header = text_tables(comparison)[0][1]
    assert header[1:3] == ["a", "b"] and "c" not in header  # a skipped engine has no column


def test_drag_finishing_forces_are_placed_against_the_reference_bands(tiny_bowl):
    case = tiny_bowl  # reference: -1.99 +- 0.63 N
    comparison = Comparison(case, None, Path("/nowhere"), [
        EngineRun("a", "ok", "", summary("a", {"fn_mean": -1.81, "fn_std": 0.25, "ft_mean": -0.3, "ft_std": 0.5})),
        EngineRun("b", "ok", "", summary("b", {"fn_mean": -2.9, "fn_std": 0.4, "fn_sem": 0.05})),
    ])
    rows = {row["source"]: row for row in comparison.reference_rows()}
    assert list(rows) == ["a", "b", "Uhlmann 2015, simulated"]
    a, b = rows["a"]["against"][0], rows["b"]["against"][0]
    assert a["fn_rel_difference"] == pytest.approx((-1.81 + 1.99) / 1.99) and a["in_band"]
    assert b["fn_rel_difference"] == pytest.approx((-2.9 + 1.99) / 1.99) and not b["in_band"]
    assert rows["b"]["fn_sem"] == 0.05 and math.isnan(rows["a"]["fn_sem"])
    assert rows["Uhlmann 2015, simulated"]["fn_mean"] == -1.99
    table = dict((title.split(" ")[0], cells) for title, _, cells in text_tables(comparison))["force"]
    assert table[0][-1] == "+9 % (in band)" and table[1][-1] == "-46 % (outside band)"
    assert comparison.unit_of("contact_fn_max") == "N" and comparison.unit_of("bed_height") == "m"
    impact = Comparison(load_case(IMPACT).model, None, Path("/nowhere"))
    assert impact.unit_of("max_overlap") == "m" and impact.reference_rows() == []


def test_overlay_plot_of_two_engines(tmp_path):
    from matplotlib.image import imread

    from conftest import build_synthetic_run
    from orchestrator.kinds.drag_finishing.plots import plot_engine_forces
    from orchestrator.runh5 import stored_case
    from orchestrator.runh5 import read_run

    first = read_run(build_synthetic_run(tmp_path / "a", seed=3))
    second = read_run(build_synthetic_run(tmp_path / "b", seed=4))
    empty = {"attrs": {}, "series": {}}
    path = plot_engine_forces([("a 1.0", first), ("b 2.0", second), ("c (failed)", empty)], stored_case(first, "run.h5"),
                              tmp_path / "cmp.png")
    rgb = imread(path)[..., :3]
    assert rgb.shape[0] > 600 and rgb.std() > 0.05
    orange = (rgb[..., 0] > 0.9) & (np.abs(rgb[..., 1] - 0.5) < 0.08) & (rgb[..., 2] < 0.2)  # C1: the 2nd engine
    assert orange.sum() > 300


def test_phase_clock_leaves_skipped_time_out():
    clock = PhaseClock()
    time.sleep(0.02)
    clock.lap("scene")
    time.sleep(0.05)
    clock.skip()  # the engine
    time.sleep(0.01)
    clock.lap("write")
    attrs = clock.attrs()
    assert 0.02 <= attrs["overhead_scene_s"] < 0.045 and 0.01 <= attrs["overhead_write_s"] < 0.035
    assert attrs["overhead_input_s"] == 0.0
    assert attrs["orchestrator_overhead_s"] == pytest.approx(sum(attrs[key] for key in PHASE_KEYS), abs=1e-12)


def test_overhead_attributes_of_a_reference_run(tmp_path):
    result = run_case(load_case(IMPACT), engine="reference", out_dir=tmp_path / "r", progress=False)
    with h5py.File(tmp_path / "r" / "run.h5") as h5:
        attrs = dict(h5.attrs)
    phases = [float(attrs[key]) for key in PHASE_KEYS]
    assert all(p > 0 for p in phases)  # every phase does work in a run: imports, scene, input, parse, analysis, write
    assert float(attrs["orchestrator_overhead_s"]) == pytest.approx(sum(phases), abs=1e-9)
    assert result.overhead_s == pytest.approx(float(attrs["orchestrator_overhead_s"]), abs=1e-6)
    assert result.overhead_phases_s["write"] == pytest.approx(float(attrs["overhead_write_s"]), abs=1e-6)


def test_missing_engine_is_skipped_with_its_install_hint(tmp_path):
    out = tmp_path / "c"
    proc = cli("compare", str(IMPACT), "--engines", "yade,reference", "--out", str(out), "--no-progress",
               env={"ORCHESTRATOR_YADE": "/nonexistent/yade"})
    assert proc.returncode == 1, proc.stderr  # the comparison is incomplete
    assert "Traceback" not in proc.stderr
    assert "note: yade: skipped: Yade is not installed" in proc.stdout and "apt-get install yade" in proc.stdout
    lines = proc.stdout.splitlines()
    reference = next(line.split() for line in lines if line.startswith("reference "))
    assert reference[2] == "ok" and float(reference[3]) > 0  # status, engine wall time
    assert any(line.startswith("max_normal_force [N]") for line in lines)
    assert (out / "reference" / "run.h5").is_file() and not (out / "yade").exists()
    assert (out / "compare_forces.png").is_file()


# ---------------------------------------------------------------- Yade


@pytest.fixture(scope="module")
def impact_comparison(tmp_path_factory):
    out = tmp_path_factory.mktemp("compare") / "impact"
    proc = cli("compare", str(IMPACT), "--engines", "yade,reference", "--out", str(out), "--json", "--no-progress")
    assert proc.returncode == 0, proc.stderr
    return strict_json(proc.stdout), out


@pytest.mark.yade
@yade_installed
def test_yade_and_reference_agree_within_the_verification_tolerance(impact_comparison):
    doc, out = impact_comparison
    case = load_case(IMPACT).model
    rows = {row["quantity"]: row for row in doc["quantities"]}
    assert {check.quantity for check in case.expected} <= set(rows)
    for check in case.expected:
        row = rows[check.quantity]
        assert set(row["values"]) == {"yade", "reference"}
        assert row["rel_spread"] <= check.tolerance, (check.quantity, row)
        assert row["spread"] == pytest.approx(abs(row["values"]["yade"] - row["values"]["reference"]))
        for value in row["values"].values():  # and each engine is on the closed form
            assert value == pytest.approx(row["expected"], rel=check.tolerance)
    assert doc["case"] == case.case.name and doc["kind"] == "impact" and doc["references"] == []
    assert doc["plot"] == str(out / "compare_forces.png") and Path(doc["plot"]).is_file()


@pytest.mark.yade
@yade_installed
def test_engine_rows_carry_speed_and_overhead(impact_comparison):
    doc, out = impact_comparison
    engines = {row["engine"]: row for row in doc["engines"]}
    assert list(engines) == ["yade", "reference"]
    for name, row in engines.items():
        with h5py.File(out / name / "run.h5") as h5:
            attrs = dict(h5.attrs)
        assert row["status"] == "ok" and row["n_particles"] == 1 and row["n_steps"] == attrs["n_steps"] > 100
        assert row["wall_time_s"] == pytest.approx(attrs["wall_time_s"], abs=1e-3)
        assert row["particle_steps_per_s"] == pytest.approx(row["n_steps"] / row["wall_time_s"], rel=1e-9)
        assert row["overhead_s"] == pytest.approx(attrs["orchestrator_overhead_s"], abs=1e-5)
        assert row["overhead_pct"] == pytest.approx(100 * row["overhead_s"] / row["wall_time_s"], rel=1e-9)
        assert sum(row[key] for key in PHASE_KEYS) == pytest.approx(row["overhead_s"], abs=1e-5)


@pytest.mark.yade
@yade_installed
def test_tiny_bowl_compare_and_its_overhead(tmp_path):
    """The drag-finishing path on the tiny bowl (Yade; the reference is skipped: it runs impacts only)."""
    out = tmp_path / "tiny"
    proc = cli("compare", str(TINY_BOWL), "--engines", "yade,reference", "--set", "process.duration=0.05", "--out",
               str(out), "--json", "--no-progress")
    assert proc.returncode == 1, proc.stderr  # the reference was skipped
    doc = strict_json(proc.stdout)
    yade, reference = doc["engines"]
    assert reference["status"] == "skipped" and "does not run drag_finishing" in reference["message"]
    assert yade["status"] == "ok"
    with h5py.File(out / "yade" / "run.h5") as h5:
        attrs = dict(h5.attrs)
        measured = dict(h5["measured"].attrs)
    total = float(attrs["orchestrator_overhead_s"])
    assert total == pytest.approx(sum(float(attrs[key]) for key in PHASE_KEYS), abs=1e-9)
    assert 0 < total < float(attrs["wall_time_s"])
    forces = {row["source"]: row for row in doc["references"]}
    assert forces["yade"]["fn_mean"] == pytest.approx(measured["fn_mean"], rel=1e-12)
    assert forces["Uhlmann 2015, simulated"]["fn_mean"] == -1.99
    assert Path(doc["plot"]).is_file() and Path(doc["plot"]).stat().st_size > 20_000
