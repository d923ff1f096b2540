"""The `orchestrator` command line. Heavy modules are imported inside the
commands, so `orchestrator --help` stays fast."""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

from orchestrator import __version__
from orchestrator.humanize import duration


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="orchestrator",
        description="Run particle simulations of machining and finishing processes on established engines "
        "(Yade and LIGGGHTS for DEM, our sph executable for SPH) and compare them with the papers and reference "
        "solvers. All quantities are SI (m, kg, s, N, Pa).",
    )
    parser.add_argument("--version", action="version", version=f"orchestrator {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    run = sub.add_parser("run", help="run a case file on an engine and write RUN_DIR/run.h5",
                         description="Validate CASE, build its scene, run it on an engine and write run.h5 "
                         "(status, series, interaction networks, meshes) into the run directory.")
    run.add_argument("case", metavar="CASE", nargs="?",
                     help="TOML case file, e.g. cases/drag_finishing_uhlmann2015.toml (not with --resume)")
    run.add_argument("--resume", metavar="RUN_DIR",
                     help="continue a stopped run from its last checkpoint (LIGGGHTS drag finishing with "
                     "output.checkpoint_interval set), with its own case, engine and MPI ranks; into the same run.h5")
    run.add_argument("--engine", help="engine name (default: the case's case.engine); see 'orchestrator doctor'")
    run.add_argument("--preset", help="named override set from the case's [presets.NAME] (e.g. quick, full)")
    run.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                     help="override any case value, SI units, e.g. --set media.count=200 (repeatable)")
    run.add_argument("--out", metavar="DIR", help="run directory: new, empty or an earlier run's (default: a new one "
                     "under runs/); locked while the run lasts")
    run.add_argument("--timeout", type=float, metavar="SECONDS",
                     help="stop the engine after this wall time, s; run.h5 keeps what was measured")
    run.add_argument("--force", action="store_true",
                     help="replace a run already in --out (its old outputs are removed before the engine starts; "
                     "a folder that is not a run directory is never written into)")
    run.add_argument("--json", action="store_true", help="print one JSON object instead of the text summary")
    run.add_argument("--no-progress", action="store_true", help="no progress bar on stderr")
    run.add_argument("--mpi", type=int, metavar="N",
                     help="run the engine under 'mpirun -np N' (liggghts; default 1, or $ORCHESTRATOR_LIGGGHTS_MPI)")

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

    verify = sub.add_parser(
        "verify", help="verification suite: every scene on every installed engine against closed forms",
        description="Run every verification scene (cases/verification/*.toml: Chung & Ooi 2011 tests 1-4 and the "
        "sphere drop of Uhlmann et al. 2015) on every installed DEM engine and on the reference DEM, compare each "
        "measured quantity with its closed form, print one table (scene, engine, quantity [SI unit], value, "
        "expected, rel_error = |value - expected| / |expected|, tolerance, passed) and save verify_dem.png (normal "
        "force in N against time in ms, engines overlaid per scene). Exit code 1 if any check fails. "
        "verify sph: the SPH scenes (cases/verification/sph_*.toml: Poiseuille and Couette start-up against the "
        "series of Morris et al. 1997, a hydrostatic tank, the 2D dam break against Koshizuka & Oka 1996 and "
        "Martin & Moyce 1952, penalty walls against eq. 14) on the sph executable, the same table and JSON rows, "
        "and verify_sph.png (profiles, pressure, surge front, wall forces).")
    verify.add_argument("suite", choices=["dem", "sph"],
                        help="which suite: dem (discrete element impacts) or sph (SPH flows on the sph executable)")
    verify.add_argument("--engine", dest="engines", action="append", metavar="NAME",
                        help="run on this engine only (repeatable; default: every installed DEM engine and the "
                        "reference)")
    verify.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                        help="override a value of every scene, SI units, e.g. --set numerics.timestep_factor=0.1")
    verify.add_argument("--cases", metavar="DIR", help="directory of scenes (default: the shipped cases/verification)")
    verify.add_argument("--out", metavar="DIR", help="run directories and the PNG (default: runs/verify-<suite>-<time>)")
    verify.add_argument("--workers", type=int, metavar="N", help="parallel runs (default: the number of cores)")
    verify.add_argument("--json", action="store_true",
                        help="print the rows as a JSON list of objects with the keys scene, engine, quantity, value, "
                        "expected, rel_error, tolerance, passed (SI units; null where not measured)")
    verify.add_argument("--timestep-factors", type=float, nargs="+", metavar="F",
                        help="speed against error instead: run the suite at each numerics.timestep_factor F (fraction "
                        "of the critical step, e.g. 0.01 0.05 0.2 1) and print, per engine and F, the worst relative "
                        "error, the checks passed and the engine compute time in s; saves timestep_sweep.png")

    calibrate = sub.add_parser(
        "calibrate", help="fit a model parameter to measured or simulated data (restitution from a sphere drop)",
        description="calibrate restitution: fit the normal coefficient of restitution e_n (-) to the first three "
        "impacts of a sphere drop, as Uhlmann et al. 2015 did: from the peak-force ratios F2/F1, F3/F1 and the times "
        "since the first impact t2-t1, t3-t1 (s), with the drop case's damped Hertz closed forms as the model.")
    calibrate.add_argument("parameter", choices=["restitution"], help="what to fit: restitution (e_n, -)")
    source = calibrate.add_mutually_exclusive_group(required=True)
    source.add_argument("--csv", metavar="FILE", help="force-sensor trace: a header line, then rows time_s,force_N")
    source.add_argument("--run", metavar="RUN_DIR", help="a simulated drop (its run.h5 contact events and case)")
    calibrate.add_argument("--case", metavar="CASE",
                           help="the drop's case file for --csv (sphere, plate, drop height; default: "
                           "cases/verification/uhlmann2015_sphere_drop.toml, the paper's 10 mm drop)")
    calibrate.add_argument("--json", action="store_true",
                           help="print one JSON object: restitution, residuals, observed and model peaks (N) and "
                           "peak times (s)")

    compare = sub.add_parser(
        "compare", help="run one case on several engines and print their results, spread, speed and overhead",
        description="Run CASE on each engine of --engines in turn (each into OUT/<engine>/run.h5) and print, per "
        "measured quantity, every engine's value and their spread (max - min, and relative to the mean); per engine "
        "the wall time, particle-steps per second (particles x steps / engine wall time) and the orchestrator's own "
        "time (by phase, and as a % of the engine's). Drag-finishing cases add F_n and F_t (mean, std, N) next to "
        "the paper's numbers; impact cases their closed forms. Writes OUT/compare_forces.png overlaying the engines' "
        "force series. An engine that is not installed is skipped with how to install it; exit code 1 unless every "
        "engine ran ok.")
    compare.add_argument("case", metavar="CASE", help="TOML case file, e.g. cases/verification/"
                         "chung_ooi_test2_sphere_plane.toml or cases/drag_finishing_uhlmann2015.toml")
    compare.add_argument("--engines", required=True, metavar="A,B[,C]",
                         help="engines separated by commas, e.g. yade,liggghts,reference (see 'orchestrator doctor')")
    compare.add_argument("--preset", help="named override set from the case's [presets.NAME] (e.g. quick)")
    compare.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                         help="override any case value, SI units (repeatable)")
    compare.add_argument("--out", metavar="DIR", help="directory of the runs and the PNG "
                         "(default: runs/compare-<case>-<time>)")
    compare.add_argument("--timeout", type=float, metavar="SECONDS", help="wall-time limit of each engine's run, s")
    compare.add_argument("--force", action="store_true", help="overwrite runs already in --out")
    compare.add_argument("--json", action="store_true",
                         help="print one JSON object: case, engines (times, speed, overhead by phase), quantities "
                         "(values per engine, spread, rel_spread), forces (drag finishing, with the references), plot")
    compare.add_argument("--no-progress", action="store_true", help="no progress bar on stderr")

    bench = sub.add_parser(
        "bench", help="speed of an engine: particle-steps per second on standard scenes",
        description="bench sph: time the sph executable on a 2D dam break (PySPH's dam_break_2d: dx = 0.03 m, "
        "h = 1.3 dx, 2278 fluid particles) and a 3D dam break (25 360 particles), each on 1 thread and on 2 threads "
        "(idle threads spinning briefly, numerics.thread_wait = spin, and sleeping at once, passive), and, "
        "when PySPH is importable ('make pysph'), the same 2D dam break in PySPH on one core. Prints particle-steps "
        "per second (over the loop's wall time and per CPU second), mean neighbours per fluid particle, the "
        "2-thread speed-ups and the ratio to PySPH. Run it on an otherwise idle machine: spinning threads on "
        "shared cores run many times slower.")
    bench.add_argument("suite", choices=["sph"], help="which engine: sph")
    bench.add_argument("--steps-2d", type=int, default=2000, metavar="N", help="steps of the 2D runs (default 2000)")
    bench.add_argument("--steps-3d", type=int, default=200, metavar="N", help="steps of the 3D runs (default 200)")
    bench.add_argument("--repeat", type=int, default=3, metavar="N",
                       help="make every run N times, round after round, and keep the fastest of each (default 3)")
    bench.add_argument("--no-pysph", action="store_true", help="skip PySPH even when it is installed")
    bench.add_argument("--out", metavar="DIR", help="run directories (default: runs/bench-sph-<time>)")
    bench.add_argument("--json", action="store_true",
                       help="print one JSON object: rows (scene, engine, threads, particles, fluid, steps, neighbours, "
                       "wall_s, cpu_s, particle_steps_per_s, per_core, status, note, wait, repeats) and summary (speed-ups, "
                       "ratios)")

    doctor = sub.add_parser("doctor", help="which engines are installed, their versions and paths")
    doctor.add_argument("--json", action="store_true", help="print a JSON list")

    export = sub.add_parser("export", help="write VTK files of a run (particles, meshes, networks) for ParaView")
    export.add_argument("run_dir", metavar="RUN_DIR", help="a directory written by 'orchestrator run'")
    export.add_argument("--out", metavar="DIR", help="where to write (default: RUN_DIR/vtk)")
    return parser


