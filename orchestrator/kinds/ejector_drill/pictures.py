"""The pictures of an ejector-drill run (drill/drawing.py draws them): its flows and probe pressures against time
(series.png, with the pressure beside the jets as dots), the SPH beside the network and the paper (comparison.png)
and, with render, sections through the frames at the case's picture times with the walls cut (section_<t>ms.png)."""

from __future__ import annotations

from pathlib import Path

from orchestrator.drill.drawing import draw_sections, plot_comparison, plot_drill_series
from orchestrator.kinds.ejector_drill.build import wall_meshes


def draw_run_pictures(run_dir: Path, case, layout, time, flows: dict, series: dict, stored, beside, rows: list,
                      frames: dict, render: bool) -> dict:
    """series.png, comparison.png and (render) the sections in run_dir; {name: path}. time s, flows m^3/s, series:
    the run's, stored: the control volume's storage rate (m^3/s, or None), beside: (frame times s, pressures Pa)
    beside the jets, rows: report.print_comparison's."""
    outputs = {"series": plot_drill_series(time, flows, series, stored, run_dir / "series.png", beside=beside),
               "comparison": plot_comparison(rows, run_dir / "comparison.png")}
    if render:
        outputs.update(draw_sections(frames, case, layout, run_dir, lambda: wall_meshes(case, layout)))
    return outputs
