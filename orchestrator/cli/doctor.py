"""orchestrator doctor: which engines are installed, their versions and paths (exit code 1 if one is missing)."""

from __future__ import annotations

import json

from orchestrator.doctor import check_engines


def add_parser(sub) -> None:
    doctor = sub.add_parser("doctor", help="which engines are installed, their versions and paths")
    doctor.add_argument("--json", action="store_true", help="print a JSON list")
    doctor.set_defaults(func=cmd_doctor)


def cmd_doctor(args) -> int:

    rows = check_engines()
    if args.json:
        print(json.dumps(rows))
        return 0
    for row in rows:
        if row["found"]:
            print(f"{row['engine']:<10} ok       {row['version']:<12} {row['path']}"
                  + (f" ({row['features']})" if row["features"] else ""))
        else:
            print(f"{row['engine']:<10} MISSING  {row['hint']}")
    return 0 if all(r["found"] for r in rows) else 1
