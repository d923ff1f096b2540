"""What every workflow over many runs shares (automan's Problem is the model): a Workflow names its folder
(humanize.stamped_dir: runs/<workflow>-<UTC timestamp> unless --out), checks everything before anything runs,
lists its jobs (a module-level function and its arguments, each run writing into its own folder under the
workflow's), runs them on a process pool (or one after the other) and hands the results, in the order of the jobs,
to whoever tabulates and plots them. One result per run has check rows; one table shows those rows.

A check row has ROW_KEYS (plus source and note): the scene, the engine, the measured quantity, its value, the
expected value, rel_error = |value - expected| / |expected| (unless the note names another scale), the tolerance
and whether it passed. `verify <suite>` and the time-step sweep produce them; compare, bench, calibrate
and studies use the same folders and pool.
"""

from __future__ import annotations

import math
import os
import signal
from concurrent.futures import Executor, ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from orchestrator.errors import OrchestratorError
from orchestrator import signals
from orchestrator.humanize import stamped_dir
from orchestrator.outputs import claim_folder

#: The keys of one check row (`verify <suite> --json`), in order.
ROW_KEYS = ("scene", "engine", "quantity", "value", "expected", "rel_error", "tolerance", "passed")


@dataclass
class CheckedRun:
    """One scene run on one engine: status, check rows (ROW_KEYS plus source and note) and run directory;
    wall_time_s: the engine's compute time, s; picture: what the suite's picture draws of this run (the kind's
    check says what, kinds.base.Verification)."""

    scene: str
    engine: str
    status: str
    message: str
    run_dir: Path
    rows: list[dict] = field(default_factory=list)
    wall_time_s: float = math.nan
    picture: dict = field(default_factory=dict)


@dataclass
class Workflow:
    """Many runs as one piece of work (automan's Problem).

    name: the folder's prefix (runs/<name>-<UTC timestamp> when run() gets no out_dir); jobs(folder) -> the jobs,
    [(function, args)], each function a module-level callable (it runs in a worker process) that writes into its
    own folder under `folder`; prepare(): validates everything (cases, engines) before the folder is made and
    anything runs; parallel: on a process pool (False: one after the other in this process, e.g. for timings or
    runs that show their own progress).
    """

    name: str
    jobs: Callable[[Path], list[tuple[Callable, tuple]]]
    prepare: Callable[[], None] = lambda: None
    parallel: bool = True

    def run(self, out_dir=None, workers: int | None = None, on_done=None, executor: Executor | None = None,
            initializer=None) -> tuple[Path, list]:
        """Prepare, make the folder, run every job; returns (folder, results in the order of the jobs).

        workers: parallel runs (default: the number of cores); on_done(result, done, total) as each ends;
        executor: run on it (e.g. a Dask cluster's) instead of an own process pool; initializer: of the own pool's
        workers (signals.install_in_worker: a signal stops the running task's engine and keeps its run.h5).
        """
        self.prepare()
        folder = workflow_dir(out_dir, self.name)
        jobs = self.jobs(folder)
        if self.parallel:
            return folder, run_in_pool(_call, jobs, workers, on_done, executor, initializer)
        results = []
        for done, (function, args) in enumerate(jobs, 1):
            results.append(function(*args))
            if on_done is not None:
                on_done(results[-1], done, len(jobs))
        return folder, results


def _call(function, args):
    """function(*args) (what a pool worker runs for one job: a signal stops it as signals.task describes)."""
    with signals.task():
        return function(*args)


def workflow_dir(out_dir, name: str, root: Path = Path("runs")) -> Path:
    """The workflow's folder, created and marked as ours (outputs.claim_folder: a non-empty folder of the user's is
    refused): out_dir, or root/<name>-<UTC timestamp> when out_dir is None."""
    return claim_folder(Path(out_dir) if out_dir is not None else stamped_dir(name, root), "--out", name)


def run_in_pool(function, jobs: list[tuple], workers: int | None = None, on_done=None,
                executor: Executor | None = None, initializer=None) -> list:
    """function(*job) for every job on a process pool of `workers` (default: the number of cores) or on the
    given executor; on_done(result, done, total) as each ends; the results in the order of jobs.

    A signal (KeyboardInterrupt, signals.Interrupted) while the own pool runs is passed on to its workers (with
    initializer=signals.install_in_worker each stops its engine and writes its run.h5) and raised again."""
    if workers is not None and workers < 1:
        raise OrchestratorError(f"--workers {workers}: allowed: 1 or more")
    own = executor is None
    if own:
        workers = workers or max(1, min(len(jobs), os.cpu_count() or 1))
        # processes, not threads: each run writes and reads its run.h5, and HDF5 is safest one file per process
        executor = ProcessPoolExecutor(max_workers=max(1, min(workers, len(jobs))),
                                       initializer=initializer or signals.install_in_worker)
    try:
        futures = [executor.submit(function, *job) for job in jobs]
        if on_done is not None:
            for done, future in enumerate(as_completed(futures), 1):
                on_done(future.result(), done, len(futures))
        return [future.result() for future in futures]
    except KeyboardInterrupt as exc:
        if own:
            stop_workers(executor, getattr(exc, "signum", signal.SIGINT))
        raise
    finally:
        if own:
            executor.shutdown(cancel_futures=True)


def stop_workers(executor: ProcessPoolExecutor, signum: int) -> None:
    """Pass the signal on to the pool's workers: each stops its engine and writes its run.h5 (status terminated)."""
    for process in list(getattr(executor, "_processes", {}).values()):  # no public API lists a pool's processes
        try:
            os.kill(process.pid, signum)
        except (ProcessLookupError, TypeError):
            continue


def rows_of(runs: list[CheckedRun]) -> list[dict]:
    """Every check row of the runs, as dicts with ROW_KEYS (plus source and note)."""
    return [row for run in runs for row in run.rows]


def json_rows(runs: list[CheckedRun]) -> list[dict]:
    """Rows with exactly ROW_KEYS; NaN becomes None."""
    def clean(value):
        return None if isinstance(value, float) and not math.isfinite(value) else value

    return [{key: clean(row[key]) for key in ROW_KEYS} for row in rows_of(runs)]


def format_table(runs: list[CheckedRun], unit_of) -> str:
    """The plain-text table: scene, engine, quantity [unit_of(quantity)], value, expected, rel_error, tolerance,
    passed; the rows' notes below."""
    header = ("scene", "engine", "quantity", "value", "expected", "rel_error", "tolerance", "passed")
    lines, notes = [], []
    table = []
    for row in rows_of(runs):
        unit = unit_of(row["quantity"])
        cells = [row["scene"], row["engine"], f"{row['quantity']} [{unit}]", _num(row["value"]),
                 _num(row["expected"]), _num(row["rel_error"], ".2e"), _num(row["tolerance"], ".2g"),
                 "yes" if row["passed"] else "NO"]
        if row["note"]:
            notes.append(f"{row['scene']} / {row['engine']}: {row['note']}")
        table.append(cells)
    widths = [max(len(h), *(len(r[i]) for r in table)) if table else len(h) for i, h in enumerate(header)]
    lines.append("  ".join(h.ljust(w) for h, w in zip(header, widths)))
    for cells in table:
        lines.append("  ".join(c.ljust(w) for c, w in zip(cells, widths)))
    for note in dict.fromkeys(notes):
        lines.append(f"note: {note}")
    return "\n".join(lines)


def _num(value, fmt: str = ".6g") -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "-"
    return format(value, fmt)
