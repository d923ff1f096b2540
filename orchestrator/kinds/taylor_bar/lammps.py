"""LAMMPS runs the Taylor bar with its MACHDYN package (Smooth Mach Dynamics, Ganzenmueller 2015): total-Lagrangian
SPH (`pair_style smd/tlsph`) of the same particles as the sph scene, the deck in templates/lammps.in.j2, the particles
in a data file; the reader is lammps_output.py, engines.lammps starts the program.

The mapping onto MACHDYN, in one place (machdyn_parameters, deck_context):

- particles: the sph scene's lattice, positions and velocities (atom_style smd: volume dx^3, mass rho0 dx^3); the
  kernel radius is our h, so a pair's support r_i + r_j is our 2h (MACHDYN's spiky kernel in place of ours);
- elasticity: E = 9KG / (3K + G), nu = (3K - 2G) / (2 (3K + G)) from the case's G and K; `*EOS_LINEAR` (the
  pressure rate K tr D, the linear EOS in rate form);
- `*JOHNSON_COOK A B n C epsdot_0 T0 Tm m`: MACHDYN's yield stress is (A + B eps_p^n)(1 + C ln(epsdot* >= 1)) with the
  rate form 'log' only, and epsdot_p a running mean over 1000 r / c_L; its thermal factor (1 - T*^m) is switched off in
  LAMMPS's source (T0, Tm, m and C_p are passed and unused), so the bar stays at room temperature and heat_fraction
  has no effect;
- Monaghan's artificial viscosity: MACHDYN writes mu_ab with the pair's support 2h where ours has h, so Q1 = alpha / 2
  and Q2 = beta / 4 give the same Pi_ab (MACHDYN also caps v_ab . r_ab / r_ab at 0.01 c_L);
- MACHDYN's hourglass control (HOURGLASS, which our SPH does not have) and no artificial stress (a total-Lagrangian
  kernel has no tensile instability);
- the wall: `fix wall/lepton zlo 0` with the potential whose force is the sph wall's eq. 14 (same range, zero and
  F(0)): normal only, so frictionless; it acts on each particle's centre, as ours;
- a fixed step: the sph engine's step at rest (SphScene.timestep, 1/8 of MACHDYN's own bound 2 r / c_L), shortened so
  that a whole number of steps per frame ends at simulation.duration.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.errors import OrchestratorError
from orchestrator.kinds.base import Adapter
from orchestrator.kinds.taylor_bar.lammps_output import (
    DUMP,
    SERIES,
    read_taylor_bar_output,
)
from orchestrator.templating import render

TEMPLATE = Path(__file__).resolve().parent / "templates" / "lammps.in.j2"
DECK = "in.lammps"
DATA = "bar.data"
#: MACHDYN's hourglass control coefficient (the amplitude of its pair hourglass force; LAMMPS's examples use 10).
HOURGLASS = 10.0
#: Neighbour skin over dx (the total-Lagrangian pairs are fixed; the skin only serves the wall and LAMMPS's lists).
SKIN_OVER_DX = 0.3
#: Series records per run at most (the progress lines follow them).
MAX_SERIES = 400


class LammpsTaylorBar(Adapter):
    """The Taylor bar as a LAMMPS MACHDYN deck (templates/lammps.in.j2) with the particles in bar.data."""

    engine = "lammps"
    templates = (TEMPLATE,)

    def check_scene(self, profile, scene) -> None:
        """OrchestratorError naming what MACHDYN lacks for this bar (exit 2 at the command line)."""
        reason = refusal(_material(scene).solid)
        if reason:
            raise OrchestratorError(f"LAMMPS MACHDYN cannot run this Taylor bar: {reason}; run it with --engine sph")

    def write_input(self, profile, scene, workdir: Path) -> None:
        workdir = Path(workdir)
        (workdir / "output").mkdir(exist_ok=True)
        write_data_file(scene, workdir / DATA)
        (workdir / DECK).write_text(render(TEMPLATE, deck_context(scene)))

    def command(self, profile, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        return profile.command(DECK)

    def read_output(self, profile, scene, workdir: Path):
        return read_taylor_bar_output(Path(workdir), scene, run_steps(scene))

    def planned_steps(self, profile, scene) -> int:
        return run_steps(scene)[0]


def _material(scene):
    """The bar's material (the one material of the bar's sph_flow scene: density, solid)."""
    return scene.case.materials[0]


def refusal(solid) -> str:
    """Why MACHDYN cannot run a bar of this solid ('' when it can): the material models it does not have."""
    reasons = {
        f"the equation of state {solid.eos!r} (the linear one only)": solid.eos != "linear",
        "an elastic bar (no yield_stress)": solid.yield_stress is None,
        f"the rate form {solid.rate_form or 'power'!r} (MACHDYN's Johnson-Cook has 1 + C ln(epsdot*) only: "
        "rate_form = 'log')": (solid.rate_form or "power") != "log" and bool(solid.rate_sensitivity),
        "Johnson-Cook failure (material.solid.failure)": solid.failure is not None,
    }
    return "; ".join(text for text, applies in reasons.items() if applies)


def deviations(solid) -> str:
    """What MACHDYN runs differently from what the case asks for this solid."""
    notes = ["no thermal softening (MACHDYN's Johnson-Cook leaves out 1 - T*^m) and no temperature"]
    if solid.heat_fraction:
        notes.append(f"heat_fraction = {solid.heat_fraction:g} unused")
    if solid.artificial_stress is not None:
        notes.append("no artificial stress (total-Lagrangian SPH)")
    notes.append(f"MACHDYN's hourglass control {HOURGLASS:g}")
    return "; ".join(notes)


def _finite(name: str, value) -> float:
    """value as a finite float; OrchestratorError naming it otherwise (no text of the case reaches the deck)."""
    number = float(value)
    if not math.isfinite(number):
        raise OrchestratorError(f"{name} = {value!r} is not a finite number")
    return number


def machdyn_parameters(scene) -> dict[str, float]:
    """The bar's MACHDYN material (SI): rho0, E, nu, Q1, Q2, hg, Cp of *COMMON; A, B, n, C, epsdot0, T0, Tm, m of
    *JOHNSON_COOK (the case's defaults where a key is left out: B 0, n 1, C 0, epsdot_0 1, T0 293, m 1)."""
    m = _material(scene)
    solid = m.solid
    shear, bulk = _finite("shear_modulus", solid.shear_modulus), _finite("bulk_modulus", solid.bulk(m.density))
    av = scene.case.physics.artificial_viscosity
    t0 = solid.room_temperature if solid.room_temperature is not None else 293.0
    values = {
        "rho0": m.density, "E": 9.0 * bulk * shear / (3.0 * bulk + shear),
        "nu": (3.0 * bulk - 2.0 * shear) / (2.0 * (3.0 * bulk + shear)),
        "Q1": av.alpha / 2.0, "Q2": av.beta / 4.0, "hg": HOURGLASS,
        "Cp": solid.heat_capacity if solid.heat_capacity is not None else 1.0,
        "A": solid.yield_stress, "B": solid.hardening_modulus or 0.0,
        "n": solid.hardening_exponent if solid.hardening_exponent is not None else 1.0,
        "C": solid.rate_sensitivity or 0.0,
        "epsdot0": solid.reference_rate if solid.reference_rate is not None else 1.0,
        "T0": t0, "Tm": solid.melting_temperature if solid.melting_temperature is not None else 2.0 * t0,
        "m": solid.thermal_exponent if solid.thermal_exponent is not None else 1.0,
    }
    return {name: _finite(name, value) for name, value in values.items()}


def run_steps(scene) -> tuple[int, float, int]:
    """(steps, dt s, steps per frame): a whole number of steps per frame, dt at most the sph step at rest."""
    duration = _finite("simulation.duration", scene.case.simulation.duration)
    frames = max(1, round(duration / scene.case.output.frame_interval))
    per_frame = max(1, math.ceil(duration / (frames * scene.timestep) - 1e-9))
    steps = per_frame * frames
    return steps, duration / steps, per_frame


def wall_energy(scene) -> tuple[str, float]:
    """(Lepton energy expression of r, range R m) whose force -dE/dr is eq. 14 of the sph wall:
    E(r) = psi / (R^2 s (2R - s)) ((R - r)^5 / 5 - (R - s)^2 (R - r)^3 / 3), J, zero at r = R."""
    wall = scene.case.physics.wall_penalty
    r_, s, psi = (_finite(f"wall {k}", getattr(wall, k)) for k in ("range", "s", "psi"))
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
        "deviation": deviations(_material(scene).solid),
        "data_file": DATA,
        "material": {name: repr(value) for name, value in machdyn_parameters(scene).items()},
        "skin": repr(SKIN_OVER_DX * _finite("numerics.dx", case.numerics.dx)),
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
    dx = _finite("numerics.dx", scene.case.numerics.dx)
    x = np.asarray(scene.positions, dtype=float)
    v = np.asarray(scene.velocities, dtype=float)
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
        raise OrchestratorError("the Taylor bar's scene holds a position or velocity that is not finite")
    volume, mass = dx**3, _finite("material.density", _material(scene).density) * dx**3
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
