"""`orchestrator report STUDY_DIR`: a self-contained HTML page (images embedded as data URIs) with the study's
table, wall time against error with the Pareto front marked, and the sections the study's kind draws
(Kind.study_pictures)."""

from __future__ import annotations

import base64
import itertools
import json
import math
import os
from pathlib import Path

from orchestrator import __version__
from orchestrator.case.common import MAX_MAGNITUDE
from orchestrator.errors import OrchestratorError
from orchestrator.kinds import get_kind
from orchestrator.plots import figure_png, number_or_nan, parameter_label, place_point_labels, plain_log_ticks
from orchestrator.study.core import INDEX_NAME, STUDY_INFO, read_index_rows
from orchestrator.templating import render

#: Resolution of the report's own figure, dots per inch (it is laid out and saved at the same one).
DPI = 110


def pareto_front(costs: list[float], errors: list[float]) -> list[bool]:
    """True for points no other point beats in both cost and error (ties count as not beaten); one sweep in
    order of cost, so a study of many runs costs n log n."""
    order = sorted(range(len(costs)), key=lambda i: (costs[i], errors[i]))
    flags = [False] * len(costs)
    cheaper_best = math.inf  # the least error of the points strictly cheaper than the current group
    for _, same_cost in itertools.groupby(order, key=lambda i: costs[i]):
        group = list(same_cost)
        group_best = errors[group[0]]  # sorted by error within a cost
        for i in group:
            flags[i] = not (cheaper_best <= errors[i] or group_best < errors[i])
        cheaper_best = min(cheaper_best, group_best)
    return flags


def relative_errors(values: list[float], reference: float) -> list[float]:
    """|v - ref| / |ref| for each value (nan where a value is missing)."""
    return [abs(v - reference) / abs(reference) if math.isfinite(v) else math.nan for v in values]


