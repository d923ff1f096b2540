"""What a Taylor bar run measured (run.h5 /measured, from the last frame and the series) and its picture: the
final length and face diameter, the plastic strain and temperature at the face centre, the rebound speed and the
energy balance. Lengths in m, temperatures in K."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.outputs import save_figure

#: The measured quantities (measure_taylor_bar): name -> (SI unit, meaning).
QUANTITIES: dict[str, tuple[str, str]] = {
    "final_length": ("m", "the bar's length at the end: highest minus lowest particle centre plus dx"),
    "face_diameter": ("m", "the impact face's diameter at the end: twice the largest radius of the bottom layer's "
                           "particle centres plus dx"),
    "face_plastic_strain": ("-", "equivalent plastic strain at the face centre (bottom-layer particles within dx "
                                 "of the axis)"),
    "face_temperature": ("K", "temperature at the face centre"),
    "max_plastic_strain": ("-", "largest equivalent plastic strain in the bar"),
    "max_temperature": ("K", "highest temperature in the bar"),
    "rebound_speed": ("m/s", "the bar's mean velocity along +z at the end (positive: moving off the wall)"),
    "energy_balance": ("-", "(kinetic + internal energy) at the end over the initial kinetic energy, minus 1 (the "
                            "internal energy holds the elastic energy, the plastic work and the artificial "
                            "viscosity's heat; the wall's penalty holds none once the bar has left it)"),
}


def face_layer(positions: np.ndarray, dx: float) -> np.ndarray:
    """Mask of the bottom layer: particles within dx/2 of the lowest centre."""
    z = positions[:, 2]
    return z < z.min() + 0.5 * dx


def shape(frame: dict, dx: float) -> dict[str, float]:
    """Length, face diameter (m) and the face centre's plastic strain and temperature of one frame."""
    x = np.asarray(frame["positions"], dtype=float)
    r = np.hypot(x[:, 0], x[:, 1])
    face = face_layer(x, dx)
    out = {"final_length": float(x[:, 2].max() - x[:, 2].min() + dx),
           "face_diameter": float(2.0 * r[face].max() + dx)}
    centre = face & (r < dx)
    for name in ("plastic_strain", "temperature"):
        if name in frame and centre.any():  # an engine without the field (MACHDYN: temperature) skips it
            out[f"face_{name}"] = float(np.mean(np.asarray(frame[name])[centre]))
            out[f"max_{name}"] = float(np.max(frame[name]))
    return out


def measure_taylor_bar(case, result) -> dict[str, float]:
    """Measured quantities of a Taylor bar run (QUANTITIES) from its last frame; empty without frames."""
    if not result.frames:
        return {}
    dx = case.numerics.dx
    frame = result.frames[-1][1]
    measured = shape(frame, dx)
    if "velocities" not in frame:
        return {k: v for k, v in measured.items() if math.isfinite(v)}
    v = np.asarray(frame["velocities"], dtype=float)
    measured["rebound_speed"] = float(np.mean(v[:, 2]))
    if "internal_energy" in frame:
        mass = case.material.density * dx**3  # every particle: rho0 dx^3
        n = len(v)
        kinetic0 = 0.5 * mass * n * case.bar.speed**2
        final = 0.5 * mass * float(np.sum(v * v)) + mass * float(np.sum(frame["internal_energy"]))
        measured["energy_balance"] = final / kinetic0 - 1.0
    return {k: v for k, v in measured.items() if math.isfinite(v)}


def analyze_taylor_bar_run(run_dir: Path, run: dict, case, render: bool = True) -> dict:
    """`orchestrator analyze` of a Taylor bar run: print the measured quantities beside the published ranges and
    write taylor_bar.png (the final outline and the plastic strain). Returns {name: path}."""
    attrs = run["attrs"]
    measured = run.get("measured", {}).get("attrs", {})
    print(f"run {run_dir}: status {attrs['status']}, {attrs['n_particles']} particles, {attrs['n_steps']} steps, "
          f"{attrs['wall_time_s']:.1f} s")
    for name, value in measured.items():
        published = getattr(case.reference, name, None) if case.reference is not None else None
        beside = f"   published {published.low:.6g} - {published.high:.6g}" if published is not None else ""
        print(f"{name:<24} {value:.6g} {QUANTITIES.get(name, ('', ''))[0]}{beside}")
    if not render:
        return {}
    path = plot_bar(run, case, Path(run_dir) / "taylor_bar.png")
    print(f"{'picture':<24} {path}")
    return {"picture": path}


def plot_bar(run: dict, case, path: Path) -> Path:
    """The final bar in the r-z plane (every particle, coloured by plastic strain) with the initial outline, mm."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    frames = run.get("frames", {})
    keys = sorted((k for k in frames if k != "attrs"), key=int)
    fig = Figure(figsize=(4.6, 6.4), dpi=120, layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    r0, l0 = case.bar.radius * 1e3, case.bar.length * 1e3
    ax.plot([0, r0, r0, 0], [0, 0, l0, l0], "k--", lw=0.8, label="initial bar")
    if keys:
        last = frames[keys[-1]]
        x = np.asarray(last["positions"], dtype=float)
        r, z = np.hypot(x[:, 0], x[:, 1]) * 1e3, (x[:, 2] - x[:, 2].min()) * 1e3
        colour = np.asarray(last.get("plastic_strain", np.zeros(len(r))), dtype=float)
        points = ax.scatter(r, z, c=colour, s=2.0, cmap="viridis", vmin=0.0)
        fig.colorbar(points, ax=ax, label="equivalent plastic strain")
    ax.set_xlim(0.0, 2.6 * r0)  # room for the legend right of the initial outline
    ax.set_ylim(-0.05 * l0, 1.12 * l0)
    ax.set_xlabel("r, mm")
    ax.set_ylabel("z above the face, mm")
    ax.set_aspect("equal")
    ax.set_title(f"{case.case.name}: {case.bar.speed:g} m/s", fontsize=9)
    ax.legend(loc="upper right", fontsize=8)
    return save_figure(fig, path, layout=False)
