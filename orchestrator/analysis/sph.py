"""SPH flow runs: the measured quantities every sph_flow run reports, from
the series the sph executable writes (run.h5 /series) and its last frame."""

from __future__ import annotations

import numpy as np

#: Series whose last value is reported as <name>_last (by prefix), with their meaning.
LAST_VALUE_SERIES = ("pressure_probe_", "flow_rate_", "inflow_", "outflow_")


def measure_sph_flow(case, result) -> dict[str, float]:
    """Measured quantities of an SPH flow run (SI units; 2D: per metre of depth):

    max_density_deviation: largest max |rho/rho0 - 1| over the fluid and over the records, -;
    kinetic_energy_last: kinetic energy of the fluid at the last record, J (2D: J/m);
    <probe or flow series>_last: last value of each pressure probe (Pa) and flow-rate,
    inflow and outflow series (m^3/s, 2D: m^2/s), NaN dropped;
    fluid_particles_last: fluid particles in the last frame, -.
    Empty when the run recorded nothing.
    """
    measured: dict[str, float] = {}
    series = result.series
    if "max_density_deviation" in series and np.size(series["max_density_deviation"].values):
        measured["max_density_deviation"] = float(np.nanmax(series["max_density_deviation"].values))
    if "kinetic_energy" in series and np.size(series["kinetic_energy"].values):
        measured["kinetic_energy_last"] = float(np.asarray(series["kinetic_energy"].values)[-1])
    for name in sorted(series):
        if name.startswith(LAST_VALUE_SERIES):
            values = np.asarray(series[name].values, dtype=float)
            values = values[np.isfinite(values)]
            if values.size:
                measured[f"{name}_last"] = float(values[-1])
    if result.frames:
        kind = result.frames[-1][1].get("kind")
        if kind is not None:
            measured["fluid_particles_last"] = float(np.count_nonzero(np.asarray(kind) == 0))
    return measured
