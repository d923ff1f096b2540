"""Bad inputs through every command of the CLI, in-process: each ends with the documented exit code and one
'error:' line naming the problem, never a traceback or an 'internal error', and changes nothing outside the
run directory it was given.

Every input fails during validation, before any engine starts (the engines' variables point at nothing, so a
regression could not start Yade, LIGGGHTS or the sph executable either). Exit codes: 2 bad input (CaseError,
OrchestratorError, argparse), 6 unreadable file (ReadError), 1 a fit the data contradict.

Counts: test_numeric_keys 960 (40 shipped cases x 4 numeric keys x 6 values), test_positive_keys 44,
test_bad_input 174, test_bad_option 21, test_out_dirs 24 (8 commands x 3 folders), test_read_only_out 6,
test_hypothesis_values 40 examples: 1269 bad inputs in all, over every command.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import h5py
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from orchestrator.case import load_case
from orchestrator.cli import main
from paths import REPO, CASES, DATA

VER = CASES / "verification"
DRAG, DROP = CASES / "drag_finishing_uhlmann2015.toml", VER / "uhlmann2015_sphere_drop.toml"
PLANE, DAM = VER / "chung_ooi_test2_sphere_plane.toml", CASES / "sph" / "dam_break_2d.toml"
TANK, POIS, PEN = VER / "sph_hydrostatic_tank.toml", VER / "sph_poiseuille_morris1997.toml", VER / "sph_penalty_column.toml"
CHANNEL, REF2D = DATA / "sph_channel_3d.toml", DATA / "sph_reference_2d.toml"
SHIPPED = sorted(p for p in CASES.rglob("*.toml") if "studies" not in p.parts and p.name != "dense_pile.toml")
VALUES = ("inf", "-inf", "nan", '"text"', "true", "1e308")
LONG = "n" * 300


@pytest.fixture(autouse=True)
def no_engines(monkeypatch):
    for name in ("YADE", "LIGGGHTS", "SPH"):
        monkeypatch.setenv(f"ORCHESTRATOR_{name}", "/nonexistent/engine")


@pytest.fixture(scope="module")
def bad(tmp_path_factory) -> Path:
    """Bad input files, written once: case and study files, CSVs, study and run directories."""
    d = tmp_path_factory.mktemp("bad")
    w = lambda name, text: (d / name).parent.mkdir(parents=True, exist_ok=True) or (d / name).write_text(text)  # noqa: E731
    (d / "binary.toml").write_bytes(bytes(range(256)) * 4)
    w("malformed.toml", "[case\nkind = ")
    w("deep.toml", "x = " + "[" * 5000 + "]" * 5000 + "\n")
    w("nocase.toml", "[media]\ncount = 3\n")
    w("case5.toml", "case = 5\n")
    w("kind.toml", '[case]\nkind = "fluent"\nname = "x"\n')
    w("empty.toml", "")
    (d / "dir.toml").mkdir()
    for name, study in {
        "sph_study": f'[study]\nname = "s"\ncase = "{TANK}"\n[sweep.parameters]\n"numerics.dx" = [0.005]\n',
        "inf_timeout": f'[study]\nname = "s"\ncase = "{PLANE}"\ntimeout = inf\nengines = ["reference"]\n'
                       '[sweep.parameters]\n"case.seed" = [1]\n',
        "neg_timeout": f'[study]\nname = "s"\ncase = "{PLANE}"\ntimeout = -1\n[sweep.parameters]\n"case.seed" = [1]\n',
        "nostudy": '[sweep.parameters]\n"case.seed" = [1]\n',
        "empty_sweep": f'[study]\nname = "s"\ncase = "{PLANE}"\n[sweep]\nmode = "grid"\n',
        "zip": f'[study]\nname = "s"\ncase = "{PLANE}"\n[sweep]\nmode = "zip"\n[sweep.parameters]\n"a.b" = [1, 2]\n'
               '"c.d" = [1]\n',
        "list_empty": f'[study]\nname = "s"\ncase = "{PLANE}"\n[sweep]\nmode = "list"\n',
        "missing_case": '[study]\nname = "s"\ncase = "nowhere.toml"\n[sweep.parameters]\n"case.seed" = [1]\n',
        "dir_case": f'[study]\nname = "s"\ncase = "{d}"\n[sweep.parameters]\n"case.seed" = [1]\n',
        "engine": f'[study]\nname = "s"\ncase = "{PLANE}"\nengines = ["fluent"]\n[sweep.parameters]\n"case.seed" = [1]\n',
        "sweep_inf": f'[study]\nname = "s"\ncase = "{PLANE}"\nengines = ["reference"]\n[sweep.parameters]\n'
                     '"simulation.duration" = [inf]\n',
        "sweep_key": f'[study]\nname = "s"\ncase = "{PLANE}"\nengines = ["reference"]\n[sweep.parameters]\n'
                     '"simulation.nope" = [1]\n',
        "ok_reference": f'[study]\nname = "s"\ncase = "{PLANE}"\nengines = ["reference"]\n'
                        '[sweep.parameters]\n"case.seed" = [1]\n',
        "bad_name": f'[study]\nname = "a/../b"\ncase = "{PLANE}"\n[sweep.parameters]\n"case.seed" = [1]\n',
        "zero_ranks": f'[study]\nname = "s"\ncase = "{TANK}"\nengines = ["lammps"]\nmpi_ranks = 0\n'
                      '[sweep.parameters]\n"simulation.duration" = [0.01]\n',
        "ranks_no_mpi": f'[study]\nname = "s"\ncase = "{PLANE}"\nengines = ["reference"]\nmpi_ranks = 2\n'
                        '[sweep.parameters]\n"case.seed" = [1]\n',
    }.items():
        w(f"studies/{name}.toml", study)
    rows = [f"{k * 1e-3},{10.0 if k == 50 else 0.0}" for k in range(100)]
    for name, text in {"short.csv": "time_s,force_N\n0,0\n1,1\n", "text.csv": "time_s,force_N\n" + "a,b\n" * 20,
                       "one.csv": "time_s,force_N\n" + "\n".join(rows), "nan.csv": "time_s,force_N\n" + "\n".join(
                           rows[:50] + ["nan,1"] + rows[51:]), "inf.csv": "time_s,force_N\n" + "\n".join(
                           rows[:50] + ["0.05,inf"] + rows[51:]), "back.csv": "time_s,force_N\n" + "\n".join(
                           reversed(rows))}.items():
        w(f"csv/{name}", text)
    (d / "csv" / "binary.csv").write_bytes(bytes(range(256)) * 4)
    for name, content in {"binary": bytes(range(256)) * 8, "nocolumns": b"a,b\n1,2\n", "latin": b"run_id,\xe9\n"}.items():
        (d / "index" / name).mkdir(parents=True)
        (d / "index" / name / "index.csv").write_bytes(content)
    (d / "index" / "zero").mkdir()
    (d / "index" / "zero" / "index.csv").write_text("run_id,engine,status,fn_mean,wall_time_s,dt\n"
                                                      "abc,yade,ok,0.0,1.0,1e-5\n")
    for name in ("text", "nocase", "empty"):
        (d / "runs" / name).mkdir(parents=True)
    (d / "runs" / "text" / "run.h5").write_text("not hdf5\n")
    with h5py.File(d / "runs" / "nocase" / "run.h5", "w") as h5:
        h5.attrs["status"] = "ok"
        h5.create_group("series").create_dataset("time", data=[0.0, 1.0])
    with h5py.File(d / "runs" / "empty" / "run.h5", "w"):
        pass
    (d / "afile").write_text("a file\n")
    return d


def _tree(root: Path, skip: Path | None = None) -> dict:
    out = {}
    for path in sorted(root.rglob("*")):
        if skip is not None and (path == skip or skip in path.parents):
            continue
        stat = path.lstat()
        out[str(path)] = (stat.st_size, stat.st_mtime_ns, path.is_dir())
    return out


@pytest.fixture
def cli(tmp_path, capsys, monkeypatch, bad):
    """call(argv, code, *words): run the CLI in tmp_path/cwd and check the exit code, the one error line, the
    words (a tuple means any of them) and that nothing outside tmp_path/out changed."""
    cwd = tmp_path / "cwd"
    cwd.mkdir()
    monkeypatch.chdir(cwd)
    out_dir = tmp_path / "out"

    def call(argv, code, *words):
        argv = [str(a).replace("@OUT", str(out_dir)).replace("@BAD", str(bad)) for a in argv]
        before = (_tree(tmp_path, skip=out_dir), _tree(CASES), _tree(bad))
        try:
            got = main(argv)
        except SystemExit as exc:  # argparse: usage and 'orchestrator X: error: ...'
            got = exc.code
        captured = capsys.readouterr()
        text = captured.err + captured.out
        assert got == code, text
        assert "Traceback" not in text and "internal error" not in text, text
        errors = [line for line in text.splitlines() if line.startswith("error:") or ": error: " in line]
        assert len(errors) == 1, text
        for word in words:
            options = word if isinstance(word, tuple) else (word,)
            assert any(option in text for option in options), f"{word!r} not in: {text}"
        assert (_tree(tmp_path, skip=out_dir), _tree(CASES), _tree(bad)) == before
        return text

    return call


def _numeric_keys(path: Path) -> list[str]:
    def leaves(node, prefix):
        if isinstance(node, dict):
            for k, v in node.items():
                yield from leaves(v, prefix + [k])
        elif isinstance(node, list):
            for i, v in enumerate(node):
                yield from leaves(v, prefix + [str(i)])
        elif isinstance(node, (int, float)) and not isinstance(node, bool):
            yield ".".join(prefix)

    keys = list(leaves(load_case(path).resolved, []))
    return [keys[round(i * (len(keys) - 1) / 3)] for i in range(4)]  # four keys spread over the case


def _shown(key: str) -> str:
    """How the error names a dotted --set key: indices in brackets, a vector's element as the vector."""
    parts = key.split(".")
    while parts and parts[-1].isdigit():
        parts.pop()
    out = ""
    for part in parts:
        out += f"[{part}]" if part.isdigit() else (f".{part}" if out else part)
    return out


