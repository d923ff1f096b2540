"""`orchestrator network-sensitivity CASE`: which of the 1D network's reconstructed dimensions and loss coefficients
the feed pressure hangs on (kinds/ejector_drill/sensitivity.py), against the paper's expected 10-20 bar. Prints the
one-at-a-time table (p_feed in bar gauge and V_loss in l/min per factor), the factors that reach the band's edges
and the feed flows that do; writes the tables (CSV, JSON) and two pictures into --out."""

from __future__ import annotations

import csv
import io
import json
import math
from dataclasses import asdict
from pathlib import Path

import numpy as np

from orchestrator.case import load_case
from orchestrator.cli.common import check_options, jsonable, print_table
from orchestrator.errors import OrchestratorError
from orchestrator.humanize import stamped_dir
from orchestrator.kinds.base import Command
from orchestrator.kinds.ejector_drill import sensitivity as study
from orchestrator.kinds.ejector_drill import sensitivity_plot as plots
from orchestrator.kinds.ejector_drill.comparison import PAPER_BAR
from orchestrator.outputs import claim_folder, write_text

#: The map's nozzle-area factors (on the case's area) and gaps d_Diff (m).
MAP_AREA_FACTORS = (0.5, 4.0)
MAP_GAPS = (0.5e-3, 2.5e-3)


def parse_factors(text: str) -> list[float]:
    """The factors of --factors, '0.5,0.75,1.5,2': finite numbers above 0 other than 1, sorted (OrchestratorError
    otherwise)."""
    try:
        values = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise OrchestratorError(f"--factors {text!r}: allowed: numbers above 0 separated by commas, e.g. "
                                "0.5,0.75,1.5,2") from None
    bad = [v for v in values if not (math.isfinite(v) and 0.0 < v < 1e3) or v == 1.0]
    if not values or bad:
        raise OrchestratorError(f"--factors {text!r}: allowed: numbers above 0 and below 1000 other than 1 (the "
                                "case's value), separated by commas, e.g. 0.5,0.75,1.5,2")
    return sorted(set(values))


def parse_names(text: str | None) -> list[str]:
    """The parameters of --parameters (comma-separated names), all when text is None."""
    if text is None:
        return list(study.BY_NAME)
    names = [n.strip() for n in text.split(",") if n.strip()]
    unknown = [n for n in names if n not in study.BY_NAME]
    if not names or unknown:
        raise OrchestratorError(f"--parameters {text!r}{': unknown ' + ', '.join(unknown) if unknown else ''}; "
                                f"allowed: names separated by commas from {', '.join(study.BY_NAME)}")
    return list(dict.fromkeys(names))


def network_of(case_file: Path, overrides=()):
    """(DrillNetwork of the case's [drill] table, the case's network_flow in l/min) of a drill case file."""
    model = load_case(case_file, overrides=overrides).model
    if not hasattr(model, "network"):
        raise OrchestratorError(f"{case_file}: case.kind = {model.case.kind!r}; network-sensitivity reads the "
                                "[drill] table of an ejector_drill or ejector_feed case")
    return model.network(), float(model.scene.network_flow)


def _cell(p: study.Point, field: str, spec: str) -> str:
    value = getattr(p, field)
    if not math.isfinite(value):
        return "-"
    return format(value, spec) if not p.note else f"({format(value, spec)})"


def oat_table(points, edges, base_values: dict, factors, field: str = "p_feed_bar") -> tuple[list, list]:
    """(header, rows) of the one-at-a-time table: per parameter its label and unit, case value, field at each
    factor (in parentheses: the geometry cannot be built), and (p_feed only) the factors that reach each band edge."""
    spec = ".1f" if field == "p_feed_bar" else "+.1f"
    header = ["parameter", "unit", "case"] + [f"x{f:g}" for f in factors]
    if field == "p_feed_bar":
        header += [f"x for {t:g} bar" for t in PAPER_BAR]
    rows = []
    for name in dict.fromkeys(p.parameter for p in points):
        par = study.BY_NAME[name]
        row = [par.label, par.unit, f"{base_values[name] * par.scale:.4g}"]
        row += [_cell(p, field, spec) for f in factors for p in points if p.parameter == name and p.factor == f]
        if field == "p_feed_bar":
            row += [f"{e.factor:.3g}" if math.isfinite(e.factor) else "-" for e in edges if e.parameter == name]
        rows.append(row)
    return header, rows


