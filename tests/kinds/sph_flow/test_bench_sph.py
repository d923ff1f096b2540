"""`orchestrator bench sph`: a smoke run of a few steps (the benchmark itself is a command, not a test)."""

import json
import math

import numpy as np
import pytest

from orchestrator.workflows.bench_sph import (
    BenchRow,
    _runs,
    format_report,
    mean_neighbours,
    pysph_available,
    run_bench,
    summary,
)
from orchestrator.cli import main
from orchestrator.kinds.sph_flow.bench_scenes import dam_break_2d_case

needs_sph = pytest.mark.sph


def test_neighbours_of_a_square_lattice():
    # inside a large lattice at spacing 1, a disc of radius 2.6 holds 21 points besides the centre
    g = np.arange(-10, 11, dtype=float)
    points = np.array([(x, y) for x in g for y in g])
    kind = np.where(np.abs(points).max(axis=1) == 0, 0, 1)
    assert mean_neighbours(points, kind, 2.6) == 20.0
    # periodic: a 1D row of 10 points at spacing 1 wrapped every 10 sees 2 neighbours within 1.5 everywhere
    row = np.column_stack([np.arange(10.0), np.zeros(10)])
    assert mean_neighbours(row, np.zeros(10, int), 1.5, periodic_box=[10.0, 0.0]) == 2.0


def test_the_2d_scene_is_pysphs_column():
    case = dam_break_2d_case(steps=10, threads=1)
    column = case["blocks"][0]
    assert column["hi"] == pytest.approx([34 * 0.03, 67 * 0.03])  # 2278 particles, as PySPH's get_2d_block
    assert case["numerics"]["h_over_dx"] * case["numerics"]["dx"] == pytest.approx(0.039)


def test_summary_ratios():
    def row(scene, engine, threads, rate, per_core, particles=100, fluid=50, wait="-"):
        return BenchRow(scene, engine, threads, particles, fluid, 10, 20.0, 1.0, 1.0, rate, per_core, wait=wait)

    rows = [row("bench_dam_break_2d", "sph 0.1.0", 1, 4e6, 5e6),
            row("bench_dam_break_2d", "sph 0.1.0", 2, 7e6, 4.5e6, wait="spin"),
            row("bench_dam_break_2d", "sph 0.1.0", 2, 5e6, 3e6, wait="passive"),
            row("pysph_dam_break_2d", "pysph 1.0b2", 1, 1e6, 1.25e6, particles=100, fluid=60)]
    s = summary(rows)
    assert s["speedup_2_threads_bench_dam_break_2d"] == pytest.approx(1.75)
    assert s["speedup_2_threads_passive_bench_dam_break_2d"] == pytest.approx(1.25)
    assert s["ratio_per_core"] == pytest.approx(4.0)
    assert s["ratio_per_core_fluid"] == pytest.approx(4.0 * 0.5 / 0.6)
    assert s["ratio_wall"] == pytest.approx(4.0)
    report = format_report(rows)
    assert "(spin, for an otherwise idle machine) run 1.75 x as fast" in report
    assert "(passive, for shared cores) run 1.25 x as fast" in report


@needs_sph
def test_repeats_keep_the_fastest_run(tmp_path):
    rows = run_bench(tmp_path, steps_2d=5, steps_3d=1, threads=(1,), with_pysph=False, repeats=2, with_lammps=False,
                     steps_shear=1)
    assert [r.repeats for r in rows] == [2] * 5  # two dam breaks, three shear cells
    assert all(r.status == "ok" and r.steps in (5, 1) for r in rows)


def test_each_two_thread_run_once_per_wait():
    assert _runs((1, 2)) == [(1, "-"), (2, "spin"), (2, "passive")]


@needs_sph
def test_smoke_run_of_ten_steps(tmp_path):
    rows = run_bench(tmp_path, steps_2d=10, steps_3d=2, threads=(1,), with_pysph=False, with_lammps=False,
                     steps_shear=2)
    assert [r.scene for r in rows] == ["bench_dam_break_2d", "bench_dam_break_3d", "bench_shear_cell_newtonian",
                                       "bench_shear_cell_ptt_1_mode", "bench_shear_cell_ptt_5_modes"]
    two, three = rows[:2]
    assert two.status == "ok" and two.steps == 10 and two.fluid == 2278
    assert three.status == "ok" and three.steps == 2 and three.fluid == 16000
    assert 15 < two.neighbours < 25  # 2h = 2.6 dx in 2D: about pi 2.6^2 - 1 inside the column
    assert 60 < three.neighbours < 95  # 4/3 pi 2.6^3 - 1 = 73 inside, fewer near the walls
    for r in rows:
        assert r.particle_steps_per_s == pytest.approx(r.particles * r.steps / r.wall_s)
        assert r.particle_steps_per_s > 1e4 and math.isfinite(r.per_core)


@needs_sph
@pytest.mark.skipif(not pysph_available(), reason="PySPH is not installed (make pysph)")
def test_cli_json_with_pysph(tmp_path, capsys):
    code = main(["bench", "sph", "--steps-2d", "10", "--steps-3d", "1", "--out", str(tmp_path), "--json"])
    # (LAMMPS, when installed, runs here too: 3 block steps and 1 dam-break step; tests/workflows/test_bench_lammps.py)
    report = json.loads(capsys.readouterr().out)
    assert code == 0
    pysph = [r for r in report["rows"] if r["engine"].startswith("pysph")]
    assert len(pysph) == 1 and pysph[0]["steps"] == 10 and pysph[0]["fluid"] == 2278
    assert report["summary"]["ratio_per_core"] > 0


def test_cli_refuses_zero_steps(capsys):
    assert main(["bench", "sph", "--steps-2d", "0"]) == 2  # a usage error, as for every OrchestratorError
    assert "--steps-2d" in capsys.readouterr().err