NUMERIC = [(path, key, value) for path in SHIPPED for key in _numeric_keys(path) for value in VALUES]


# 576 cases: 24 shipped cases x 4 numeric keys x {inf, -inf, nan, "text", true, 1e308}
@pytest.mark.parametrize("path,key,value", NUMERIC, ids=[f"{p.stem}-{k}={v}" for p, k, v in NUMERIC])
def test_numeric_keys(cli, path, key, value):
    cli(["run", path, "--set", f"{key}={value}", "--out", "@OUT", "--no-progress"], 2, _shown(key))


POSITIVE = [(DRAG, k) for k in ("materials.steel.density", "materials.ceramic.young_modulus", "media.radius",
                                "media.count", "bowl.inner_radius", "process.duration", "workpiece.speed",
                                "output.record_interval", "numerics.timestep_factor", "numerics.stiffness_scale",
                                "numerics.threads")] + \
           [(DROP, k) for k in ("spheres.0.radius", "simulation.duration", "contacts.0.restitution",
                                "numerics.timestep", "output.record_interval")] + \
           [(DAM, k) for k in ("numerics.dx", "fluid.density", "fluid.max_speed", "simulation.duration",
                               "output.frame_interval", "numerics.h_over_dx")]


# 44 cases: 22 keys that must be positive x {0, -1}
@pytest.mark.parametrize("path,key,value", [(p, k, v) for p, k in POSITIVE for v in ("0", "-1")])
def test_positive_keys(cli, path, key, value):
    cli(["run", path, "--set", f"{key}={value}", "--out", "@OUT", "--no-progress"], 2, _shown(key))


