"""orchestrator analyze RUN_DIR: a run's measured quantities next to the paper's, and PNG plots."""

from __future__ import annotations

from orchestrator.report import analyze_run, write_summary


def add_parser(sub) -> None:
    analyze = sub.add_parser("analyze", help="compare a run with the paper: table and PNG plots",
                             description="Print the run's measured quantities next to the case's published "
                             "references and write PNG plots (force series with the paper's bands; the "
                             "interaction network at its snapshot time) into the run directory.")
    analyze.add_argument("run_dir", metavar="RUN_DIR", help="a directory written by 'orchestrator run'")
    analyze.add_argument("--no-render", action="store_true", help="skip the 3D network rendering (pyvista)")
    analyze.add_argument("--summary", metavar="FILE", help="also write the run's summary as JSON to FILE: what ran "
                         "and how long (s), the resolved case, the measured quantities (SI) and the printed report")
    analyze.set_defaults(func=cmd_analyze)


def cmd_analyze(args) -> int:
    if args.summary:
        print(f"summary  {write_summary(args.run_dir, args.summary, render=not args.no_render)}")
    else:
        analyze_run(args.run_dir, render=not args.no_render)
    return 0