def speed_error_figure(walls: list[float], errors: list[float], front: list[bool], labels: list[str],
                       short_labels: list[str], quantity: str, tolerance: float):
    """A matplotlib Figure of wall time (s) against relative error (-), both on log axes, with the Pareto front
    (front: one flag per point) and the tolerance line; points are labelled, those on the front first (labels,
    or short_labels where those do not fit). Points with error 0 (the reference run) cannot sit on a log axis:
    each is marked by a dotted vertical line at its wall time, named in the legend, and the Pareto line runs
    level from the last point above 0 to that line instead of dropping."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7, 4.8), dpi=DPI, layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    shown = sorted((i for i, e in enumerate(errors) if e > 0 and walls[i] > 0), key=lambda i: not front[i])
    exact = [i for i, e in enumerate(errors) if e == 0 and walls[i] > 0]
    for on_front, color, layer in ((False, "tab:gray", 3), (True, "tab:green", 4)):  # the front on top
        ax.scatter([walls[i] for i in shown if front[i] == on_front],
                   [errors[i] for i in shown if front[i] == on_front], color=color, zorder=layer)
    steps = sorted((walls[i], errors[i]) for i in shown if front[i])
    ends = [walls[i] for i in exact if front[i] and steps and walls[i] > steps[-1][0]]
    if ends:  # the front runs on level to the zero-error run's wall time, where its dotted line takes over
        steps.append((min(ends), steps[-1][1]))
    if steps:
        ax.step([w for w, _ in steps], [e for _, e in steps], where="post", color="tab:green", label="Pareto front")
    for k, i in enumerate(exact):
        ax.axvline(walls[i], color="tab:blue", ls=":", lw=1.2,
                   label=f"{', '.join(short_labels[j] for j in exact)}: error 0, drawn at its wall time"
                   if k == 0 else None)
    ax.axhline(tolerance, color="tab:red", ls="--", label=f"tolerance {tolerance:g}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    if not shown:
        ax.set_ylim(tolerance / 10, max(1.0, 10 * tolerance))
    ax.margins(x=0.15, y=0.15)  # room for the labels beside the outermost points
    plain_log_ticks(ax.xaxis)
    plain_log_ticks(ax.yaxis)
    ax.set_xlabel("wall time [s]")
    ax.set_ylabel(f"relative error of {quantity} [-]")
    fig.legend(loc="outside lower center", ncols=3, fontsize=8, frameon=False)
    place_point_labels(ax, [walls[i] for i in shown], [errors[i] for i in shown], [labels[i] for i in shown],
                       [short_labels[i] for i in shown])
    return fig


def write_study_report(study_dir, quantity: str = "fn_mean", reference: str = "finest", tolerance: float = 0.05,
                       path=None) -> Path:
    """Write STUDY_DIR/report.html (or path); returns its path.

    quantity: a measured column of index.csv (e.g. fn_mean, N). reference:
    'finest' (the ok run with the smallest time step, then the longest wall
    time), a run_id prefix, or a number (a closed form or a paper's value).
    The recommendation is the cheapest run whose error is within `tolerance`.
    """
    study_dir = Path(study_dir)
    out = Path(path) if path is not None else study_dir / "report.html"
    rows = [{**r, "run_dir": str(_run_dir(study_dir, r))} for r in read_index_rows(study_dir)]
    number = {id(r): n for n, r in enumerate(rows, 1)}
    ok = [r for r in rows if r.get("status") == "ok" and math.isfinite(number_or_nan(r.get(quantity)))
          and number_or_nan(r.get("wall_time_s")) > 0]
    if not ok:
        raise OrchestratorError(f"{study_dir}: no finished run has the quantity {quantity!r}")
    ref_row, ref_value, reference_label = _reference(ok, quantity, reference)
    walls = [number_or_nan(r["wall_time_s"]) for r in ok]
    errors = relative_errors([number_or_nan(r[quantity]) for r in ok], ref_value)
    front = pareto_front(walls, errors)
    varied = [k for k in rows[0] if k.startswith("param:") and len({r.get(k) for r in rows}) > 1]
    figure = speed_error_figure(walls, errors, front, [parameter_label(r, varied) for r in ok],
                                [f"#{number[id(r)]}" for r in ok], quantity, tolerance)
    info = _study_info(study_dir)
    pictures, pictures_note = _kind_pictures(info.get("kind") or _kind_of_runs(ok), rows, quantity, ref_row,
                                             tolerance)
    html = render("report/study.html.j2", {
        "name": info.get("name") or study_dir.name, "runs": rows, "quantity": quantity,
        "reference_label": reference_label, "version": __version__,
        "index_path": _relative(study_dir / INDEX_NAME, out.parent),
        "recommendation": _recommendation(ok, walls, errors, ref_row, varied, quantity, tolerance, number),
        "pareto_png": base64.b64encode(figure_png(figure)).decode(), "header": ["#"] + _table_header(rows, quantity),
        "table": _table(rows, ok, errors, front, quantity), "description": info.get("description", ""),
        "exact_note": _exact_note(ok, errors, number), "pictures": pictures, "pictures_note": pictures_note,
    })
    out.write_text(html)
    return out


def _reference(ok: list[dict], quantity: str, reference: str) -> tuple[dict | None, float, str]:
    """(reference row or None for a number, reference value, how the page names it); OrchestratorError when
    the reference is unknown, not finite or zero."""
    ref_row = None
    try:
        ref_value, label = float(reference), f"the value {reference}"
    except ValueError:
        if reference == "finest":
            ref_row = min(ok, key=lambda r: (number_or_nan(r.get("dt")), -number_or_nan(r.get("wall_time_s"))))
        else:
            matches = [r for r in ok if r["run_id"].startswith(reference)]
            if not matches:
                raise OrchestratorError(f"no finished run's id starts with {reference!r}; use 'finest', an id or a "
                                        "number") from None
            ref_row = matches[0]
        ref_value = number_or_nan(ref_row[quantity])
        label = f"run {ref_row['run_id'][:12]} ({quantity} = {ref_value:.4g})"
    if not (math.isfinite(ref_value) and 1.0 / MAX_MAGNITUDE <= abs(ref_value) <= MAX_MAGNITUDE):
        raise OrchestratorError(f"--reference {reference}: the reference {quantity} is {ref_value:g}; relative errors "
                                f"need a reference of magnitude {1.0 / MAX_MAGNITUDE:g} to {MAX_MAGNITUDE:g} "
                                "('finest', a run id or a number such as 1.8)")
    return ref_row, ref_value, label


def _recommendation(ok, walls, errors, ref_row, varied, quantity, tolerance, number) -> str:
    """The cheapest run other than the reference within tolerance, as a sentence."""
    candidates = [(w, e, r) for w, e, r in zip(walls, errors, ok) if e <= tolerance and r is not ref_row]
    if not candidates:
        return f"no run other than the reference is within {100 * tolerance:g} % of it"
    wall, err, best = min(candidates, key=lambda item: item[0])
    text = (f"#{number[id(best)]}, {parameter_label(best, varied or None, short=False)} on {best['engine']}: "
            f"{quantity} within {100 * tolerance:g} % of the reference ({100 * err:.1f} %) in {wall:.1f} s")
    if ref_row is not None:
        speed_up = number_or_nan(ref_row["wall_time_s"]) / wall
        text += (f", {speed_up:.0f} x faster than the reference run" if speed_up >= 1.5 else
                 f" (the reference run took {number_or_nan(ref_row['wall_time_s']):.1f} s)")
    return text


def _exact_note(ok: list[dict], errors: list[float], number: dict) -> str:
    """Which runs have error 0 (drawn as dotted lines, not points, on the log axis)."""
    exact = [f"#{number[id(r)]}" for r, e in zip(ok, errors) if e == 0]
    if not exact:
        return ""
    return (f"Error 0 ({', '.join(exact)}): a log axis has no 0, so the dotted line marks that run's wall time "
            "instead of a point.")


def _table_header(rows: list[dict], quantity: str) -> list[str]:
    params = [k for k in rows[0] if k.startswith("param:")]
    return [p.removeprefix("param:") for p in params] + ["engine", "status", "wall time [s]", quantity,
                                                        "rel. error", "run"]


def _table(rows: list[dict], ok: list[dict], errors: list[float], front: list[bool], quantity: str) -> list[dict]:
    """The table's rows: {"cells": [text, ...], "pareto": bool}; cells start with the run's number."""
    params = [k for k in rows[0] if k.startswith("param:")]
    by_id = {id(r): (e, f) for r, e, f in zip(ok, errors, front)}
    table = []
    for n, r in enumerate(rows, 1):
        err, on_front = by_id.get(id(r), (math.nan, False))
        cells = [f"#{n}"] + [r.get(p, "") for p in params] + [
            r.get("engine", ""), r.get("status", ""), f"{number_or_nan(r.get('wall_time_s')):.1f}",
            f"{number_or_nan(r.get(quantity)):.4g}", "" if math.isnan(err) else f"{err:.3g}", r["run_id"][:12]]
        table.append({"cells": cells, "pareto": on_front})
    return table


def _kind_pictures(kind: str, rows, quantity, ref_row, tolerance) -> tuple[list[dict], str]:
    """The study kind's report sections with their PNGs as base64 text, and a note when there are none."""
    if not kind:
        return [], ""
    try:
        sections = get_kind(kind).draw_study_pictures(rows, quantity, ref_row, tolerance)
    except OrchestratorError as exc:
        return [], f"No pictures of the {kind} kind: {str(exc).splitlines()[0]}"
    return [{"title": s["title"], "note": s.get("note", ""), "png": base64.b64encode(s.get("png", b"")).decode()}
            for s in sections], ""


def _study_info(study_dir: Path) -> dict:
    """study.json of the study directory (name, description, kind, ...); {} when missing or unreadable."""
    try:
        info = json.loads((study_dir / STUDY_INFO).read_text())
    except (OSError, ValueError):
        return {}
    return info if isinstance(info, dict) else {}


def _kind_of_runs(rows: list[dict]) -> str:
    """The case kind the first readable run.h5 of rows records ('' when none does); for study directories whose
    study.json does not name it."""
    import h5py

    for row in rows:
        try:
            with h5py.File(Path(row["run_dir"]) / "run.h5", "r") as h5:
                kind = h5.attrs["case_kind"]
            return kind.decode() if isinstance(kind, bytes) else str(kind)
        except (OSError, KeyError):
            continue
    return ""


def _run_dir(study_dir: Path, row: dict) -> Path:
    """A run's directory: as the index gives it, or, when that is gone (a moved study or a relative path), the
    folder of the same name in the study directory."""
    given = Path(row.get("run_dir") or ".")
    return given if (given / "run.h5").is_file() else study_dir / given.name


def _relative(path: Path, start: Path) -> str:
    """path relative to start (the page names no absolute path of the machine that wrote it)."""
    try:
        return Path(os.path.relpath(path.resolve(), start.resolve())).as_posix()
    except ValueError:  # another drive
        return path.name
