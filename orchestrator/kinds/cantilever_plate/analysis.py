"""What a cantilever plate run measured (run.h5 /measured, from its frames): the tip's swing (period from its zero
crossings, amplitude, decay), the clumping (the smallest distance between two plate particles) and the energy
balance. The tip is the plate's last column of particles (its mean y). Lengths in m, times in s."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.kinds.cantilever_plate.pictures import plot_plate
from orchestrator.kinds.cantilever_plate.theory import plate_theory
from orchestrator.kinds.sph_flow.checks_base import frames_of

#: The measured quantities (measure_cantilever_plate): name -> (SI unit, meaning).
QUANTITIES: dict[str, tuple[str, str]] = {
    "period": ("s", ("period of the tip's vertical displacement: twice the least-squares slope of its zero "
                     "crossings against their count")),
    "crossings": ("-", "zero crossings of the tip's displacement the period is fitted to"),
    "tip_amplitude": ("m", "the tip's largest displacement in the first half period"),
    "amplitude_ratio": ("-", "the tip's largest displacement in the last half period over that of the first"),
    "min_distance": ("-", ("the smallest distance between two plate particles over all frames, over dx (1 on the "
                           "initial lattice; tensile clumping pulls pairs together)")),
    "neighbour_spread": ("-", ("the largest, over frames, standard deviation of the plate particles' nearest-"
                               "neighbour distance, over dx (0 on the lattice)")),
    "energy_balance": ("-", "(kinetic + internal energy) at the end over the initial kinetic energy, minus 1"),
}


def tip_series(frames, length: float, dx: float) -> tuple[np.ndarray, np.ndarray]:
    """(t s, y m) of the tip: the mean y of the plate particles that start within dx of its free end, relative to
    that mean at the first frame. frames: [(t, arrays)] with ids, kind, positions."""
    first = frames[0][1]
    plate = np.asarray(first["kind"]) == 0
    x0 = np.asarray(first["positions"], dtype=float)
    tip_ids = np.asarray(first["ids"])[plate & (x0[:, 0] > length - dx)]
    times, ys = [], []
    for t, frame in frames:
        at = np.isin(np.asarray(frame["ids"]), tip_ids)
        if not at.any():
            break
        times.append(t)
        ys.append(float(np.mean(np.asarray(frame["positions"], dtype=float)[at, 1])))
    y = np.asarray(ys)
    return np.asarray(times), y - y[0]


def zero_crossings(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Times (s) where y changes sign after the first sample, each the root of the cubic through the four samples
    around it (the linear root when fewer exist)."""
    out = []
    for i in range(1, len(y) - 1):
        if not (y[i] != 0.0 and y[i] * y[i + 1] <= 0.0):
            continue
        lo, hi = max(i - 1, 0), min(i + 3, len(y))
        linear = t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])
        if hi - lo < 4:
            out.append(linear)
            continue
        scale = t[i + 1] - t[i]
        roots = np.roots(np.polyfit((t[lo:hi] - t[i]) / scale, y[lo:hi], 3))
        real = [r.real * scale + t[i] for r in roots if abs(r.imag) < 1e-9 and -1e-9 <= r.real <= 1.0 + 1e-9]
        out.append(min(real, key=lambda r: abs(r - linear)) if real else linear)
    return np.asarray(out)


def swing(t: np.ndarray, y: np.ndarray) -> dict[str, float]:
    """Period (s, from at least 2 zero crossings), crossings, the first half period's largest |y| (m) and the last
    half period's over it (-) of a tip series; only what the series allows."""
    crossings = zero_crossings(t, y)
    out: dict[str, float] = {"crossings": float(len(crossings))}
    if len(crossings) >= 2:
        slope = np.polyfit(np.arange(len(crossings)), crossings, 1)[0]
        out["period"] = float(2.0 * slope)
    if len(crossings) >= 1:
        first = float(np.max(np.abs(y[t <= crossings[0]])))
        out["tip_amplitude"] = first
        if len(crossings) >= 2:
            last = np.abs(y[(t >= crossings[-2]) & (t <= crossings[-1])])
            if len(last) and first > 0.0:
                out["amplitude_ratio"] = float(np.max(last) / first)
    return out


def spacing(frame, dx: float) -> tuple[float, float]:
    """(smallest, standard deviation of) the plate particles' nearest-neighbour distance in one frame, over dx."""
    from scipy.spatial import cKDTree

    x = np.asarray(frame["positions"], dtype=float)[np.asarray(frame["kind"]) == 0]
    distance, _ = cKDTree(x).query(x, k=2)
    nearest = distance[:, 1] / dx
    return float(nearest.min()), float(nearest.std())


def energy_balance(first, last, mass: float) -> float:
    """(kinetic + internal energy) of the last frame over the kinetic energy of the first, minus 1 (every particle
    of mass `mass`, kg/m)."""
    v0, v1 = (np.asarray(f["velocities"], dtype=float) for f in (first, last))
    kinetic0 = 0.5 * mass * float(np.sum(v0 * v0))
    final = 0.5 * mass * float(np.sum(v1 * v1)) + mass * float(np.nansum(last["internal_energy"]))
    return final / kinetic0 - 1.0


def measure_frames(case, frames) -> dict[str, float]:
    """Measured quantities (QUANTITIES) of a run's frames [(t s, arrays)]; empty with fewer than 2."""
    if len(frames) < 2:
        return {}
    dx = case.numerics.dx
    t, y = tip_series(frames, case.plate.length, dx)
    measured = swing(t, y)
    spreads = [spacing(frame, dx) for _, frame in frames]
    measured["min_distance"] = min(s[0] for s in spreads)
    measured["neighbour_spread"] = max(s[1] for s in spreads)
    if "internal_energy" in frames[-1][1]:
        mass = case.material.density * dx**2
        measured["energy_balance"] = energy_balance(frames[0][1], frames[-1][1], mass)
    return {k: v for k, v in measured.items() if math.isfinite(v)}


def measure_cantilever_plate(case, result) -> dict[str, float]:
    """Measured quantities of a cantilever plate run (QUANTITIES) from its frames; empty without two frames."""
    return measure_frames(case, result.frames)


def expected_cantilever_plate(case) -> dict[str, float]:
    """Thin-plate theory's period (s) and the tip amplitude of the mode at that frequency, V c0 / omega (m)."""
    theory = plate_theory(case)
    return {"period": theory["period"], "tip_amplitude": theory["amplitude"]}


def analyze_cantilever_plate_run(run_dir: Path, run: dict, case, render: bool = True) -> dict:
    """`orchestrator analyze` of a cantilever plate run: print the measured quantities beside thin-plate theory and
    write cantilever_plate.png. Returns {name: path}."""
    attrs = run["attrs"]
    measured = run.get("measured", {}).get("attrs", {})
    theory = plate_theory(case)
    print(f"run {run_dir}: status {attrs['status']}, {attrs['n_particles']} particles, {attrs['n_steps']} steps, "
          f"{attrs['wall_time_s']:.1f} s")
    beside = {"period": theory["period"], "tip_amplitude": theory["amplitude"]}
    for name, value in measured.items():
        note = f"   thin-plate theory {beside[name]:.6g}" if name in beside else ""
        print(f"{name:<20} {value:.6g} {QUANTITIES.get(name, ('', ''))[0]}{note}")
    if not render:
        return {}
    frames = frames_of(run)
    tip = tip_series(frames, case.plate.length, case.numerics.dx) if len(frames) >= 2 else None
    path = plot_plate(frames, tip, case, Path(run_dir) / "cantilever_plate.png")
    print(f"{'picture':<20} {path}")
    return {"picture": path}
