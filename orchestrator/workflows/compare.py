"""`orchestrator compare CASE --engines a,b[,c]`: one case on several engines,
side by side.

The engines run one after the other, each into OUT/<engine>/ through
run.run_case (so each gets its own run.h5). An engine that is not installed,
or that does not run this kind of case, is skipped with the reason; an
engine that fails keeps its row (status, message, whatever it measured) and
the others still run. Per measured quantity (RunSummary.measured, from the
case's kind, Kind.measure) the table shows every engine's value and their spread
(max - min, and relative to the mean's magnitude); per engine the engine's
wall time, particle-steps per second and the orchestrator's own overhead by
phase (run.OVERHEAD_PHASES). What else a comparison shows is the case's
kind's (kinds.base.Kind): the units of its quantities (quantities), what the
case predicts for them (expected: closed forms), a table of its published
values beside each engine's (references), and OUT/compare_forces.png, the
engines' series overlaid (compare_picture).
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

from orchestrator.engines import engine_names, get_engine
from orchestrator.errors import EngineNotFound, OrchestratorError, ReadError
from orchestrator.kinds import engines_for_kind, get_kind, kinds_for_engine
from orchestrator.run import OVERHEAD_PHASES, run_case
from orchestrator.runh5 import RUN_FILE, read_run
from orchestrator.workflows.base import Workflow

#: Status of an engine that did not run (not installed, or not for this kind of case).
SKIPPED = "skipped"
PLOT_FILE = "compare_forces.png"


@dataclass
class EngineRun:
    """One engine's part of a comparison: its status and, when it ran, its RunSummary."""

    engine: str
    status: str
    message: str = ""
    summary: object = None  # run.RunSummary, or None when the engine did not run

    @property
    def measured(self) -> dict:
        """The run's measured quantities (SI), empty when it did not run."""
        return self.summary.measured if self.summary is not None else {}

    def row(self) -> dict:
        """Engine, version, status, wall time (s), particles, steps, particle-steps per s, overhead (s, % of the
        engine's wall time, and per phase in s), message, run directory; NaN where the engine did not run."""

        s = self.summary
        wall = float(s.wall_time_s) if s is not None else math.nan
        overhead = float(s.overhead_s) if s is not None and s.overhead_s is not None else math.nan
        steps = s.n_particles * s.n_steps if s is not None else math.nan
        phases = s.overhead_phases_s if s is not None else {}
        return {
            "engine": self.engine, "version": s.engine_version if s is not None else "", "status": self.status,
            "wall_time_s": wall, "n_particles": s.n_particles if s is not None else None,
            "n_steps": s.n_steps if s is not None else None,
            "particle_steps_per_s": steps / wall if wall > 0 else math.nan,
            "overhead_s": overhead, "overhead_pct": 100.0 * overhead / wall if wall > 0 else math.nan,
            **{f"overhead_{name}_s": float(phases.get(name, math.nan)) for name in OVERHEAD_PHASES},
            "message": self.message, "run_dir": s.run_dir if s is not None else None,
        }


@dataclass
class Comparison:
    """A case run on several engines (see the module docstring); times in s."""

    case: object  # the validated case model
    preset: str | None
    out_dir: Path
    runs: list[EngineRun] = field(default_factory=list)
    plot: Path | None = None
    wall_time_s: float = math.nan  # the whole comparison, from loading the case to the plot

    @property
    def kind(self) -> str:
        """case.kind."""
        return self.case.case.kind

    def unit_of(self, quantity: str) -> str:
        """SI unit of one of the kind's measured quantities ('' when the kind does not say)."""
        return get_kind(self.kind).unit_of(quantity)

    def quantity_rows(self) -> list[dict]:
        """Per measured quantity, in the order of the kind's table of quantities: unit, each engine's value (None if
        it has none), spread = max - min and rel_spread = spread / |mean| over the engines that have it, and the
        expected value where the case predicts one (the kind's expected)."""

        kind = get_kind(self.kind)
        expected = kind.expected(self.case) if kind.expected is not None else {}
        names = list(dict.fromkeys(key for run in self.runs for key in run.measured))
        order = list(kind.quantities.load()) if kind.quantities is not None else []
        names.sort(key=lambda n: order.index(n) if n in order else len(order))
        rows = []
        for name in names:
            values = {run.engine: _number(run.measured.get(name)) for run in self.runs}
            finite = [v for v in values.values() if math.isfinite(v)]
            spread = max(finite) - min(finite) if len(finite) > 1 else math.nan
            mean = sum(finite) / len(finite) if finite else math.nan
            rows.append({"quantity": name, "unit": kind.unit_of(name), "values": values, "spread": spread,
                         "rel_spread": abs(spread / mean) if math.isfinite(spread) and mean != 0 else math.nan,
                         "expected": expected.get(name, math.nan)})
        return rows

    def reference_table(self):
        """The kind's table of the case's published values beside each engine's that ran (Kind.references):
        (title, header, cells, rows), or None when the kind has none."""
        references = get_kind(self.kind).references
        if references is None:
            return None
        return references(self.case, [(run.engine, run.measured) for run in self.runs if run.summary is not None])

    def reference_rows(self) -> list[dict]:
        """The rows of reference_table as JSON objects ([] when the kind has none)."""
        table = self.reference_table()
        return table[3] if table is not None else []

    def as_dict(self) -> dict:
        """One JSON-ready document (NaN stays float; the CLI turns it into null)."""
        return {"case": self.case.case.name, "kind": self.kind, "preset": self.preset or "",
                "out_dir": str(self.out_dir), "plot": str(self.plot) if self.plot else None,
                "wall_time_s": self.wall_time_s, "engines": [run.row() for run in self.runs],
                "quantities": self.quantity_rows(), "references": self.reference_rows()}


