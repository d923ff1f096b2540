"""orchestrator study STUDY, status STUDY_DIR and report STUDY_DIR: run a sweep, tabulate it, report on it."""

from __future__ import annotations

import json

from orchestrator.cli.common import check_options, jsonable, print_table
from orchestrator.study import Study
from orchestrator.study.core import read_index_rows
from orchestrator.study.dask import dask_executor
from orchestrator.study.report import write_study_report


def add_parser(sub) -> None:
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
    study.set_defaults(func=cmd_study)

    status = sub.add_parser("status", help="table of a study's runs: parameters, engine, status, wall time, results")
    status.add_argument("study_dir", metavar="STUDY_DIR", help="directory of a study (holds index.csv)")
    status.set_defaults(func=cmd_status)

    report = sub.add_parser("report", help="HTML report of a study: table, speed against error, Pareto front",
                            description="Write STUDY_DIR/report.html (self-contained): the runs' table, wall time "
                            "against the relative error of a measured quantity with the Pareto front, the "
                            "cheapest run within the tolerance, and the pictures the study's kind draws.")
    report.add_argument("study_dir", metavar="STUDY_DIR", help="directory of a study (holds index.csv)")
    report.add_argument("--quantity", default="fn_mean", help="measured quantity (default fn_mean, N)")
    report.add_argument("--reference", default="finest",
                        help="'finest' (smallest time step), a run id prefix, or a number (closed form / paper)")
    report.add_argument("--tolerance", type=float, default=0.05, help="relative error accepted (default 0.05)")
    report.set_defaults(func=cmd_report)


def cmd_study(args) -> int:

    check_options(args)
    study = Study.from_file(args.study, out_dir=args.out)
    if args.dask:
        with dask_executor(args.dask, workers=args.workers) as executor:
            rows = study.run(executor=executor, force=args.force, progress=not args.no_progress)
    else:
        rows = study.run(force=args.force, progress=not args.no_progress, max_workers=args.workers)
    if args.json:
        print(json.dumps([jsonable(row) for row in rows]))
    else:
        print_rows(rows)
        print(f"index        {study.out_dir / 'index.csv'}")
    return 0 if all(row["status"] == "ok" for row in rows) else 1


def cmd_status(args) -> int:

    print_rows(read_index_rows(args.study_dir))
    return 0


def cmd_report(args) -> int:

    check_options(args)
    print(write_study_report(args.study_dir, quantity=args.quantity, reference=args.reference,
                             tolerance=args.tolerance))
    return 0


def print_rows(rows: list[dict]) -> None:
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
    print_table(header, table)
