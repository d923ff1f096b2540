"""SPH flow runs: the measured quantities every sph_flow run reports, from
the series the sph executable writes (run.h5 /series) and its last frame."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from orchestrator.outputs import save_figure

#: Series whose last value is reported as <name>_last (by prefix), with their meaning.
LAST_VALUE_SERIES = ("pressure_probe_", "flow_rate_", "inflow_", "outflow_")
#: The measured quantities (measure_sph_flow): name or fnmatch pattern -> (SI unit, meaning); 2D: per metre of depth.
QUANTITIES: dict[str, tuple[str, str]] = {
    "max_density_deviation": ("-", "largest max |rho/rho0 - 1| over the fluid and the records"),
    "kinetic_energy_last": ("J", "kinetic energy of the fluid at the last record (2D: J/m)"),
    "pressure_probe_*_last": ("Pa", "last value of a pressure probe"),
    "flow_rate_*_last": ("m^3/s", "last flow rate through a plane (2D: m^2/s)"),
    "inflow_*_last": ("m^3/s", "last inflow of an inlet (2D: m^2/s)"),
    "outflow_*_last": ("m^3/s", "last outflow of an outlet (2D: m^2/s)"),
    "fluid_particles_last": ("-", "fluid particles in the last frame"),
}


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


#: Panels of the series figure: (title, y label, series name prefix).
SERIES_PANELS = (
    ("pressure probes", "p [Pa]", "pressure_probe_"),
    ("flow rates", "Q [m^3/s, 2D: m^2/s]", ("flow_rate_", "inflow_", "outflow_")),
    ("fluid kinetic energy", "E_k [J, 2D: J/m]", "kinetic_energy"),
    ("max |rho/rho0 - 1|", "-", "max_density_deviation"),
)


def analyze_sph_run(run_dir: Path, run: dict, case, render: bool = True) -> dict:
    """`orchestrator analyze` of an SPH flow run: print the measured quantities (SI units), write series.png
    (probes, flow rates, kinetic energy, density deviation against time) and, with render, last_frame.png
    (the particles of the last frame coloured by pressure). Returns {name: path}."""
    attrs = run["attrs"]
    measured = run.get("measured", {}).get("attrs", {})
    print(f"run {run_dir}: status {attrs['status']}, {attrs['engine']} {attrs['engine_version']}, "
          f"{attrs['n_particles']} particles, {attrs['n_steps']} steps, {attrs['wall_time_s']:.1f} s"
          + (f": {attrs['message']}" if attrs.get("message") else ""))
    for name, value in measured.items():
        print(f"{name:<40} {value:.6g}")
    outputs = {"series": plot_sph_series(run, Path(run_dir) / "series.png")}
    frames = [k for k in run.get("frames", {}) if k != "attrs"]
    if render and frames:
        outputs["last_frame"] = plot_sph_frame(run["frames"][max(frames, key=int)], Path(run_dir) / "last_frame.png")
    for name, path in outputs.items():
        print(f"{name:<10} {path}")
    return outputs


def plot_sph_series(run: dict, path: Path) -> Path:
    """The run's SPH series against time (s), one panel per kind (SERIES_PANELS), as a PNG at path."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    series = run.get("series", {})
    time = np.asarray(series.get("time", []), dtype=float)
    panels = [(title, label, [n for n in sorted(series) if n != "attrs" and n.startswith(prefix)])
              for title, label, prefix in SERIES_PANELS]
    panels = [p for p in panels if p[2]]
    fig = Figure(figsize=(9.0, 2.4 * max(1, len(panels))), dpi=120, layout="constrained")
    FigureCanvasAgg(fig)
    axes = np.atleast_1d(fig.subplots(max(1, len(panels)), 1, sharex=True))
    for ax, (title, label, names) in zip(axes, panels):
        for name in names:
            values = np.asarray(series[name], dtype=float)
            if values.ndim == 1 and len(values) == len(time):
                ax.plot(time, values, label=name)
        ax.set_title(title, fontsize=10)
        ax.set_ylabel(label)
        if len(names) > 1:
            ax.legend(fontsize=8)
    axes[-1].set_xlabel("t [s]")
    save_figure(fig, path, dpi=fig.dpi, layout=False)  # the output policy: temporary name, rename
    return Path(path)


def plot_sph_frame(frame: dict, path: Path) -> Path:
    """The particles of one frame (x-y in 2D, x-z in 3D, m), fluid coloured by pressure (Pa), boundary grey."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    x = np.asarray(frame["positions"], dtype=float)
    kind = np.asarray(frame["kind"])
    vertical = 1 if x.shape[1] == 2 else 2
    fig = Figure(figsize=(8.0, 5.0), dpi=120, layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    fluid = kind == 0
    ax.scatter(x[~fluid, 0], x[~fluid, vertical], s=2, c="0.6")
    points = ax.scatter(x[fluid, 0], x[fluid, vertical], s=2, c=np.asarray(frame["pressures"])[fluid], cmap="viridis")
    fig.colorbar(points, ax=ax, label="p [Pa]")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel(("y" if vertical == 1 else "z") + " [m]")
    ax.set_title(f"t = {frame['attrs'].get('time', float('nan')):.4g} s")
    save_figure(fig, path, dpi=fig.dpi, layout=False)  # the output policy: temporary name, rename
    return Path(path)