def points_csv(points) -> str:
    """CSV of the scan's points: parameter, factor (-), value (the parameter's display unit), unit, p_feed_bar,
    p_C1_bar, p_mixing_bar (bar gauge), V_EN_lpm, V_loss_lpm (l/min), cavitating, buildable, note."""
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(["parameter", "factor", "value", "unit", "p_feed_bar", "p_C1_bar", "p_mixing_bar", "V_EN_lpm",
                "V_loss_lpm", "cavitating", "buildable", "note"])
    for p in points:
        par = study.BY_NAME[p.parameter]
        w.writerow([p.parameter, f"{p.factor:g}", f"{p.value * par.scale:.6g}", par.unit, *(
            f"{v:.6g}" for v in (p.p_feed_bar, p.p_C1_bar, p.p_mixing_bar, p.V_EN, p.V_loss)),
            int(p.cavitating), int(p.buildable), p.note])
    return out.getvalue()


def map_csv(m: study.AreaGapMap) -> str:
    """CSV of the map: d_diff_mm, nozzle_area_mm2, p_feed_bar (bar gauge), V_loss_lpm (l/min), cavitating,
    buildable, in_band (10-20 bar with V_loss < 0)."""
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(["d_diff_mm", "nozzle_area_mm2", "p_feed_bar", "V_loss_lpm", "cavitating", "buildable", "in_band"])
    band = study.in_band(m)
    for i, gap in enumerate(m.gaps):
        for j, area in enumerate(m.areas):
            w.writerow([f"{gap * 1e3:.6g}", f"{area * 1e6:.6g}", f"{m.p_feed_bar[i, j]:.6g}", f"{m.V_loss[i, j]:.6g}",
                        int(m.cavitating[i, j]), int(m.buildable[i, j]), int(band[i, j])])
    return out.getvalue()


def summary_lines(base, edges, flows: dict) -> list[str]:
    """The reading: the case's point, the single changes that reach the band with the ejector drawing (V_loss < 0)
    and those that reach it leaking, and the feed flows at the band's edges with the case's values."""
    case = (f"case: p_feed {base.p_feed_bar:.2f} bar, V_EN {base.V_EN:.2f} l/min, V_loss {base.V_loss:+.2f} l/min, "
            f"p_mixing {base.p_mixing_bar:.2f} bar{' (cavitating)' if base.cavitating else ''}")
    lines = [case]
    for name in dict.fromkeys(e.parameter for e in edges):
        mine = [e for e in edges if e.parameter == name and math.isfinite(e.factor)]
        if not mine:
            continue
        par = study.BY_NAME[name]
        unit = "" if par.unit == "-" else f" {par.unit}"
        parts = [f"{e.target_bar:g} bar at x{e.factor:.3g} ({e.value * par.scale:.3g}{unit}, V_EN {e.V_EN:.1f},"
                 f" V_loss {e.V_loss:+.1f} l/min{', cavitating' if e.cavitating else ''})" for e in mine]
        lines.append(f"{par.label}: " + "; ".join(parts))
    lines.append("feed flow with the case's values: " + "; ".join(
        f"{t:g} bar at {q:.1f} l/min" for t, q in flows.items() if math.isfinite(q)))
    return lines


def add_arguments(p) -> None:
    """The options of `orchestrator network-sensitivity`."""
    p.add_argument("case", type=Path, help="an ejector_drill or ejector_feed case file; its [drill] table is the "
                   "network's base point (e.g. cases/ejector_drill_canini.toml)")
    p.add_argument("--flow", type=float, metavar="L/MIN", help="feed flow V_total, l/min (default: the case's "
                   "scene.network_flow, the paper's standard 60)")
    p.add_argument("--factors", default="0.5,0.75,1.5,2", metavar="F1,F2,...", help="factors on each parameter's "
                   "case value, -, comma-separated (default 0.5,0.75,1.5,2)")
    p.add_argument("--parameters", metavar="NAME,...", help="the parameters to scan (default: all): "
                   + ", ".join(study.BY_NAME))
    p.add_argument("--map-points", type=int, default=41, metavar="N", help="points along each axis of the map over "
                   "the nozzles' total area (x0.5-4) and the gap d_Diff (0.5-2.5 mm) (default 41; 0: no map)")
    p.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                   help="override a case value, SI units, e.g. --set drill.d_diff=1.2e-3")
    p.add_argument("--out", metavar="DIR", help="folder of the CSV, JSON and PNG files (default: "
                   "runs/network-sensitivity-<time>)")
    p.add_argument("--json", action="store_true", help="print the study as JSON (flows l/min, pressures bar gauge, "
                   "values SI; null where the network did not solve)")