def _run(case, *sets):
    return ["run", case, *[a for s in sets for a in ("--set", s)], "--out", "@OUT", "--no-progress"]


CSV = "@BAD/csv/"
BAD_INPUTS = [
    # case files
    (["run", "@BAD/missing.toml"], 2, "not found"), (["run", "@BAD/dir.toml"], 2, "is a directory"),
    (["run", "/dev/null"], 2, "not a regular file"), (["run", "@BAD/binary.toml"], 2, "not a text file"),
    (["run", "@BAD/malformed.toml"], 2, "malformed TOML"), (["run", "@BAD/deep.toml"], 2, "nested too deeply"),
    (["run", "@BAD/nocase.toml"], 2, "[case] table is missing"), (["run", "@BAD/case5.toml"], 2, "case = 5"),
    (["run", "@BAD/kind.toml"], 2, "case.kind"), (["run", "@BAD/empty.toml"], 2, "[case] table is missing"),
    (_run(DAM, "fluid.density=" + "[" * 5000 + "]" * 5000), 2, "nested too deeply"),
    (_run(DAM, "blocks.-1.lo=[0, 0]"), 2, "negative indices are not allowed", "0 to 3"),
    (_run(DAM, "blocks.9.lo=[0, 0]"), 2, "allowed indices: 0 to 3"),
    (_run(DAM, "output.probes.-1=1"), 2, "negative indices are not allowed"),
    (_run(DAM, "noequals"), 2, "expected KEY=VALUE"), (_run(DAM, "a..b=1"), 2, "empty part"),
    (_run(DAM, "fluid.nope=1"), 2, "fluid.nope", "unknown key"), (_run(DAM, "fluid.density.x=1"), 2, "is a value"),
    (["run", PLANE, "--engine", "fluent"], 2, "unknown engine"), (["run", PLANE, "--preset", "nope"], 2, "unknown preset"),
    # item 5: non-finite numbers, named
    (_run(DAM, "fluid.density=inf"), 2, "fluid.density", "finite"),
    (_run(DAM, "numerics.h_over_dx=inf"), 2, "numerics.h_over_dx"), (_run(POIS, "fluid.viscosity=inf"), 2, "fluid.viscosity"),
    (_run(PEN, "physics.wall_penalty.psi=inf"), 2, "physics.wall_penalty.psi"), (_run(CHANNEL, "walls.2.scale=inf"), 2, "walls[2].scale"),
    (_run(DRAG, "contacts.0.friction=inf"), 2, "contacts[0].friction"), (_run(DROP, "contacts.0.friction=nan"), 2, "contacts[0].friction"),
    (_run(DROP, "spheres.0.velocity=[0, 0, -inf]"), 2, "spheres[0].velocity"), (_run(DAM, "domain.hi=[nan, 1]"), 2, "domain.hi"),
    (_run(REF2D, "numerics.dt=nan"), 2, "numerics.dt"), (_run(DRAG, "output.network_times=[1, inf]"), 2, "output.network_times"),
    # item 5: step counts, records, memory, placement
    (_run(TANK, "output.frame_interval=1e-12"), 2, "output.frame_interval", "particle frames"),
    (_run(TANK, "output.series_interval=1e-12"), 2, "output.series_interval", "records"),
    (_run(TANK, "numerics.dt=1e-20"), 2, "numerics.dt", "time steps"), (_run(TANK, "numerics.dt=1e-300"), 2, "numerics.dt"),
    (_run(TANK, "simulation.duration=1e25"), 2, "simulation.duration", "time steps"),
    (_run(TANK, "numerics.dx=1e-9"), 2, "numerics.dx", "memory"), (_run(CHANNEL, "numerics.dx=1e-7"), 2, "memory"),
    (_run(TANK, "numerics.dx=1e308"), 2, "numerics.dx"), (_run(TANK, "numerics.dx=10"), 2, "less than one spacing"),
    (_run(REF2D, "output.series_interval=1e-5"), 2, "below the time step"),
    (_run(REF2D, "output.frame_interval=1e-5"), 2, "below the time step"),
    (_run(DAM, "output.probes.0.point=[9, 9]"), 2, "output.probes[0].point", "outside the domain"),
    (_run(DAM, "output.flow_planes.0.center=[-9, 0.1]"), 2, "output.flow_planes[0].center", "outside"),
    (_run(CHANNEL, "inlets.0.center=[5, 5, 5]"), 2, "inlets[0].center", "outside"),
    (_run(CHANNEL, "outlets.0.center=[-5, 0, 0]"), 2, "outlets[0].center", "outside"),
    (_run(CHANNEL, "inlets.0.layers=100000"), 2, "inlets[0].layers"), (_run(CHANNEL, "numerics.max_steps=2000000000"), 2, "numerics.max_steps"),
    (_run(DROP, "numerics.timestep=1.0"), 2, "numerics.timestep", "longer than the run"),
    (_run(DROP, "numerics.timestep=1e-20"), 2, "time steps"), (_run(DROP, "numerics.timestep_factor=1e-25"), 2, "time steps"),
    (_run(DROP, "simulation.duration=1e308"), 2, "simulation.duration"), (_run(DROP, "simulation.duration=1e20"), 2, "time steps"),
    (_run(DROP, "output.record_interval=1e-15"), 2, "output.record_interval", "records"),
    (_run(DRAG, "process.duration=1e20"), 2, "process.duration", "time steps"),
    (_run(DRAG, "settling.max_time=1e20"), 2, "settling.max_time", "time steps"),
    (_run(DRAG, "output.checkpoint_interval=1e-9"), 2, "output.checkpoint_interval", "checkpoints"),
    (_run(DRAG, "output.record_interval=1e-7", "process.duration=0.8", "output.network_times=[]",
          "output.impact_window=[0.5, 0.8]"), 2, "output.record_interval", "below the time step"),
    (_run(DRAG, "output.record_interval=1e-12"), 2, "output.record_interval"), (_run(DRAG, "media.radius=1e-31"), 2, "media.radius"),
    (_run(DRAG, "bowl.inner_radius=1e-300"), 2, "bowl.inner_radius"), (_run(DRAG, "case.seed=1e308"), 2, "case.seed"),
    (_run(DAM, "numerics.h_over_dx=0.1"), 2, "numerics.h_over_dx"), (_run(DAM, "numerics.h_over_dx=50"), 2, "numerics.h_over_dx"),
    # item 6: mesh files
    (_run(CHANNEL, 'walls.2.file="/etc/passwd"'), 2, "walls[2].file", "not a mesh file"),
    (_run(CHANNEL, f'walls.2.file="{REPO / "README.md"}"'), 2, "walls[2].file", "'.md'"),
    (_run(CHANNEL, 'walls.2.file="/tmp"'), 2, "walls[2].file", "not a regular file"),
    (_run(CHANNEL, 'walls.2.file="/dev/null"'), 2, "not a regular file"),
    (_run(CHANNEL, 'walls.2.file="nowhere.stl"'), 2, "walls[2].file", "not found"),
    (_run(DRAG, 'workpiece.mesh="/etc/passwd"'), 2, "workpiece.mesh", "not a mesh file"),
    (_run(DRAG, 'workpiece.mesh="/etc/hostname.stl"'), 2, "workpiece.mesh", "not found"),
    # analyze and export of what is not a run
    (["analyze", "@BAD/nowhere"], 6, "no run.h5"), (["analyze", "@BAD/runs/text"], 6, "cannot read"),
    (["analyze", "@BAD/runs/nocase"], 6, "no /case"), (["analyze", "@BAD/runs/empty"], 6, "no /case"),
    (["analyze", "@BAD/afile"], 6, "cannot read"),
    (["export", "@BAD/nowhere", "--out", "@OUT"], 6, "no run.h5"), (["export", "@BAD/runs/text", "--out", "@OUT"], 6, "cannot read"),
    (["export", "@BAD/runs/nocase", "--out", "@OUT"], 6, "no /case"), (["export", "@BAD/runs/empty", "--out", "@OUT"], 6, "no /case"),
    # study files
    *[(["study", f"@BAD/studies/{name}.toml", "--out", "@OUT", "--no-progress"], 2, *words) for name, words in {
        "sph_study": ("does not run sph_flow", 'engines = ["lammps", "sph"]'), "inf_timeout": ("study.timeout", "finite"),
        "neg_timeout": ("study.timeout",), "nostudy": ("study", "missing"), "empty_sweep": ("sweep.parameters",),
        "zip": ("zip",), "list_empty": ("sweep.runs",), "missing_case": ("case file not found",),
        "dir_case": ("is a directory",), "engine": ("fluent",), "sweep_inf": ("simulation.duration", "finite"),
        "sweep_key": ("simulation.nope",), "bad_name": ("study.name",), "zero_ranks": ("study.mpi_ranks",),
        "ranks_no_mpi": ("study.mpi_ranks = 2", "does not run under MPI")}.items()],
    (["study", "@BAD/missing.toml"], 2, "not found"), (["study", "@BAD/dir.toml"], 2, "is a directory"),
    (["study", "@BAD/binary.toml"], 2, "not a text file"), (["study", "@BAD/deep.toml"], 2, "nested too deeply"),
    (["study", "/dev/null"], 2, "not a regular file"),
    (["study", CASES / "studies" / "tiny_bowl_sweep.toml", "--workers", "0", "--out", "@OUT"], 2, "--workers"),
    (["study", CASES / "studies" / "tiny_bowl_sweep.toml", "--workers", "-2", "--out", "@OUT"], 2, "--workers"),
    # status and report
    *[([command, f"@BAD/index/{name}"], 2, *words) for command in ("status", "report") for name, words in {
        "binary": ("index.csv", "not a text file"), "nocolumns": ("index.csv", "no column"),
        "latin": ("not a text file",)}.items()],
    (["status", "@BAD/nowhere"], 2, "no index.csv"), (["report", "@BAD/nowhere"], 2, "no index.csv"),
    (["status", "@BAD/afile"], 2, "no index.csv"), (["report", "@BAD/index/zero"], 2, "magnitude"),
    *[(["report", "@BAD/index/zero", "--reference", r], 2, "--reference") for r in ("nan", "5e-324", "1e308")],
    (["report", "@BAD/index/zero", "--quantity", "nope"], 2, "'nope'"),
    *[(["report", "@BAD/index/zero", "--tolerance", t], 2, "--tolerance") for t in ("0", "-1", "nan", "inf")],
    # verify
    (["verify", "dem", "--cases", "@BAD/nowhere", "--out", "@OUT"], 2, "does not exist"),
    (["verify", "dem", "--cases", "@BAD/afile", "--out", "@OUT"], 2, "is not a directory"),
    (["verify", "sph", "--cases", "@BAD/csv", "--out", "@OUT"], 2, "no sph_flow case files"),
    (["verify", "dem", "--engine", "reference", "--set", "numerics.timestep_factor=inf", "--out", "@OUT"], 2,
     "numerics.timestep_factor"),
    (["verify", "dem", "--engine", "reference", "--set", "simulation.nope=1", "--out", "@OUT"], 2, "simulation.nope"),
    (["verify", "sph", "--set", "numerics.dx=1e-9", "--out", "@OUT"], 2, "memory"),
    (["verify", "dem", "--engine", "fluent", "--out", "@OUT"], 2, "unknown engine"),
    (["verify", "dem", "--engine", "sph", "--out", "@OUT"], 2, "does not run DEM"),
    (["verify", "sph", "--engine", "yade", "--out", "@OUT"], 2, "the engines lammps, sph"),
    (["verify", "sph", "--timestep-factors", "0.1", "--out", "@OUT"], 2, "--timestep-factors"),
    *[(["verify", "dem", "--timestep-factors", f, "--out", "@OUT"], 2, "--timestep-factors") for f in ("0", "2", "nan")],
    *[(["verify", s, "--workers", n, "--out", "@OUT"], 2, "--workers") for s in ("dem", "sph") for n in ("0", "-1")],
    *[(["verify", s, "--timeout", t, "--out", "@OUT"], 2, "--timeout") for s in ("dem", "sph") for t in ("0", "nan")],
    # calibrate
    *[(["calibrate", "restitution", "--csv", CSV + name], 6, *words) for name, words in {
        "missing.csv": ("no CSV file",), "short.csv": ("fewer than 10",), "text.csv": ("of numbers",),
        "one.csv": ("found 1 impact",), "nan.csv": ("not a finite number",), "inf.csv": ("not a finite number",),
        "back.csv": ("must increase",), "binary.csv": (("of numbers", "not a text CSV"),)}.items()],
    (["calibrate", "restitution", "--csv", "@BAD/csv"], 6, "is a directory"),
    (["calibrate", "restitution", "--csv", "/dev/null"], 6, "not a regular file"),
    (["calibrate", "restitution", "--run", "@BAD/nowhere"], 6, "no run.h5"),
    (["calibrate", "restitution", "--run", "@BAD/runs/nocase"], 6, ("no /case", "contact events")),
    (["calibrate", "restitution", "--run", "@BAD/runs/text"], 6, "cannot read"),
    # compare and bench
    (["compare", PLANE, "--engines", "", "--out", "@OUT"], 2, "--engines"),
    (["compare", PLANE, "--engines", "fluent", "--out", "@OUT"], 2, "unknown engine"),
    (["compare", PLANE, "--engines", "reference", "--set", "simulation.duration=inf", "--out", "@OUT"], 2,
     "simulation.duration"),
    (["compare", "@BAD/dir.toml", "--engines", "reference", "--out", "@OUT"], 2, "is a directory"),
    *[(["compare", PLANE, "--engines", "reference", "--timeout", t, "--out", "@OUT"], 2, "--timeout") for t in ("0", "nan")],
    *[(["bench", "sph", option, value, "--out", "@OUT"], 2, option) for option, value in (
        ("--steps-2d", "0"), ("--steps-3d", "-1"), ("--repeat", "0"), ("--steps-2d", "10000000000"))],
    # run options
    *[(["run", PLANE, "--engine", "reference", "--timeout", t, "--out", "@OUT"], 2, "--timeout") for t in
      ("0", "-1", "nan", "inf", "-inf")],
    *[(["run", PLANE, "--mpi", n, "--out", "@OUT"], 2, "--mpi") for n in ("0", "-3")],
    *[(["run", TANK, "--engine", "lammps", "--mpi", n, "--out", "@OUT"], 2, "--mpi") for n in ("0", "-2", "2000")],
]