def parse_engines(text: str) -> list[str]:
    """Engine names from 'yade,liggghts,reference' (each registered; duplicates dropped, order kept).

    Raises OrchestratorError naming an unknown engine and the allowed ones.
    """
    names = list(dict.fromkeys(name.strip() for name in text.split(",") if name.strip()))
    if not names:
        raise OrchestratorError(f"--engines: give engine names separated by commas, e.g. yade,reference; "
                                f"allowed: {', '.join(engine_names())}")
    for name in names:
        if name not in engine_names():
            raise OrchestratorError(f"--engines: unknown engine {name!r}; allowed: {', '.join(engine_names())}")
    return names


def why_not(engine: str, loaded) -> str:
    """Why engine cannot run this case here ('' when it can): not installed (with the install hint), or the
    case's kind is not one it runs."""
    profile = get_engine(engine)
    if engine not in engines_for_kind(loaded.kind):
        return f"{engine} does not run {loaded.kind} cases (it runs: {', '.join(kinds_for_engine(engine))})"
    try:
        profile.check_available()
    except EngineNotFound as exc:
        hint = profile.install_hint()
        return str(exc) if hint in str(exc) else f"{exc}; {hint}"
    return ""


def compare_engines(loaded, engines: list[str], out_dir=None, timeout_s: float | None = None,
                    progress: bool = True, force: bool = False, log=None) -> Comparison:
    """Run loaded (a LoadedCase) on each engine in turn into out_dir/<engine>/ and return the Comparison.

    timeout_s: wall-time limit of each engine's run, s. log(text) gets one line per engine as it starts and ends
    (default: stderr). Raises OrchestratorError before anything runs when an engine's directory already holds a
    run and force is not set.
    """

    started = time.perf_counter()
    log = log or (lambda text: print(text, file=sys.stderr, flush=True))

    def prepare():
        folder = Path(out_dir) if out_dir is not None else None
        held = [name for name in engines if folder is not None and (folder / name / RUN_FILE).exists()]
        if held and not force:
            raise OrchestratorError(f"{folder} already holds runs of {', '.join(held)}; choose another --out, or "
                                    "pass --force to overwrite them")

    def jobs(folder: Path):
        return [(_run_engine, (loaded, engine, k, len(engines), folder, timeout_s, progress, force, log))
                for k, engine in enumerate(engines, 1)]

    folder, runs = Workflow(f"compare-{loaded.name}", jobs, prepare, parallel=False).run(out_dir)
    comparison = Comparison(loaded.model, loaded.preset, folder, runs=runs)
    comparison.plot = plot_forces(comparison)
    comparison.wall_time_s = time.perf_counter() - started
    return comparison


