"""`orchestrator analyze RUN_DIR`: the run's kind prints its comparison with the case's references and draws its
pictures (kinds.<kind>: Kind.analyze)."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

from orchestrator.errors import OrchestratorError, ReadError
from orchestrator.kinds import get_kind
from orchestrator.measure import remeasure
from orchestrator.humanize import os_problem
from orchestrator.outputs import RUN_FILE, check_target, write_text
from orchestrator.runh5 import read_run, stored_case


def analyze_run(run_dir, render: bool = True) -> dict:
    """Print the run's comparison table and write its PNG pictures into run_dir; returns {name: path}.

    render=False leaves out the pyvista renderings (networks, meshes).
    """
    run_dir = Path(run_dir)
    run = read_run(run_dir)
    case = stored_case(run, run_dir)
    attrs = run["attrs"]
    missing = [key for key in ("status", "engine", "engine_version", "n_particles", "n_steps", "wall_time_s")
               if key not in attrs]
    if missing:
        raise ReadError(f"{run_dir}: run.h5 lacks the attribute {missing[0]!r}; it was not written by "
                        "'orchestrator run' (or is damaged)")
    if not run.get("measured", {}).get("attrs"):  # its measuring failed, or the kind measured nothing then
        run["measured"] = {"attrs": remeasure(run)}
    return get_kind(case.case.kind).analyze(run_dir, run, case, render)


#: Root attributes of run.h5 a summary keeps (what ran, how long, what it settled to).
SUMMARY_ATTRS = ("case_name", "case_kind", "case_hash", "preset", "engine", "engine_version", "status", "message",
                 "command", "n_particles", "n_steps", "dt", "simulated_time", "process_start_time", "bed_height",
                 "settled", "wall_time_s", "engine_wall_time_s", "started", "finished")


def write_summary(run_dir, path, render: bool = True) -> Path:
    """analyze_run() with what it prints also written to path as JSON: the run's identity and timing
    (SUMMARY_ATTRS), its resolved case (TOML text), its measured quantities (SI) and the printed report (lines):
    a few kB that stand for a run whose raw data stay out of the repository. Returns path; OrchestratorError,
    before anything is analysed, when path cannot be written."""
    run_files = [Path(run_dir) / name for name in (RUN_FILE, "case.toml")]
    # checked first: a summary that cannot be written (a FIFO, a folder, the run's own files) costs no analysis
    path = check_target(path, "--summary", inputs=run_files)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OrchestratorError(f"--summary {path}: cannot create its folder: {os_problem(exc)}") from None
    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer):
        analyze_run(run_dir, render)
    text = buffer.getvalue()
    print(text, end="")
    run = read_run(run_dir)
    plain = lambda v: v.item() if hasattr(v, "item") else v.tolist() if hasattr(v, "tolist") else v  # noqa: E731
    summary = {"run": {k: plain(run["attrs"][k]) for k in SUMMARY_ATTRS if k in run["attrs"]},
               "measured": {k: plain(v) for k, v in run.get("measured", {}).get("attrs", {}).items()},
               "case": str(run.get("case", {}).get("attrs", {}).get("toml", "")),
               "report": text.splitlines()}
    return write_text(path, json.dumps(summary, indent=1, allow_nan=True) + "\n", "--summary", inputs=run_files)