# 174 cases (the list above, by command: run 81, analyze 5, export 4, study 22, status 5, report 13, verify 21,
# calibrate 13, compare 6, bench 4; the comprehensions expand to these counts)
@pytest.mark.parametrize("argv,code,words", [(a, c, w) for a, c, *w in BAD_INPUTS],
                         ids=[" ".join(str(x).rsplit("/", 1)[-1] for x in a)[:80] for a, *_ in BAD_INPUTS])
def test_bad_input(cli, argv, code, words):
    cli(argv, code, *words)


BAD_OPTIONS = [["doctor", "--bogus"], ["doctor", "extra"], ["run"], ["run", PLANE, "--timeout", "abc"],
               ["run", PLANE, "--mpi", "x"], ["verify", "xyz"], ["verify", "dem", "--workers", "1.5"],
               ["bench", "sph", "--steps-2d", "abc"], ["bench", "gpu"], ["calibrate", "restitution"],
               ["calibrate", "friction", "--csv", "x"], ["calibrate", "restitution", "--csv", "a", "--run", "b"],
               ["compare", PLANE], ["study", "x.toml", "--workers", "abc"], ["export"], ["status"], ["analyze"],
               ["report", "x", "--tolerance", "abc"], ["nosuchcommand"], ["--nosuchoption"],
               ["verify", "dem", "--timestep-factors"]]


