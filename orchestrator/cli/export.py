"""orchestrator export RUN_DIR: VTK files of a run for ParaView."""

from __future__ import annotations

from orchestrator.cli.common import check_options
from orchestrator.export import export_vtk


def add_parser(sub) -> None:
    export = sub.add_parser("export", help="write VTK files of a run (particles, meshes, networks) for ParaView")
    export.add_argument("run_dir", metavar="RUN_DIR", help="a directory written by 'orchestrator run'")
    export.add_argument("--out", metavar="DIR", help="where to write (default: RUN_DIR/vtk)")
    export.set_defaults(func=cmd_export)


def cmd_export(args) -> int:

    check_options(args)
    for path in export_vtk(args.run_dir, args.out):
        print(path)
    return 0
