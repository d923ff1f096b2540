"""Studies: cached runs, reruns of changed points only, resume after a kill, bad study files."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from orchestrator.engines import engine_names

from orchestrator.study import Study, grid, zipped
from paths import VERIFICATION, TINY_BOWL

needs_yade = pytest.mark.yade


def study_file(tmp_path, seeds=(7, 8), name="s.toml", extra=""):
    path = tmp_path / name
    path.write_text(f"""
[study]
name = "t"
case = "{TINY_BOWL}"
engines = ["yade"]
{extra}
[sweep]
mode = "grid"
[sweep.parameters]
"numerics.stiffness_scale" = [0.001, 0.002]
"case.seed" = {list(seeds)}
"process.duration" = [0.06]
""")
    return path


def mtimes(rows):
    return {row["run_id"]: os.path.getmtime(Path(row["run_dir"]) / "run.h5") for row in rows}


@needs_yade
@pytest.mark.yade
def test_rerun_only_what_changed(tmp_path):
    out = tmp_path / "study"
    first = Study.from_file(study_file(tmp_path), out_dir=out).run(progress=False)
    assert [r["status"] for r in first] == ["ok"] * 4 and not any(r["reused"] for r in first)
    assert len({r["run_id"] for r in first}) == 4
    second = Study.from_file(study_file(tmp_path), out_dir=out).run(progress=False)
    assert all(r["reused"] for r in second) and mtimes(second) == mtimes(first)
    # seed 8 -> 9: the two runs with seed 7 are reused, the two with seed 9 are new
    third = Study.from_file(study_file(tmp_path, seeds=(7, 9)), out_dir=out).run(progress=False)
    assert [r["reused"] for r in third if r["param:case.seed"] == 7] == [True, True]
    assert [r["reused"] for r in third if r["param:case.seed"] == 9] == [False, False]
    assert (out / "index.csv").is_file()
    table = Study.from_file(study_file(tmp_path, seeds=(7, 9)), out_dir=out).results()
    assert len(table) == 4


@needs_yade
@pytest.mark.yade
def test_killed_study_resumes_without_redoing_finished_runs(tmp_path):
    out = tmp_path / "study"
    path = study_file(tmp_path)
    cmd = [sys.executable, "-m", "orchestrator", "study", str(path), "--out", str(out), "--workers", "1",
           "--no-progress"]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline and not list(out.glob("*/run.h5")):
        time.sleep(0.2)
    os.killpg(proc.pid, signal.SIGKILL)  # the study and its engines die at once, as on a lost machine
    proc.wait()
    finished = {p.parent.name: p.stat().st_mtime for p in out.glob("*/run.h5")}
    assert 1 <= len(finished) < 4
    rows = Study.from_file(path, out_dir=out).run(progress=False)
    assert [r["status"] for r in rows] == ["ok"] * 4
    for name, mtime in finished.items():
        assert (out / name / "run.h5").stat().st_mtime == mtime  # not redone
    assert sum(r["reused"] for r in rows) == len(finished)


def test_points_of_grid_zip_list():
    assert grid({"a": [1, 2], "b": [3, 4]}) == [{"a": 1, "b": 3}, {"a": 1, "b": 4}, {"a": 2, "b": 3}, {"a": 2, "b": 4}]
    assert zipped({"a": [1, 2], "b": [3, 4]}) == [{"a": 1, "b": 3}, {"a": 2, "b": 4}]


BAD = {
    "unknown-parameter": ('[study]\nname="t"\ncase="CASE"\n[sweep]\n[sweep.parameters]\n"media.colour"=[1]\n',
                          ["media.colour", "unknown key"]),
    "empty-sweep": ('[study]\nname="t"\ncase="CASE"\n[sweep]\n[sweep.parameters]\n', ["sweep.parameters is empty"]),
    "empty-list": ('[study]\nname="t"\ncase="CASE"\n[sweep]\n[sweep.parameters]\n"media.count"=[]\n',
                   ["media.count", "empty list"]),
    "zip-lengths": ('[study]\nname="t"\ncase="CASE"\n[sweep]\nmode="zip"\n[sweep.parameters]\n'
                    '"media.count"=[50,60]\n"case.seed"=[1]\n', ["equal length", "media.count"]),
    "unknown-engine": ('[study]\nname="t"\ncase="CASE"\nengines=["fluent"]\n[sweep]\n[sweep.parameters]\n'
                       '"media.count"=[50]\n', ["fluent", f"allowed: {', '.join(engine_names())}"]),
    "bad-value": ('[study]\nname="t"\ncase="CASE"\n[sweep]\n[sweep.parameters]\n"media.count"=[50, -3]\n',
                  ["media.count", "-3"]),
    "missing-case": ('[study]\nname="t"\ncase="nope.toml"\n[sweep]\n[sweep.parameters]\n"media.count"=[50]\n',
                     ["nope.toml", "not found"]),
    "unknown-mode": ('[study]\nname="t"\ncase="CASE"\n[sweep]\nmode="random"\n[sweep.parameters]\n"a"=[1]\n',
                     ["sweep.mode", "random"]),
    # 200 x 200 = 40,000 grid points: refused before one point is built, naming the limit and both axes
    "too-many-points": ('[study]\nname="t"\ncase="CASE"\n[sweep]\n[sweep.parameters]\n'
                        f'"numerics.stiffness_scale"={[1e-3 * (1 + k) for k in range(200)]}\n'
                        f'"case.seed"={list(range(200))}\n',
                        ["40,000 runs", "at most 10,000",
                         "numerics.stiffness_scale (200 values) x case.seed (200 values)"]),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_study_files(tmp_path, name):
    text, words = BAD[name]
    path = tmp_path / "bad.toml"
    path.write_text(text.replace("CASE", str(TINY_BOWL)))
    proc = subprocess.run([sys.executable, "-m", "orchestrator", "study", str(path), "--out", str(tmp_path / "o")],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode != 0
    assert proc.stderr.startswith("error:") and "Traceback" not in proc.stderr
    for word in words:
        assert word in proc.stderr, (word, proc.stderr)
    assert proc.returncode == 2
    if name == "too-many-points":
        assert len(proc.stderr.strip().splitlines()) == 1
    assert not list((tmp_path / "o").glob("*/run.h5"))


def test_a_huge_grid_is_refused_before_any_point_is_built():
    """A 1e5 x 1e5 grid (1e10 runs) is counted, not built: one CaseError naming the limit and the axes, at once."""
    from orchestrator.errors import CaseError
    from orchestrator.study.spec import MAX_STUDY_POINTS, Sweep

    axis = list(range(100_000))
    sweep = Sweep(mode="grid", parameters={"numerics.stiffness_scale": axis, "case.seed": axis})
    assert sweep.size() == 10 ** 10
    start = time.monotonic()
    with pytest.raises(CaseError) as caught:
        sweep.points()
    assert time.monotonic() - start < 1.0
    message = str(caught.value)
    assert f"{MAX_STUDY_POINTS:,}" in message and "10,000,000,000 runs" in message
    assert "numerics.stiffness_scale (100,000 values) x case.seed (100,000 values)" in message
    assert len(message.splitlines()) == 1
    # at the limit a grid is built; zip and list count their runs, not a product
    assert len(grid({"a": list(range(100)), "b": list(range(100))})) == MAX_STUDY_POINTS
    assert Sweep(mode="zip", parameters={"a": axis[:5000], "b": axis[:5000]}).size() == 5000


@needs_yade
@pytest.mark.yade
def test_dask_local_cluster_gives_the_same_index(tmp_path):
    pytest.importorskip("distributed")
    from orchestrator.study.dask import dask_executor

    path = study_file(tmp_path)
    local = Study.from_file(path, out_dir=tmp_path / "local").run(progress=False)
    with dask_executor("local", workers=2) as executor:
        on_dask = Study.from_file(path, out_dir=tmp_path / "dask").run(executor=executor, progress=False)
    assert [r["run_id"] for r in on_dask] == [r["run_id"] for r in local]
    assert [r["status"] for r in on_dask] == ["ok"] * 4
    # same identity and same physics: Yade on one thread is deterministic
    for a, b in zip(local, on_dask):
        assert a["fn_mean"] == b["fn_mean"] and a["n_steps"] == b["n_steps"]


def test_pareto_front_and_errors():
    from orchestrator.study.report import pareto_front, relative_errors

    # (wall, error): (1, .5) (2, .1) (3, .2) (4, .0) -> (3, .2) is beaten by (2, .1)
    assert pareto_front([1, 2, 3, 4], [0.5, 0.1, 0.2, 0.0]) == [True, True, False, True]
    # equal points beat neither; at equal cost the smaller error wins; at equal error the cheaper one
    assert pareto_front([1, 1, 2], [0.2, 0.2, 0.2]) == [True, True, False]
    assert pareto_front([1, 1, 3], [0.3, 0.2, 0.1]) == [False, True, True]
    assert relative_errors([-2.0, -1.8], -2.0) == pytest.approx([0.0, 0.1])


def test_report_from_an_index(tmp_path):
    import csv

    from orchestrator.study.report import write_study_report

    rows = [  # a stiffness sweep: stiffer = finer step = slower; fn_mean converges to -2.0
        {"run_id": "a" * 64, "engine": "yade", "run_dir": str(tmp_path / "a"), "param:numerics.stiffness_scale": 1.0,
         "status": "ok", "wall_time_s": 1000.0, "dt": 1e-7, "fn_mean": -2.0},
        {"run_id": "b" * 64, "engine": "yade", "run_dir": str(tmp_path / "b"), "param:numerics.stiffness_scale": 0.1,
         "status": "ok", "wall_time_s": 300.0, "dt": 3e-7, "fn_mean": -1.95},
        {"run_id": "c" * 64, "engine": "yade", "run_dir": str(tmp_path / "c"), "param:numerics.stiffness_scale": 0.01,
         "status": "ok", "wall_time_s": 100.0, "dt": 1e-6, "fn_mean": -1.7},
        {"run_id": "d" * 64, "engine": "yade", "run_dir": str(tmp_path / "d"), "param:numerics.stiffness_scale": 0.001,
         "status": "failed", "wall_time_s": 5.0, "dt": 3e-6, "fn_mean": ""},
    ]
    with open(tmp_path / "index.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    html = write_study_report(tmp_path, quantity="fn_mean", tolerance=0.05).read_text()
    # the finest run is the reference; 0.1 is the cheapest within 5 % (error 0.025); 0.01 is 15 % off
    assert "run aaaaaaaaaaaa" in html
    assert "#2, numerics.stiffness_scale = 0.1 on yade" in html and "3 x faster than the reference run" in html
    assert "0.025" in html and "0.15" in html and "failed" in html
    assert "data:image/png;base64," in html


SPHERE_PLANE = VERIFICATION / "chung_ooi_test2_sphere_plane.toml"


def test_a_change_to_the_code_that_fills_the_input_reruns_the_run(tmp_path, monkeypatch):
    """The run identity hashes the rendered input files: changing only the Python that fills them (here the
    reference engine's scene description, not any template or case value) makes the study rerun the run."""
    from orchestrator.kinds.impact import reference

    study_path = tmp_path / "ref.toml"
    study_path.write_text(f"""
[study]
name = "ref"
case = "{SPHERE_PLANE}"
engines = ["reference"]
[sweep]
mode = "list"
[[sweep.runs]]
"contacts.0.restitution" = 0.5
""")
    out = tmp_path / "study"
    first = Study.from_file(study_path, out_dir=out).run(progress=False)
    assert [r["status"] for r in first] == ["ok"] and not first[0]["reused"]
    again = Study.from_file(study_path, out_dir=out).run(progress=False)
    assert again[0]["reused"] and again[0]["run_id"] == first[0]["run_id"]

    original = reference.scene_description

    def changed(scene):
        description = original(scene)
        description["dt"] *= 0.5  # what a change to a context function does
        return description

    monkeypatch.setattr(reference, "scene_description", changed)
    third = Study.from_file(study_path, out_dir=out).run(progress=False)
    assert third[0]["run_id"] != first[0]["run_id"] and not third[0]["reused"] and third[0]["status"] == "ok"
    assert third[0]["n_steps"] > first[0]["n_steps"]


def test_the_mpi_rank_count_is_part_of_the_identity(monkeypatch):
    from orchestrator.kinds import bind
    from orchestrator.case import load_case
    from orchestrator.identity import run_identity
    from orchestrator.kinds import build_scene

    loaded = load_case(TINY_BOWL)
    scene = build_scene(loaded.model)
    one = run_identity(loaded, "liggghts", "3.8.0", bind("drag_finishing", "liggghts", mpi_ranks=1), scene)
    two = run_identity(loaded, "liggghts", "3.8.0", bind("drag_finishing", "liggghts", mpi_ranks=2), scene)
    assert one != two
    assert one == run_identity(loaded, "liggghts", "3.8.0", bind("drag_finishing", "liggghts", mpi_ranks=1), scene)
