"""The `orchestrator` command line. Heavy modules are imported inside the
commands, so `orchestrator --help` stays fast."""

from __future__ import annotations

import argparse
import json
import math
import sys

from . import __version__


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="orchestrator",
        description="Run particle simulations of machining and finishing processes on established engines "
        "(Yade now; LIGGGHTS and our SPH executable to come) and compare them with the papers and reference "
        "solvers. All quantities are SI (m, kg, s, N, Pa).",
    )
    parser.add_argument("--version", action="version", version=f"orchestrator {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    run = sub.add_parser("run", help="run a case file on an engine and write RUN_DIR/run.h5",
                         description="Validate CASE, build its scene, run it on an engine and write run.h5 "
                         "(status, series, interaction networks, meshes) into the run directory.")
    run.add_argument("case", metavar="CASE", help="TOML case file, e.g. cases/drag_finishing_uhlmann2015.toml")
    run.add_argument("--engine", help="engine name (default: the case's case.engine); see 'orchestrator doctor'")
    run.add_argument("--preset", help="named override set from the case's [presets.NAME] (e.g. quick, full)")
    run.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                     help="override any case value, SI units, e.g. --set media.count=200 (repeatable)")
    run.add_argument("--out", metavar="DIR", help="run directory (default: a new one under runs/)")
    run.add_argument("--timeout", type=float, metavar="SECONDS",
                     help="stop the engine after this wall time, s; run.h5 keeps what was measured")
    run.add_argument("--force", action="store_true", help="overwrite a run already in --out")
    run.add_argument("--json", action="store_true", help="print one JSON object instead of the text summary")
    run.add_argument("--no-progress", action="store_true", help="no progress bar on stderr")

    analyze = sub.add_parser("analyze", help="compare a run with the paper: table and PNG plots",
                             description="Print the run's measured quantities next to the case's published "
                             "references and write PNG plots (force series with the paper's bands; the "
                             "interaction network at its snapshot time) into the run directory.")
    analyze.add_argument("run_dir", metavar="RUN_DIR", help="a directory written by 'orchestrator run'")
    analyze.add_argument("--no-render", action="store_true", help="skip the 3D network rendering (pyvista)")

    study = sub.add_parser("study", help="run a study file: a sweep of a case over parameters and engines",
                           description="Run every point of STUDY (a TOML study file) that is not finished yet; "
                           "finished runs with the same identity (case, engine, engine version, template) are "
                           "reused, so an interrupted study resumes where it stopped. Writes STUDY_DIR/index.csv.")
    study.add_argument("study", metavar="STUDY", help="study TOML file, e.g. cases/studies/tiny.toml")
    study.add_argument("--out", metavar="DIR", help="study directory (default: runs/studies/<name>)")
    study.add_argument("--force", action="store_true", help="rerun every run, finished or not")
    study.add_argument("--workers", type=int, metavar="N", help="parallel runs (default: cores / threads per run)")
    study.add_argument("--dask", metavar="ADDRESS",
                       help="run on a Dask cluster: a scheduler address (tcp://host:8786), or 'local' for a "
                       "LocalCluster of --workers processes; run directories must be on storage the workers share")
    study.add_argument("--json", action="store_true", help="print the rows as a JSON list")
    study.add_argument("--no-progress", action="store_true", help="no progress bar")

    status = sub.add_parser("status", help="table of a study's runs: parameters, engine, status, wall time, results")
    status.add_argument("study_dir", metavar="STUDY_DIR", help="directory of a study (holds index.csv)")

    report = sub.add_parser("report", help="HTML report of a study: table, speed against error, Pareto front",
                            description="Write STUDY_DIR/report.html (self-contained): the runs' table, wall time "
                            "against the relative error of a measured quantity with the Pareto front, the "
                            "cheapest run within the tolerance, and each run's force plot.")
    report.add_argument("study_dir", metavar="STUDY_DIR", help="directory of a study (holds index.csv)")
    report.add_argument("--quantity", default="fn_mean", help="measured quantity (default fn_mean, N)")
    report.add_argument("--reference", default="finest",
                        help="'finest' (smallest time step), a run id prefix, or a number (closed form / paper)")
    report.add_argument("--tolerance", type=float, default=0.05, help="relative error accepted (default 0.05)")

    doctor = sub.add_parser("doctor", help="which engines are installed, their versions and paths")
    doctor.add_argument("--json", action="store_true", help="print a JSON list")

    export = sub.add_parser("export", help="write VTK files of a run (particles, meshes, networks) for ParaView")
    export.add_argument("run_dir", metavar="RUN_DIR", help="a directory written by 'orchestrator run'")
    export.add_argument("--out", metavar="DIR", help="where to write (default: RUN_DIR/vtk)")
    return parser


