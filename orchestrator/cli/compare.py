"""orchestrator compare CASE --engines A,B: one case on several engines, their results side by side."""

from __future__ import annotations

import json

from orchestrator.case import load_case
from orchestrator.cli.common import check_options, jsonable, print_table
from orchestrator.humanize import duration
from orchestrator.workflows.compare import compare_engines, notes, parse_engines, text_tables


def add_parser(sub) -> None:
    compare = sub.add_parser(
        "compare", help="run one case on several engines and print their results, spread, speed and overhead",
        description="Run CASE on each engine of --engines in turn (each into OUT/<engine>/run.h5) and print, per "
        "measured quantity, every engine's value and their spread (max - min, and relative to the mean); per engine "
        "the wall time, particle-steps per second (particles x steps / engine wall time) and the orchestrator's own "
        "time (by phase, and as a % of the engine's). The case's kind adds what it declares: the values its case "
        "predicts (closed forms) in an expected column, a table of its published values beside each engine's (e.g. "
        "the force on the rod, N, against the paper's bands), and OUT/compare_forces.png overlaying the engines' "
        "series. An engine that is not installed is skipped with how to install it; exit code 1 unless every "
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
                         "(values per engine, spread, rel_spread), references (the kind's published values beside each "
                         "engine's; [] when it has none), plot")
    compare.add_argument("--no-progress", action="store_true", help="no progress bar on stderr")
    compare.set_defaults(func=cmd_compare)


def cmd_compare(args) -> int:

    check_options(args)
    engines = parse_engines(args.engines)
    loaded = load_case(args.case, preset=args.preset, overrides=args.overrides)
    comparison = compare_engines(loaded, engines, out_dir=args.out, timeout_s=args.timeout,
                                 progress=not args.no_progress, force=args.force)
    if args.json:
        print(json.dumps(jsonable(comparison.as_dict())))
    else:
        print(f"case         {loaded.name}" + (f" (preset {loaded.preset})" if loaded.preset else ""))
        for title, header, table in text_tables(comparison):
            print(f"\n{title}")
            print_table(header, table)
        print()
        for line in notes(comparison):
            print(f"note: {line}")
        print(f"compare took {duration(comparison.wall_time_s)} in all")
        if comparison.plot:
            print(f"picture      {comparison.plot}")
        print(f"runs         {comparison.out_dir}")
    return 0 if all(run.status == "ok" for run in comparison.runs) else 1