# 21 cases: what argparse refuses (exit 2, 'orchestrator ...: error: ...')
@pytest.mark.parametrize("argv", BAD_OPTIONS, ids=[" ".join(map(str, a))[-60:] for a in BAD_OPTIONS])
def test_bad_option(cli, argv):
    cli(argv, 2, "error:")


OUT_COMMANDS = {
    "run": ["run", PLANE, "--engine", "reference", "--no-progress"], "study": ["study", "@BAD/studies/ok_reference.toml"],
    "compare": ["compare", PLANE, "--engines", "reference"], "verify": ["verify", "dem", "--engine", "reference"],
    "verify-sph": ["verify", "sph"], "bench": ["bench", "sph"], "export": ["export", "@BAD/runs/nocase"],
    "timestep-sweep": ["verify", "dem", "--engine", "reference", "--timestep-factors", "0.1"],
}
OUTS = {"file": ("@BAD/afile", "is a file, not a folder"), "devnull": ("/dev/null", "device or special file"),
        "long": (f"@OUT/{LONG}", "bytes long")}


# 24 cases: 8 commands x --out a file, /dev/null, a name over NAME_MAX
@pytest.mark.parametrize("command", OUT_COMMANDS)
@pytest.mark.parametrize("out", OUTS)
def test_out_dirs(cli, command, out):
    target, words = OUTS[out]
    cli(OUT_COMMANDS[command] + ["--out", target], 2, "--out", words)