def _run_engine(loaded, engine: str, k: int, total: int, folder: Path, timeout_s, progress: bool, force: bool,
                log) -> EngineRun:
    """One engine's run of the comparison into folder/<engine> (skipped, with the reason, when it cannot run)."""
    reason = why_not(engine, loaded)
    if reason:
        log(f"compare: {engine} skipped: {reason}")
        return EngineRun(engine, SKIPPED, reason)
    log(f"compare: {k}/{total} running {loaded.name} on {engine} into {folder / engine}")
    try:
        summary = run_case(loaded, engine=engine, out_dir=folder / engine, timeout_s=timeout_s,
                           progress=progress, force=force)
        run = EngineRun(engine, summary.status, summary.message, summary)
    except OrchestratorError as exc:  # a failed engine keeps its row; the others still run
        summary = exc.summary
        run = EngineRun(engine, summary.status if summary is not None else SKIPPED,
                        str(exc).split("\n")[0], summary)
    log(f"compare: {engine} {run.status}" + (f" in {run.summary.wall_time_s:.3g} s" if run.summary else "")
        + (f": {run.message}" if run.message and run.status != "ok" else ""))
    return run


def plot_forces(comparison: Comparison) -> Path | None:
    """Write out_dir/compare_forces.png, the engines' series overlaid as the kind draws them (Kind.compare_picture:
    e.g. forces in N against time in s). Returns the path, or None when the kind draws none or no engine left a
    run.h5."""

    picture = get_kind(comparison.kind).compare_picture
    if picture is None:
        return None
    runs = []
    for run in comparison.runs:
        if run.summary is None:
            continue
        try:
            data = read_run(run.summary.run_dir)
        except ReadError:
            continue
        label = f"{run.engine} {run.summary.engine_version}" + ("" if run.status == "ok" else f" ({run.status})")
        runs.append((label, data))
    return picture(runs, comparison.case, comparison.out_dir / PLOT_FILE) if runs else None


def text_tables(comparison: Comparison) -> list[tuple[str, list[str], list[list[str]]]]:
    """The comparison as (title, header, rows of cells) tables for a plain-text printer."""
    engines = [run.engine for run in comparison.runs if run.summary is not None]
    tables = []
    quantities = comparison.quantity_rows()
    if quantities:
        with_expected = any(math.isfinite(row["expected"]) for row in quantities)
        header = ["quantity [unit]", *engines, "spread", "rel_spread"] + (["expected"] if with_expected else [])
        cells = [[f"{row['quantity']} [{row['unit'] or '?'}]", *(_cell(row["values"][e]) for e in engines),
                  _cell(row["spread"], ".3g"), _percent(row["rel_spread"])]
                 + ([_cell(row["expected"])] if with_expected else []) for row in quantities]
        tables.append(("measured quantities (SI units; spread = max - min, rel_spread = spread / |mean|)",
                       header, cells))
    references = comparison.reference_table()
    if references is not None:
        tables.append(references[:3])
    rows = [run.row() for run in comparison.runs]
    header = ["engine", "version", "status", "engine wall [s]", "particles", "steps", "particle-steps/s",
              "overhead [s]", "overhead [% of engine]"]
    cells = [[r["engine"], r["version"] or "-", r["status"], _cell(r["wall_time_s"], ".4g"),
              _cell(r["n_particles"]), _cell(r["n_steps"]), _cell(r["particle_steps_per_s"], ".3g"),
              _cell(r["overhead_s"], ".3g"), _percent(r["overhead_pct"] / 100.0, digits=3)] for r in rows]
    tables.append(("engines: wall time and speed; the orchestrator's own time around each run", header, cells))

    ran = [r for r in rows if math.isfinite(r["overhead_s"])]
    if ran:
        header = ["engine", *(f"{name} [s]" for name in OVERHEAD_PHASES), "total [s]"]
        cells = [[r["engine"], *(_cell(r[f"overhead_{name}_s"], ".3f") for name in OVERHEAD_PHASES),
                  _cell(r["overhead_s"], ".3f")] for r in ran]
        tables.append(("orchestrator overhead by phase (setup: imports, backend, engine version; input: run "
                       "directory and engine input; write: run.h5)", header, cells))
    return tables


def notes(comparison: Comparison) -> list[str]:
    """One line per engine that was skipped or did not end ok."""
    return [f"{run.engine}: {run.status}: {run.message}" for run in comparison.runs if run.status != "ok"]


def _number(value) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        return math.nan


def _cell(value, fmt: str = ".6g") -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "-"
    if isinstance(value, int):
        return str(value)
    return format(value, fmt)


def _percent(fraction: float, signed: bool = False, digits: int = 2) -> str:
    if not math.isfinite(fraction):
        return "-"
    return f"{100.0 * fraction:{'+' if signed else ''}.{digits}g} %"
