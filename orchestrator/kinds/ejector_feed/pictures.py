"""The pictures of an ejector-feed run (drill/drawing.py draws them): its flows and probe pressures against time
(series.png), the SPH beside the network (comparison.png) and, with render, sections through the frames at the
case's picture times with the tubes cut (section_<t>ms.png)."""

from __future__ import annotations

import math
from pathlib import Path

from orchestrator.drill.drawing import draw_sections, plot_comparison, plot_drill_series
from orchestrator.kinds.ejector_feed.layout import feed_layout
from orchestrator.kinds.ejector_feed.walls import feed_wall_meshes

#: The comparison's columns (report.feed_rows).
COLUMNS = ("SPH", "network")
#: The flows drawn in series.png and the two panels' titles.
FLOWS = ("V_total", "V_AG", "V_EN", "V_IB", "V_mixed")
TITLES = ("volume flows (eq. 1: V_total = V_AG + V_EN; the tube: V_IB + V_EN = V_mixed)",
          "sensor pressures (Fig. 5: B in the gap, C1 before and C2 behind the nozzles)")


def draw_run_pictures(run_dir: Path, case, time, flows: dict, series: dict, rows: list, frames: dict,
                      render: bool) -> dict:
    """series.png, comparison.png (the rows in l/min and bar that the SPH has) and (render) the sections in run_dir;
    {name: path}. time s, flows m^3/s, series: the run's, rows: report.feed_rows'."""
    bars = [(n, u, a, b, note) for n, u, a, b, note in rows if u in ("l/min", "bar") and math.isfinite(a)]
    outputs = {"series": plot_drill_series(time, flows, series, None, run_dir / "series.png", names=FLOWS,
                                           titles=TITLES),
               "comparison": plot_comparison(bars, run_dir / "comparison.png", labels=COLUMNS)}
    if render:
        layout = feed_layout(case)
        outputs.update(draw_sections(frames, case, layout, run_dir, feed_wall_meshes(layout)))
    return outputs