@pytest.fixture
def read_only(tmp_path) -> Path:
    """A folder in which nothing can be created: a chmod 555 folder, or as root a sysfs folder."""
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o555)
    try:
        (folder / "probe").mkdir()
    except OSError:
        return folder / "out"
    (folder / "probe").rmdir()
    if os.path.isdir("/sys/kernel"):
        try:
            os.mkdir("/sys/kernel/orchestrator-probe")
        except OSError:
            return Path("/sys/kernel/orchestrator-out")
        os.rmdir("/sys/kernel/orchestrator-probe")
    pytest.skip("no read-only folder here (root, and /sys is writable)")


# 6 cases: --out in a read-only folder
@pytest.mark.parametrize("command", ["study", "compare", "verify", "verify-sph", "export", "bench"])
def test_read_only_out(cli, read_only, command):
    argv = OUT_COMMANDS[command] + ["--out", read_only]
    if command == "export":  # a real run, so that only the folder is wrong
        from conftest import build_synthetic_run

        argv = ["export", build_synthetic_run(Path.cwd() / "run"), "--out", read_only]
    cli(argv, 2, "--out", ("permission denied", "read-only"))


_HYPOTHESIS_KEYS = [(DAM, "fluid.density"), (DAM, "numerics.dx"), (DROP, "simulation.duration"),
                    (DROP, "spheres.0.radius"), (DRAG, "media.radius"), (DRAG, "process.duration"),
                    (TANK, "output.frame_interval"), (PLANE, "contacts.0.friction")]
_UNPHYSICAL = st.floats(allow_nan=True, allow_infinity=True).filter(
    lambda x: not math.isfinite(x) or abs(x) > 1e30 or 0 < abs(x) < 1e-30)


# 40 examples: a key of a shipped case set to a non-finite, huge or tiny number
@settings(max_examples=40, deadline=None, database=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(where=st.sampled_from(_HYPOTHESIS_KEYS), value=_UNPHYSICAL)
def test_hypothesis_values(cli, tmp_path, where, value):
    path, key = where
    text = repr(value).replace("+", "") if math.isfinite(value) else str(value)
    cli(["run", path, "--set", f"{key}={text}", "--out", tmp_path / "out" / "h", "--no-progress"], 2, _shown(key))


def test_describe_returncode():
    from orchestrator.humanize import describe_returncode

    assert describe_returncode(0) == "exited with code 0" and describe_returncode(3) == "exited with code 3"
    assert describe_returncode(-9).startswith("was killed by signal 9 (SIGKILL") and "out-of-memory" in \
        describe_returncode(-9)
    assert "SIGSEGV" in describe_returncode(-11) and "SIGTERM" in describe_returncode(-15)
    assert describe_returncode(-200) == "was killed by signal 200"