def main(argv=None) -> int:
    """Entry point of the console script; returns the exit code.

    SIGINT, SIGTERM and SIGHUP stop a running engine, keep what was measured in run.h5 (status terminated) and
    exit with 128 + the signal's number.
    """
    from orchestrator import signals

    with signals.installed():
        try:
            code = _main(argv)
            signals.check()  # a signal that a library swallowed still ends the command
            return code
        except KeyboardInterrupt as exc:
            return _interrupted(exc)


def _main(argv) -> int:
    from orchestrator.errors import OrchestratorError

    parser = _parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    try:
        commands = {"run": _cmd_run, "analyze": _cmd_analyze, "doctor": _cmd_doctor, "export": _cmd_export,
                    "study": _cmd_study, "status": _cmd_status, "report": _cmd_report, "verify": _cmd_verify,
                    "calibrate": _cmd_calibrate, "compare": _cmd_compare, "bench": _cmd_bench}
        return commands[args.command](args)
    except OrchestratorError as exc:
        if getattr(args, "json", False) and exc.summary is not None:
            print(json.dumps(_jsonable(exc.summary.as_dict())))
        print(f"error: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt as exc:
        if getattr(args, "json", False) and getattr(exc, "summary", None) is not None:
            print(json.dumps(_jsonable(exc.summary.as_dict())))
        raise
    except Exception as exc:  # a bug of ours: keep the traceback in a file, show one line
        import tempfile
        import traceback

        with tempfile.NamedTemporaryFile("w", prefix="orchestrator-crash-", suffix=".log", delete=False) as fh:
            traceback.print_exc(file=fh)
        print(f"error: internal error ({type(exc).__name__}: {exc}); this is a bug in orchestrator, "
              f"please report it with the traceback saved in {fh.name}", file=sys.stderr)
        return 70


def _interrupted(exc: KeyboardInterrupt) -> int:
    """Say what a signal stopped and what is on disk; the exit code is 128 + the signal's number."""
    from orchestrator.signals import Interrupted

    how = exc.describe() if isinstance(exc, Interrupted) else "Ctrl-C (SIGINT)"
    kept = getattr(exc, "kept", None)
    if kept is not None:
        print(f"error: stopped by {how}; the engine was stopped and {kept}", file=sys.stderr)
    else:
        print(f"error: stopped by {how}; no run.h5 was written by this command", file=sys.stderr)
    return exc.exit_code if isinstance(exc, Interrupted) else 130


def _jsonable(value):
    if isinstance(value, dict):
        return {k: _jsonable(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_jsonable(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _check_options(args) -> None:
    """Refuse option values no command can use: a wall-time limit or tolerance that is not a finite positive
    number, fewer than one worker or MPI rank, an --out that cannot be a folder (OrchestratorError, exit 2)."""
    from orchestrator.errors import OrchestratorError
    from orchestrator.humanize import check_out_dir

    for option in ("timeout", "tolerance"):
        value = getattr(args, option, None)
        if value is not None and not (math.isfinite(value) and value > 0):
            unit = " s" if option == "timeout" else ""
            raise OrchestratorError(f"--{option} {value:g}: allowed: a finite number above 0{unit}"
                                    + (" (leave --timeout out for no limit)" if option == "timeout" else ""))
    for option in ("workers", "mpi"):
        value = getattr(args, option, None)
        if value is not None and value < 1:
            raise OrchestratorError(f"--{option} {value}: allowed: 1 or more")
    if getattr(args, "out", None) is not None:
        check_out_dir(args.out)


def _cmd_run(args) -> int:
    from orchestrator.case import load_case
    from orchestrator.run import run_case

    _check_options(args)
    if args.resume is not None or args.case is None:
        return _cmd_resume(args)
    loaded = load_case(args.case, preset=args.preset, overrides=args.overrides)
    if args.engine is not None:
        from orchestrator.engines import engine_names
        from orchestrator.errors import OrchestratorError

        if args.engine not in engine_names():
            raise OrchestratorError(f"unknown engine {args.engine!r}; allowed: {', '.join(engine_names())}")
        from orchestrator.kinds import get_kind

        kind = get_kind(loaded.kind)
        # A kind with a refusal for the engine explains it itself (e.g. the reference DEM: why, and what to use).
        if args.engine not in kind.adapters and args.engine not in kind.refusals:
            raise OrchestratorError(f"--engine {args.engine} does not run {loaded.kind} cases; allowed: "
                                    f"{', '.join(kind.engines())}")

    def announce(timing):
        print(f"estimate: {timing.seconds_per_step * 1e3:.3g} ms per step x {timing.planned_steps} steps planned "
              f"-> the whole run takes about {duration(timing.estimate_s)}", file=sys.stderr, flush=True)

    summary = run_case(loaded, engine=args.engine, out_dir=args.out, timeout_s=args.timeout,
                       progress=not args.no_progress, force=args.force, on_timing=announce, mpi_ranks=args.mpi)
    return _print_summary(summary, loaded, args.json)


def _cmd_resume(args) -> int:
    """run --resume RUN_DIR: the stopped run's own case, engine and ranks, from its last checkpoint."""
    from orchestrator.errors import OrchestratorError
    from orchestrator.run import resumable_run, run_case

    if args.resume is None:
        raise OrchestratorError("run needs a CASE file, or --resume RUN_DIR to continue a stopped run")
    given = [name for name, value in (("CASE", args.case), ("--engine", args.engine), ("--preset", args.preset),
                                      ("--set", args.overrides), ("--out", args.out), ("--force", args.force))
             if value]
    if given:
        raise OrchestratorError(f"--resume continues a run as it was set up: {', '.join(given)} cannot go with it "
                                "(allowed: --timeout, --mpi, --json, --no-progress)")
    loaded, engine, mpi_ranks = resumable_run(args.resume)
    summary = run_case(loaded, engine=engine, out_dir=args.resume, timeout_s=args.timeout,
                       progress=not args.no_progress, mpi_ranks=args.mpi or mpi_ranks, resume=True)
    return _print_summary(summary, loaded, args.json)


def _print_summary(summary, loaded, as_json: bool) -> int:
    """What run prints: one JSON object, or the text summary (SI units)."""
    if as_json:
        print(json.dumps(_jsonable(summary.as_dict())))
    else:
        print(f"status       {summary.status}")
        print(f"engine       {summary.engine} {summary.engine_version}")
        print(f"case         {summary.case_name}" + (f" (preset {loaded.preset})" if loaded.preset else ""))
        print(f"particles    {summary.n_particles}")
        print(f"steps        {summary.n_steps}")
        print(f"wall time    {summary.wall_time_s:.1f} s")
        if summary.overhead_s is not None and summary.wall_time_s > 0:
            print(f"overhead     {summary.overhead_s:.2f} s ({100 * summary.overhead_s / summary.wall_time_s:.2g} % of "
                  "the engine's wall time; per phase in run.h5)")
        for key, value in summary.measured.items():
            print(f"{key:<12} {value:.6g}" if isinstance(value, float) else f"{key:<12} {value}")
        print(f"run.h5       {summary.run_dir}/run.h5")
    return 0


def _cmd_analyze(args) -> int:
    from orchestrator.report import analyze_run

    analyze_run(args.run_dir, render=not args.no_render)
    return 0


def _cmd_doctor(args) -> int:
    from orchestrator.doctor import check_engines

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
    from orchestrator.export import export_vtk

    _check_options(args)
    for path in export_vtk(args.run_dir, args.out):
        print(path)
    return 0


def _cmd_study(args) -> int:
    from orchestrator.study import Study
    from orchestrator.study.dask import dask_executor

    _check_options(args)
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
    from orchestrator.study.core import read_index_rows

    _print_rows(read_index_rows(args.study_dir))
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
    _print_table(header, table)


def _print_table(header: list[str], table: list[list[str]]) -> None:
    """Columns of strings, left-aligned, two spaces apart, under a header line."""
    widths = [max(len(h), *(len(r[i]) for r in table)) for i, h in enumerate(header)]
    print("  ".join(h.ljust(w) for h, w in zip(header, widths)))
    for r in table:
        print("  ".join(c.ljust(w) for c, w in zip(r, widths)))


def _cmd_report(args) -> int:
    from orchestrator.study.report import write_study_report

    _check_options(args)
    print(write_study_report(args.study_dir, quantity=args.quantity, reference=args.reference,
                             tolerance=args.tolerance))
    return 0


def _cmd_verify(args) -> int:
    from orchestrator.workflows.verify import (
        default_out_dir,
        format_table,
        json_rows,
        plot_force_curves,
        run_verification,
    )

    _check_options(args)
    if args.suite == "sph":
        return _verify_sph(args)
    out_dir = args.out or default_out_dir()
    if args.timestep_factors:
        return _verify_sweep(args, Path(out_dir))
    def done(run, count, total):
        print(f"verify: {count}/{total} {run.scene} on {run.engine}: {run.status}", file=sys.stderr, flush=True)

    runs = run_verification(engines=args.engines, out_dir=out_dir, cases_dir=args.cases, overrides=args.overrides,
                            workers=args.workers, on_done=done)
    png = plot_force_curves(runs, Path(out_dir) / "verify_dem.png")
    rows = json_rows(runs)
    failed = sum(not row["passed"] for row in rows)
    if args.json:
        print(json.dumps(rows))
    else:
        print(format_table(runs))
        engines = ", ".join(dict.fromkeys(run.engine for run in runs))
        print(f"{len(rows) - failed} of {len(rows)} checks passed ({len(runs)} runs on {engines})")
        print(f"curves       {png}")
        print(f"runs         {out_dir}")
    return 1 if failed else 0


def _verify_sph(args) -> int:
    from orchestrator.errors import OrchestratorError
    from orchestrator.workflows.verify import format_table, json_rows
    from orchestrator.workflows.verify_sph import default_out_dir, plot_scenes, run_verification, unit_of

    if args.timestep_factors:
        raise OrchestratorError("--timestep-factors is for 'verify dem' only")
    if args.engines and set(args.engines) != {"sph"}:
        raise OrchestratorError(f"verify sph runs on the sph engine only, not {', '.join(args.engines)}")
    out_dir = Path(args.out) if args.out else default_out_dir()

    def done(run, count, total):
        print(f"verify: {count}/{total} {run.scene} on {run.engine}: {run.status}", file=sys.stderr, flush=True)

    runs = run_verification(out_dir=out_dir, cases_dir=args.cases, overrides=args.overrides, workers=args.workers,
                            on_done=done)
    png = plot_scenes(runs, out_dir / "verify_sph.png")
    rows = json_rows(runs)
    failed = sum(not row["passed"] for row in rows)
    if args.json:
        print(json.dumps(rows))
    else:
        print(format_table(runs, unit_of=unit_of))
        print(f"{len(rows) - failed} of {len(rows)} checks passed ({len(runs)} scenes on sph)")
        print(f"plots        {png}")
        print(f"runs         {out_dir}")
    return 1 if failed else 0


def _verify_sweep(args, out_dir: Path) -> int:
    from dataclasses import asdict

    from orchestrator.errors import OrchestratorError
    from orchestrator.workflows.timestep_study import format_sweep, plot_sweep, run_timestep_sweep

    if any(not 0 < f <= 1 for f in args.timestep_factors):
        raise OrchestratorError("--timestep-factors: every factor must be in (0, 1] (a fraction of the critical step)")
    points, _ = run_timestep_sweep(args.timestep_factors, engines=args.engines, out_dir=out_dir,
                                   cases_dir=args.cases, workers=args.workers)
    png = plot_sweep(points, out_dir / "timestep_sweep.png")
    if args.json:
        print(json.dumps([_jsonable(asdict(p)) for p in points]))
    else:
        print(format_sweep(points))
        print(f"plot         {png}")
        print(f"runs         {out_dir}")
    return 0


def _cmd_compare(args) -> int:
    from orchestrator.case import load_case
    from orchestrator.workflows.compare import compare_engines, notes, parse_engines, text_tables

    _check_options(args)
    engines = parse_engines(args.engines)
    loaded = load_case(args.case, preset=args.preset, overrides=args.overrides)
    comparison = compare_engines(loaded, engines, out_dir=args.out, timeout_s=args.timeout,
                                 progress=not args.no_progress, force=args.force)
    if args.json:
        print(json.dumps(_jsonable(comparison.as_dict())))
    else:
        print(f"case         {loaded.name}" + (f" (preset {loaded.preset})" if loaded.preset else ""))
        for title, header, table in text_tables(comparison):
            print(f"\n{title}")
            _print_table(header, table)
        print()
        for line in notes(comparison):
            print(f"note: {line}")
        print(f"compare took {duration(comparison.wall_time_s)} in all")
        if comparison.plot:
            print(f"forces       {comparison.plot}")
        print(f"runs         {comparison.out_dir}")
    return 0 if all(run.status == "ok" for run in comparison.runs) else 1


def _cmd_calibrate(args) -> int:
    from dataclasses import asdict

    from orchestrator.case import load_case
    from orchestrator.workflows.calibrate import (
        drop_case_path,
        fit_restitution,
        format_fit,
        observations_from_csv,
        observations_from_run,
    )

    if args.run:
        observed, case = observations_from_run(args.run)
        if args.case:
            case = load_case(args.case).model
        source = f"run {args.run}"
    else:
        observed = observations_from_csv(args.csv)
        case = load_case(args.case or drop_case_path()).model
        source = f"CSV {args.csv}"
    fit = fit_restitution(case, observed, source)
    if args.json:
        print(json.dumps(_jsonable(asdict(fit))))
    else:
        print(format_fit(fit))
    if fit.failure:
        print(f"error: the fit failed: {fit.failure}", file=sys.stderr)
        return 1
    return 0


def _cmd_bench(args) -> int:
    from orchestrator.errors import OrchestratorError
    from orchestrator.workflows.bench_sph import format_report, json_report, run_bench

    for option, value, most in (("--steps-2d", args.steps_2d, 10**9), ("--steps-3d", args.steps_3d, 10**9),
                                ("--repeat", args.repeat, 1000)):
        if not 1 <= value <= most:
            raise OrchestratorError(f"{option} {value}: allowed: 1 to {most}")
    _check_options(args)

    def done(row):
        wait = f" ({row.wait})" if row.wait != "-" else ""
        print(f"bench: {row.scene} on {row.engine}, {row.threads} thread(s){wait}: {row.status}", file=sys.stderr,
              flush=True)

    rows = run_bench(args.out, steps_2d=args.steps_2d, steps_3d=args.steps_3d,
                     with_pysph=False if args.no_pysph else None, on_done=done, repeats=args.repeat)
    if args.json:
        print(json.dumps(json_report(rows)))
    else:
        print(format_report(rows))
    return 0 if all(row.status == "ok" for row in rows) else 1