def main(argv=None) -> int:
    """Entry point of the console script; returns the exit code."""
    from .errors import OrchestratorError

    parser = _parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    try:
        commands = {"run": _cmd_run, "analyze": _cmd_analyze, "doctor": _cmd_doctor, "export": _cmd_export,
                    "study": _cmd_study, "status": _cmd_status, "report": _cmd_report}
        return commands[args.command](args)
    except OrchestratorError as exc:
        if getattr(args, "json", False) and exc.summary is not None:
            print(json.dumps(_jsonable(exc.summary.as_dict())))
        print(f"error: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        print("error: interrupted; the engine was stopped and run.h5 records what was measured", file=sys.stderr)
        return 130
    except Exception as exc:  # a bug of ours: keep the traceback in a file, show one line
        import tempfile
        import traceback

        with tempfile.NamedTemporaryFile("w", prefix="orchestrator-crash-", suffix=".log", delete=False) as fh:
            traceback.print_exc(file=fh)
        print(f"error: internal error ({type(exc).__name__}: {exc}); this is a bug in orchestrator, "
              f"please report it with the traceback saved in {fh.name}", file=sys.stderr)
        return 70


def _jsonable(value):
    if isinstance(value, dict):
        return {k: _jsonable(v) for k, v in value.items()}
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _cmd_run(args) -> int:
    from .case import load_case
    from .run import run_case

    loaded = load_case(args.case, preset=args.preset, overrides=args.overrides)
    if args.engine is not None:
        from .backends import engine_names
        from .errors import OrchestratorError

        if args.engine not in engine_names():
            raise OrchestratorError(f"unknown engine {args.engine!r}; allowed: {', '.join(engine_names())}")

    def announce(timing):
        print(f"estimate: {timing.seconds_per_step * 1e3:.3g} ms per step x {timing.planned_steps} steps planned "
              f"-> the whole run takes about {_duration(timing.estimate_s)}", file=sys.stderr, flush=True)

    summary = run_case(loaded, engine=args.engine, out_dir=args.out, timeout_s=args.timeout,
                       progress=not args.no_progress, force=args.force, on_timing=announce)
    if args.json:
        print(json.dumps(_jsonable(summary.as_dict())))
    else:
        print(f"status       {summary.status}")
        print(f"engine       {summary.engine} {summary.engine_version}")
        print(f"case         {summary.case_name}" + (f" (preset {loaded.preset})" if loaded.preset else ""))
        print(f"particles    {summary.n_particles}")
        print(f"steps        {summary.n_steps}")
        print(f"wall time    {summary.wall_time_s:.1f} s")
        for key, value in summary.measured.items():
            print(f"{key:<12} {value:.6g}" if isinstance(value, float) else f"{key:<12} {value}")
        print(f"run.h5       {summary.run_dir}/run.h5")
    return 0


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    if seconds < 3 * 86400:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 86400:.1f} days"


def _cmd_analyze(args) -> int:
    from .report import analyze_run

    analyze_run(args.run_dir, render=not args.no_render)
    return 0


def _cmd_doctor(args) -> int:
    from .doctor import check_engines

    rows = check_engines()
    if args.json:
        print(json.dumps(rows))
        return 0
    for row in rows:
        if row["found"]:
            print(f"{row['engine']:<10} ok       {row['version']:<12} {row['path']}")
        else:
            print(f"{row['engine']:<10} MISSING  {row['hint']}")
    return 0 if all(r["found"] for r in rows) else 1


def _cmd_export(args) -> int:
    from .export import export_vtk

    for path in export_vtk(args.run_dir, args.out):
        print(path)
    return 0


def _cmd_study(args) -> int:
    from .study import Study

    from .study.dask import dask_executor

    study = Study.from_file(args.study, out_dir=args.out)
    if args.dask:
        with dask_executor(args.dask, workers=args.workers) as executor:
            rows = study.run(executor=executor, force=args.force, progress=not args.no_progress)
    else:
        rows = study.run(force=args.force, progress=not args.no_progress, max_workers=args.workers)
    if args.json:
        print(json.dumps([_jsonable(row) for row in rows]))
    else:
        _print_rows(rows)
        print(f"index        {study.out_dir / 'index.csv'}")
    return 0 if all(row["status"] == "ok" for row in rows) else 1


def _cmd_status(args) -> int:
    import csv
    from pathlib import Path

    from .errors import OrchestratorError

    path = Path(args.study_dir) / "index.csv"
    if not path.is_file():
        raise OrchestratorError(f"no index.csv in {args.study_dir}; give a study directory written by 'orchestrator study'")
    with open(path, newline="") as fh:
        _print_rows(list(csv.DictReader(fh)))
    return 0


def _print_rows(rows: list[dict]) -> None:
    """A plain table: parameters, engine, status, wall time and the main measured quantities."""
    if not rows:
        print("(no runs)")
        return
    params = [k for k in rows[0] if k.startswith("param:")]
    results = [k for k in ("fn_mean", "fn_std", "ft_mean", "bed_height") if k in rows[0]]
    header = [p.removeprefix("param:") for p in params] + ["engine", "status", "wall_s"] + results + ["reused"]
    table = []
    for row in rows:
        cells = [row.get(p, "") for p in params] + [row.get("engine", ""), row.get("status", ""),
                                                     row.get("wall_time_s", "")]
        cells += [row.get(k, "") for k in results] + [row.get("reused", "")]
        table.append([f"{c:.4g}" if isinstance(c, float) else str(c) for c in cells])
    widths = [max(len(h), *(len(r[i]) for r in table)) for i, h in enumerate(header)]
    print("  ".join(h.ljust(w) for h, w in zip(header, widths)))
    for r in table:
        print("  ".join(c.ljust(w) for c, w in zip(r, widths)))


def _cmd_report(args) -> int:
    from .study.report import write_study_report

    print(write_study_report(args.study_dir, quantity=args.quantity, reference=args.reference,
                             tolerance=args.tolerance))
    return 0
