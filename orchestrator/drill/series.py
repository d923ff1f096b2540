"""A drill run's series as both drill kinds read them: the header line of `orchestrator analyze`, the steady window
(the last STEADY_FRACTION of the run) and the sensor probes' pressures over it. Times in s, pressures in Pa (gauge:
the outlets hold gauge pressures)."""

from __future__ import annotations

import math

import numpy as np

#: The last fraction of the run over which steady values are averaged.
STEADY_FRACTION = 0.2


def steady_window(time: np.ndarray) -> np.ndarray:
    """Mask of the records (times s) in the last STEADY_FRACTION of the run."""
    return time >= time[-1] - STEADY_FRACTION * (time[-1] - time[0])


def run_series(run_dir, run: dict, case, paper_dt: str = "") -> tuple[dict, np.ndarray]:
    """Print a drill run's header line (status, particles, steps, mean dt with the paper's beside it, c0, CFL, wall
    time) and return its series (name -> values) and their times (s, empty when fewer than two records: then it
    says so)."""
    attrs = run["attrs"]
    series = {k: v for k, v in run.get("series", {}).items() if k != "attrs"}
    time = np.asarray(series.pop("time", []), dtype=float)
    print(f"run {run_dir}: status {attrs['status']}, {attrs.get('n_particles')} particles at the start, "
          f"{attrs.get('n_steps')} steps, mean dt {attrs.get('dt', float('nan')):.4g} s{paper_dt}, c0 {case.c0:g} m/s, "
          f"CFL {case.numerics.adaptive['cfl']:g}, wall time {attrs.get('wall_time_s', 0):.1f} s{_parts(attrs)}")
    if time.size < 2:
        print("the run recorded fewer than two series records: nothing to analyse")
        return series, np.zeros(0)
    return series, time


def _parts(attrs: dict) -> str:
    """' (the last of N parts; the engine's X s over all)' for a resumed run, '' otherwise."""
    parts = int(attrs.get("engine_parts", 1))
    if parts < 2:
        return ""
    engine = float(attrs.get("engine_wall_time_s", 0))
    return f" (the last of {parts} parts: resumed; the engine's {engine:.1f} s over all)"


def sensor_pressures(series: dict, time: np.ndarray) -> dict[str, float]:
    """Mean gauge pressure (Pa) of each probe over the steady window (NaN where no fluid was near the probe)."""
    window = steady_window(time)
    out = {}
    for name in sorted(series):
        if name.startswith("pressure_probe_"):
            values = np.asarray(series[name], dtype=float)[window]
            out[name.removeprefix("pressure_probe_")] = float(np.nanmean(values)) if np.isfinite(values).any() \
                else math.nan
    return out
