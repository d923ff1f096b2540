"""orchestrator run CASE, and run --resume RUN_DIR: one case on one engine into RUN_DIR/run.h5."""

from __future__ import annotations

import json
import sys

from orchestrator.case import load_case
from orchestrator.cli.common import check_options, jsonable
from orchestrator.engines import engine_names
from orchestrator.errors import OrchestratorError
from orchestrator.humanize import duration
from orchestrator.kinds import get_kind
from orchestrator.rundir import resumable_run
from orchestrator.run import run_case


def add_parser(sub) -> None:
    run = sub.add_parser("run", help="run a case file on an engine and write RUN_DIR/run.h5",
                         description="Validate CASE, build its scene, run it on an engine and write run.h5 "
                         "(status, series, interaction networks, meshes) into the run directory.")
    run.add_argument("case", metavar="CASE", nargs="?",
                     help="TOML case file, e.g. cases/drag_finishing_uhlmann2015.toml (not with --resume)")
    run.add_argument("--resume", metavar="RUN_DIR",
                     help="continue a stopped run from its last checkpoint (drag finishing on LIGGGHTS or Yade with "
                     "output.checkpoint_interval set; sph runs stopped by --timeout or a signal, from their last "
                     "frame), with its own case, engine and MPI ranks; into the same run.h5")
    run.add_argument("--until", type=float, metavar="SECONDS",
                     help="with --resume on an sph run: run on to this simulated time, s (later than the case's "
                     "simulation.duration; a finished run continues from its last frame, and its case.toml takes the "
                     "new duration)")
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
                     help="MPI ranks of the engine (liggghts, lammps; default 1, or $ORCHESTRATOR_LIGGGHTS_MPI / "
                          "$ORCHESTRATOR_LAMMPS_MPI)")
    run.set_defaults(func=cmd_run)


def cmd_run(args) -> int:

    check_options(args)
    if args.resume is not None or args.case is None:
        return _cmd_resume(args)
    if args.until is not None:
        raise OrchestratorError("--until goes with --resume RUN_DIR (it runs a run on); a new run takes "
                                "--set simulation.duration=SECONDS")
    loaded = load_case(args.case, preset=args.preset, overrides=args.overrides)
    if args.engine is not None:

        if args.engine not in engine_names():
            raise OrchestratorError(f"unknown engine {args.engine!r}; allowed: {', '.join(engine_names())}")

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

    if args.resume is None:
        raise OrchestratorError("run needs a CASE file, or --resume RUN_DIR to continue a stopped run")
    given = [name for name, value in (("CASE", args.case), ("--engine", args.engine), ("--preset", args.preset),
                                      ("--set", args.overrides), ("--out", args.out), ("--force", args.force))
             if value]
    if given:
        raise OrchestratorError(f"--resume continues a run as it was set up: {', '.join(given)} cannot go with it "
                                "(allowed: --until, --timeout, --mpi, --json, --no-progress)")
    loaded, engine, mpi_ranks = resumable_run(args.resume, until=args.until)
    summary = run_case(loaded, engine=engine, out_dir=args.resume, timeout_s=args.timeout,
                       progress=not args.no_progress, mpi_ranks=args.mpi or mpi_ranks, resume=True)
    return _print_summary(summary, loaded, args.json)


def _print_summary(summary, loaded, as_json: bool) -> int:
    """What run prints: one JSON object, or the text summary (SI units)."""
    if as_json:
        print(json.dumps(jsonable(summary.as_dict())))
    else:
        print(f"status       {summary.status}")
        print(f"engine       {summary.engine} {summary.engine_version}")
        print(f"case         {summary.case_name}" + (f" (preset {loaded.preset})" if loaded.preset else ""))
        print(f"particles    {summary.n_particles}")
        print(f"steps        {summary.n_steps}")
        print(f"wall time    {summary.wall_time_s:.1f} s")
        if summary.peak_memory_mb is not None:
            print(f"memory       {summary.peak_memory_mb:.0f} MiB (the engine's peak resident)")
        if summary.overhead_s is not None and summary.wall_time_s > 0:
            print(f"overhead     {summary.overhead_s:.2f} s ({100 * summary.overhead_s / summary.wall_time_s:.2g} % of "
                  "the engine's wall time; per phase in run.h5)")
        for key, value in summary.measured.items():
            print(f"{key:<12} {value:.6g}" if isinstance(value, float) else f"{key:<12} {value}")
        print(f"run.h5       {summary.run_dir}/run.h5")
    return 0
