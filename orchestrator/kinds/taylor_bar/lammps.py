"""LAMMPS runs the Taylor bar with its MACHDYN package (Smooth Mach Dynamics, Ganzenmueller 2015): total-Lagrangian
SPH (`pair_style smd/tlsph`) of the same particles as the sph scene, the deck in templates/lammps.in.j2, the particles
in a data file; the reader is lammps_output.py, engines.lammps starts the program.

The solid's mapping onto MACHDYN (elasticity, equation of state, Johnson-Cook, artificial viscosity, hourglass
control, the fixed step) is kinds/sph_flow/machdyn.py, shared with the crater. What is the bar's own:

- the wall: `fix wall/lepton zlo 0` with the potential whose force is the sph wall's eq. 14 (same range, zero and
  F(0)): normal only, so frictionless; it acts on each particle's centre, as ours;
- the equation of state: the linear one only (the template writes `*EOS_LINEAR`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from orchestrator.errors import OrchestratorError
from orchestrator.kinds.sph_flow.machdyn import (
    deviations,
    finite,
    machdyn_parameters,
    run_steps,
    solid_material,
)
from orchestrator.kinds.sph_flow.machdyn_files import MachdynAdapter
from orchestrator.kinds.taylor_bar.lammps_output import (
    DUMP,
    SERIES,
    read_taylor_bar_output,
)

TEMPLATE = Path(__file__).resolve().parent / "templates" / "lammps.in.j2"
DECK = "in.lammps"
DATA = "bar.data"
#: Neighbour skin over dx (the total-Lagrangian pairs are fixed; the skin only serves the wall and LAMMPS's lists).
SKIN_OVER_DX = 0.3
#: Series records per run at most (the progress lines follow them).
MAX_SERIES = 400


def wall_energy(scene) -> tuple[str, float]:
    """(Lepton energy expression of r, range R m) whose force -dE/dr is eq. 14 of the sph wall:
    E(r) = psi / (R^2 s (2R - s)) ((R - r)^5 / 5 - (R - s)^2 (R - r)^3 / 3), J, zero at r = R."""
    wall = scene.case.physics.wall_penalty
    r_, s, psi = (finite(f"wall {k}", getattr(wall, k)) for k in ("range", "s", "psi"))
    scale = psi / (r_ * r_ * s * (2.0 * r_ - s))
    return f"{scale!r}*(({r_!r}-r)^5/5-{(r_ - s) ** 2!r}*({r_!r}-r)^3/3)", r_


def deck_context(scene) -> dict:
    """The template's values (SI): numbers as repr, words chosen here; see the module's mapping."""
    case = scene.case
    steps, dt, per_frame = run_steps(scene)
    expression, reach = wall_energy(scene)
    records = max(1, round(case.output.frame_interval / (case.output.series_interval or case.output.frame_interval)))
    series_every = max(1, per_frame // records, steps // MAX_SERIES)
    return {
        "deviation": deviations(solid_material(scene).solid),
        "data_file": DATA,
        "material": {name: repr(value) for name, value in machdyn_parameters(scene).items()},
        "skin": repr(SKIN_OVER_DX * finite("numerics.dx", case.numerics.dx)),
        "wall_energy": expression,
        "wall_range": repr(reach),
        "dt": repr(dt),
        "steps": steps,
        "frame_every": per_frame,
        "series_every": series_every,
        "dump_file": DUMP,
        "series_file": SERIES,
    }


def write_data_file(scene, path: Path) -> None:
    """The read_data file of the bar (atom_style smd: id type molecule volume mass kernel-radius contact-radius
    x0 y0 z0 x y z; Velocities: id vx vy vz), numbers as repr, in a box reaching 3 radii around the axis."""
    dx = finite("numerics.dx", scene.case.numerics.dx)
    x = np.asarray(scene.positions, dtype=float)
    v = np.asarray(scene.velocities, dtype=float)
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
        raise OrchestratorError("the Taylor bar's scene holds a position or velocity that is not finite")
    volume, mass = dx**3, finite("material.density", solid_material(scene).density) * dx**3
    reach = 3.0 * float(np.hypot(x[:, 0], x[:, 1]).max()) + 4.0 * dx  # the mushroomed face stays inside
    top = float(x[:, 2].max()) + 4.0 * dx
    lines = ["Taylor bar particles (SI units)", "", f"{len(x)} atoms", "1 atom types", "",
             f"{-reach!r} {reach!r} xlo xhi", f"{-reach!r} {reach!r} ylo yhi", f"{-dx!r} {top!r} zlo zhi",
             "", "Atoms # smd", ""]
    radius, contact = repr(float(scene.h)), repr(0.5 * dx)
    for i, p in enumerate(x.tolist()):
        site = f"{p[0]!r} {p[1]!r} {p[2]!r}"
        lines.append(f"{i + 1} 1 1 {volume!r} {mass!r} {radius} {contact} {site} {site}")
    lines += ["", "Velocities", ""]
    lines += [f"{i + 1} {u[0]!r} {u[1]!r} {u[2]!r}" for i, u in enumerate(v.tolist())]
    Path(path).write_text("\n".join(lines) + "\n")


class LammpsTaylorBar(MachdynAdapter):
    """The Taylor bar as a LAMMPS MACHDYN deck (templates/lammps.in.j2) with the particles in bar.data."""

    templates = (TEMPLATE,)
    label, eos = "Taylor bar", ("linear",)
    deck_file, data_file = DECK, DATA

    def write_data(self, scene, path: Path) -> None:
        write_data_file(scene, path)

    def context(self, scene) -> dict:
        return deck_context(scene)

    def read(self, workdir: Path, scene, steps):
        return read_taylor_bar_output(workdir, scene, steps)
