"""The crater's verification rows (`verify solids`, one run per [sweep] speed): the crater diameter (the plastic
zone's rim at the surface) against Hutchings' eq. 20 with the run's own mean contact pressure, and the energy
balance."""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from orchestrator.kinds.crater.analysis import QUANTITIES, contact_modulus
from orchestrator.kinds.crater.pictures import plot_speed_sweep
from orchestrator.kinds.sph_flow.checks_base import check_row

#: Units of the checked quantities in the table.
UNITS = {name: unit for name, (unit, _) in QUANTITIES.items()}


def sweep_runs(case, stem: str) -> list[tuple[str, tuple[str, ...]]]:
    """(run folder, overrides) of each run: one, or one per [sweep] speed (sphere.speed set to it, m/s)."""
    if case.sweep is None:
        return [(stem, ())]
    return [(f"{stem}/v_{v:g}", (f"sphere.speed={v!r}",)) for v in case.sweep.speeds]


def check_run(case, engine: str, run: dict) -> tuple[list[dict], dict]:
    """The crater's rows (one per [[expected]] row; a quantity the run did not measure fails) and its picture data."""
    measured = run.get("measured", {}).get("attrs", {}) if run else {}
    name = f"{case.case.name} at {case.sphere.speed:g} m/s"
    rows = []
    for row in case.expected:
        if row.quantity == "speed_exponent":  # over the sweep: check_sweep
            continue
        if row.quantity == "energy_balance":
            value = measured.get("energy_balance")
            known = value is not None and math.isfinite(value)
            rows.append(check_row(name, "energy_balance", value if known else None, 0.0, abs(value) if known else None,
                                  row.tolerance, passed=None if known else False, source="conservation",
                                  note="energy_balance: (kinetic + internal + contact energy) at the end / initial "
                                       "kinetic energy - 1"))
            continue
        if row.quantity == "hertz_modulus":
            value, expected = measured.get("hertz_modulus"), contact_modulus(case)
            known = value is not None and math.isfinite(value)
            rows.append(check_row(name, "hertz_modulus", value if known else None, expected,
                                  abs(value / expected - 1.0) if known else None, row.tolerance,
                                  passed=None if known else False, source="Hertz: E / (1 - nu^2) of the target",
                                  note="hertz_modulus: E* of the line through (delta, (F / f)^(2/3)), f the "
                                       "bonded-layer factor of the block's depth (Dimitriadis et al. 2002)"))
            continue
        value, expected = measured.get("crater_diameter"), measured.get("hutchings_diameter")
        if value is None or expected is None:
            rows.append(check_row(name, "crater_diameter", None, expected, None, row.tolerance, passed=False,
                                  source="Hutchings eq. 20", note="crater_diameter: not measured (no contact?)"))
            continue
        rows.append(check_row(name, "crater_diameter", value, expected, abs(value / expected - 1.0), row.tolerance,
                              source="Hutchings eq. 20 with the measured mean contact pressure",
                              note=f"mean contact pressure {measured.get('mean_pressure', math.nan) / 1e9:.3g} GPa"))
    picture = {"speed": case.sphere.speed, "diameter": measured.get("crater_diameter", math.nan),
               "contact": measured.get("contact_diameter", math.nan),
               "volume": measured.get("volume_diameter", math.nan),
               "hutchings": measured.get("hutchings_diameter", math.nan),
               "hardness": measured.get("dynamic_hardness", math.nan),
               "pressure": measured.get("mean_pressure", math.nan)}
    return rows, picture


def speed_slope(speeds, diameters) -> float:
    """The slope of log d against log v (eq. 20: 1/2) by least squares; nan with fewer than two finite points."""
    v, d = np.asarray(speeds, dtype=float), np.asarray(diameters, dtype=float)
    ok = np.isfinite(v) & np.isfinite(d) & (v > 0) & (d > 0)
    if ok.sum() < 2:
        return math.nan
    return float(np.polyfit(np.log(v[ok]), np.log(d[ok]), 1)[0])


def check_sweep(case, engine: str, runs) -> list[dict]:
    """The speed_exponent row over one sweep's runs (workflows.base.CheckedRun, their check_run pictures): the
    slope of log volume_diameter (the cap of the sphere's radius holding the crater's volume: the crater of eq.
    20's energy balance) against log speed, against eq. 20's 1/2 at a constant dynamic hardness, its relative
    error against the row's tolerance; the note gives the slopes of the rim crest (crater_diameter), the contact
    chord and eq. 20 at each run's own mean contact pressure. A sweep of two speeds or more also draws its
    diameters and hardness against speed (pictures.plot_speed_sweep) as crater_speeds.png in the folder that holds
    its runs."""
    if len(runs) >= 2:
        plot_speed_sweep(runs, Path(os.path.commonpath([run.run_dir for run in runs])) / "crater_speeds.png")
    rows = []
    for row in (r for r in case.expected if r.quantity == "speed_exponent"):
        speeds = [run.picture.get("speed", math.nan) for run in runs]
        slopes = {key: speed_slope(speeds, [run.picture.get(key, math.nan) for run in runs])
                  for key in ("volume", "diameter", "contact", "hutchings")}
        value = slopes["volume"]
        known = math.isfinite(value) and all(math.isfinite(run.picture.get("volume", math.nan)) for run in runs)
        rows.append(check_row(f"{case.case.name} over {len(runs)} speeds", "speed_exponent",
                              value if known else None, 0.5, abs(value / 0.5 - 1.0) if known else None,
                              row.tolerance, passed=None if known else False,
                              source="Hutchings eq. 20 at a constant dynamic hardness: d ~ v^(1/2)",
                              note=f"speed_exponent: log volume_diameter on log v; rim crest "
                                   f"{slopes['diameter']:.3f}, contact chord {slopes['contact']:.3f}, eq. 20 at "
                                   f"each run's own mean contact pressure {slopes['hutchings']:.3f}"))
    return rows