def run(args) -> int:
    """Scan, print the tables (or JSON), write network_sensitivity.{csv,json,png} and network_map.{csv,png}."""
    check_options(args)
    factors, names = parse_factors(args.factors), parse_names(args.parameters)
    if not 0 <= args.map_points <= 201 or args.map_points == 1:
        raise OrchestratorError(f"--map-points {args.map_points}: allowed: 0 (no map) or 2-201")
    net, case_flow = network_of(args.case, args.overrides)
    flow = case_flow if args.flow is None else args.flow
    if not (math.isfinite(flow) and 0.0 < flow <= 1000.0):
        raise OrchestratorError(f"--flow {flow:g}: allowed: a feed flow above 0 and up to 1000 l/min")
    base = study.solve_point(net, flow)
    if not math.isfinite(base.p_feed_bar):
        raise OrchestratorError(f"the case's network does not solve at {flow:g} l/min: {base.note}")
    folder = claim_folder(args.out or stamped_dir("network-sensitivity"), command="network-sensitivity")
    base_values = {name: study.parameter_value(net, name) for name in names}
    points = study.one_at_a_time(net, flow, factors, names)
    edges = study.band_edges(net, flow, names)
    flows = {t: study.flow_for(net, t) for t in PAPER_BAR}
    write_text(folder / "network_sensitivity.csv", points_csv(points))
    plots.plot_tornado(points, base, base_values, flow, folder / "network_sensitivity.png")
    result = {"flow_lpm": flow, "band_bar": list(PAPER_BAR), "base": asdict(base), "base_values": base_values,
              "points": [asdict(p) for p in points], "band_edges": [asdict(e) for e in edges],
              "flows_for_band_lpm": {f"{t:g}": q for t, q in flows.items()}}
    if args.map_points:
        n = args.map_points
        m = study.area_gap_map(net, flow, np.geomspace(*MAP_AREA_FACTORS, n), np.linspace(*MAP_GAPS, n))
        write_text(folder / "network_map.csv", map_csv(m))
        plots.plot_area_gap_map(m, round(net.n_ejector_nozzles), folder / "network_map.png")
        result["map"] = {"csv": "network_map.csv", "points_in_band": int(study.in_band(m).sum())}
    write_text(folder / "network_sensitivity.json", json.dumps(jsonable(result), indent=1) + "\n")
    if args.json:
        print(json.dumps(jsonable(result)))
        return 0
    print(f"p_feed [bar gauge] at {flow:g} l/min, one parameter times a factor; (..): cannot be built")
    print_table(*oat_table(points, edges, base_values, factors))
    print("\nV_loss [l/min] (< 0: the ejector draws from the bore mouth)")
    print_table(*oat_table(points, edges, base_values, factors, "V_loss"))
    print()
    print("\n".join(summary_lines(base, edges, flows)))
    print(f"files        {folder}")
    return 0


COMMAND = Command(
    help="the ejector drill's 1D network: feed pressure (bar) against its reconstructed dimensions and losses",
    description="Solve the ejector drill's 1D hydraulic network (Canini et al.; reference/drill_network.py) with the "
    "case's [drill] table at one feed flow (l/min), then with each reconstructed dimension or loss coefficient "
    "times each factor (the nozzle count and diameter, the nozzle's Cd, the gap d_Diff, the tubes, the head's "
    "holes and passages, the clearances, the viscosity), the rest kept. Prints the feed's gauge pressure p_feed "
    "(bar) and the leak V_loss (l/min; < 0: the ejector draws) per factor, the factors that put p_feed at the "
    "paper's 10 and 20 bar, and the feed flows that do; writes network_sensitivity.csv/.json, a tornado chart "
    "network_sensitivity.png, and a map of p_feed over the nozzles' total area (mm^2) and d_Diff (mm) with the "
    "10-20 bar band where the ejector draws, network_map.png/.csv.",
    add_arguments=add_arguments, run=run)
