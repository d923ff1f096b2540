"""LAMMPS runs the crater with its MACHDYN package: the target box of the sph scene (the same particles, its held
support layers) in total-Lagrangian SPH (`pair_style smd/tlsph`) and the sphere as a rigid body of particles,
touching through MACHDYN's `pair_style smd/hertz`. The deck is templates/lammps.in.j2, the particles a data file;
the reader is lammps_output.py, engines.lammps starts the program.

The target's material is mapped by kinds/sph_flow/machdyn.py (shared with the Taylor bar: elasticity, the shock EOS
for Mie-Grueneisen, Johnson-Cook, viscosity, hourglass control, the fixed step). What is the crater's own:

- the held support: its layers are particles of the target's body (one molecule, so bonded to it, as ours are
  glued), left out of the time integration, so they stay where they start at rest;
- the sphere: a shell of SHELL_LAYERS layers of particles on spheres of radii r - (k + 1/2) dx, spaced about dx
  on Fibonacci spirals with a point on each pole, so that with contact radius dx/2 the shell reaches out to r and
  down to the same gap of a quarter dx above the target as the sph engine's sphere; each particle carries the
  sphere's mass and volume over the particle count (the body's mass is the case's exactly). Free, it translates as
  one rigid body: `fix aveforce` gives every particle the body's mean force and `fix nve` moves them alike (RIGID's
  `fix rigid` stops LAMMPS on MACHDYN's finite-size particles); it does not turn, as neither engine's sphere does in
  a normal impact on the axis. Kinematic, it moves at its speed (`fix move
  linear`). Ours is a smooth sphere; MACHDYN's is a surface of particles, bumpy on the scale of dx;
- the contact: smd/hertz between a sphere particle and a target particle, F = 16/15 E_c sqrt(r_g) d^(3/2) for the
  overlap d of their contact radii (dx/2 each, r_g = dx/4), repulsive only and without friction, as ours; E_c is
  numerics.contact_stiffness times rho0 c_L^2 of the target, the scale of the sph engine's spring rho0 c_L^2 dx;
- what is recorded: the sphere's centre of mass, its velocity and the total force on it (the contact force) in the
  series, with its kinetic energy and the contact's elastic energy; the target's particles (not the sphere's) in
  the frames.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from orchestrator.errors import OrchestratorError
from orchestrator.kinds.crater.lammps_output import DUMP, SERIES, read_crater_output
from orchestrator.kinds.sph_flow.machdyn import (
    deviations,
    finite,
    machdyn_parameters,
    material_cards,
    run_steps,
    solid_material,
)
from orchestrator.kinds.sph_flow.machdyn_files import MachdynAdapter

TEMPLATE = Path(__file__).resolve().parent / "templates" / "lammps.in.j2"
DECK = "in.lammps"
DATA = "crater.data"
#: Neighbour skin over dx (the total-Lagrangian pairs are fixed; the skin serves the contact's list).
SKIN_OVER_DX = 0.3
#: Series records per run at most.
MAX_SERIES = 1000
#: Layers of the sphere's shell of particles (a target particle reaches none deeper; the body only translates).
SHELL_LAYERS = 2
#: Molecule ids of the data file: the target with its held support (smd/tlsph bonds only particles of one
#: molecule), the sphere.
TARGET, SPHERE = 1, 2


def sphere(scene):
    """The scene's one impactor (the sphere: spheres[0] = centre x, y, z and radius, m)."""
    return scene.case.impactors[0]


def sphere_particles(scene) -> np.ndarray:
    """Centres (n, 3) m of the sphere's particles: SHELL_LAYERS spherical layers at radii r - (k + 1/2) dx, each of
    about 4 pi R^2 / dx^2 points on a Fibonacci spiral from pole to pole (spacing about dx, a point on each pole); a
    cubic lattice would meet the target with a flat facet of some 7 x 7 particles at its lowest layer. An indenter
    keeps its lower half only (its motion is prescribed)."""
    dx = finite("numerics.dx", scene.case.numerics.dx)
    cx, cy, cz, radius = (finite("sphere", v) for v in sphere(scene).spheres[0])
    layers = []
    for k in range(SHELL_LAYERS):
        shell = radius - (k + 0.5) * dx
        if shell <= 0.0:
            break
        count = max(2, round(4.0 * np.pi * shell * shell / (dx * dx)))
        z = np.linspace(-1.0, 1.0, count)
        azimuth = np.pi * (3.0 - np.sqrt(5.0)) * np.arange(count)  # the golden angle between neighbours
        ring = np.sqrt(np.clip(1.0 - z * z, 0.0, None))
        layers.append(shell * np.column_stack([ring * np.cos(azimuth), ring * np.sin(azimuth), z]))
    points = np.vstack(layers)
    if sphere(scene).kinematic:
        points = points[points[:, 2] <= 0.0]
    return points + np.array([cx, cy, cz])


def support_ids(scene) -> str:
    """The held particles as a LAMMPS id range 'first:last' (the scene lists them after the moving ones, in one run);
    OrchestratorError otherwise."""
    held = np.flatnonzero(np.asarray(scene.kind) != 0)
    if not len(held) or held[-1] - held[0] + 1 != len(held) or held[-1] != len(scene.kind) - 1:
        raise OrchestratorError("the crater's scene does not list its held support as one run after the target")
    return f"{held[0] + 1}:{held[-1] + 1}"


def contact_modulus(scene) -> float:
    """E_c of smd/hertz, Pa: the impactor's stiffness_factor times rho0 c_L^2 of the target."""
    m = solid_material(scene)
    factor = finite("numerics.contact_stiffness", sphere(scene).stiffness_factor)
    return factor * m.density * m.solid.wave_speed(m.density) ** 2


def deck_context(scene) -> dict:
    """The template's values (SI): numbers as repr, words chosen here; see the module's mapping."""
    case = scene.case
    steps, dt, per_frame = run_steps(scene)
    records = max(1, round(case.output.frame_interval / (case.output.series_interval or case.output.frame_interval)))
    body = sphere(scene)
    return {
        "deviation": deviations(solid_material(scene).solid),
        "data_file": DATA,
        "common": " ".join(repr(machdyn_parameters(scene)[k]) for k in ("rho0", "E", "nu", "Q1", "Q2", "hg", "Cp")),
        "cards": material_cards(scene),
        "contact_modulus": repr(contact_modulus(scene)),
        "kinematic": bool(body.kinematic),
        "sphere_velocity": [repr(finite("sphere velocity", v)) for v in body.velocity],
        "centre_offset": [repr(float(c - m)) for c, m in zip(body.spheres[0][:3], sphere_particles(scene).mean(axis=0))],
        "molecules": {"target": TARGET, "sphere": SPHERE},
        "support_ids": support_ids(scene),
        "skin": repr(SKIN_OVER_DX * finite("numerics.dx", case.numerics.dx)),
        "dt": repr(dt),
        "steps": steps,
        "frame_every": per_frame,
        "series_every": max(1, per_frame // records, steps // MAX_SERIES),
        "dump_file": DUMP,
        "series_file": SERIES,
    }


def write_data_file(scene, path: Path) -> None:
    """The read_data file (atom_style smd: id type molecule volume mass kernel-radius contact-radius x0 y0 z0 x y z;
    Velocities: id vx vy vz): the scene's particles first (type 1, molecule TARGET, in input order), then the
    sphere's (type 2, molecule SPHERE); numbers as repr."""
    dx = finite("numerics.dx", scene.case.numerics.dx)
    x = np.asarray(scene.positions, dtype=float)
    v = np.asarray(scene.velocities, dtype=float)
    ball = sphere_particles(scene)
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
        raise OrchestratorError("the crater's scene holds a position or velocity that is not finite")
    radius = float(sphere(scene).spheres[0][3])
    density = finite("material.density", solid_material(scene).density)
    ball_volume = 4.0 / 3.0 * np.pi * radius**3 / len(ball)
    ball_mass = finite("sphere.density", sphere(scene).density) * ball_volume
    rows = [(1, TARGET, dx**3, density * dx**3, p) for p in x.tolist()]
    rows += [(2, SPHERE, ball_volume, ball_mass, p) for p in ball.tolist()]
    every = np.vstack([x, ball])
    lo, hi = (every.min(axis=0) - 4.0 * dx).tolist(), (every.max(axis=0) + 4.0 * dx).tolist()
    lines = ["Crater particles (SI units)", "", f"{len(rows)} atoms", "2 atom types", "",
             f"{lo[0]!r} {hi[0]!r} xlo xhi", f"{lo[1]!r} {hi[1]!r} ylo yhi", f"{lo[2]!r} {hi[2]!r} zlo zhi",
             "", "Atoms # smd", ""]
    kernel, contact = repr(float(scene.h)), repr(0.5 * dx)
    for i, (kind, mol, volume, mass, p) in enumerate(rows):
        site = f"{p[0]!r} {p[1]!r} {p[2]!r}"
        lines.append(f"{i + 1} {kind} {mol} {volume!r} {mass!r} {kernel} {contact} {site} {site}")
    velocities = v.tolist() + [list(sphere(scene).velocity)] * len(ball)
    lines += ["", "Velocities", ""]
    lines += [f"{i + 1} {float(u[0])!r} {float(u[1])!r} {float(u[2])!r}" for i, u in enumerate(velocities)]
    Path(path).write_text("\n".join(lines) + "\n")


class LammpsCrater(MachdynAdapter):
    """The crater as a LAMMPS MACHDYN deck (templates/lammps.in.j2) with the particles in crater.data."""

    templates = (TEMPLATE,)
    label, eos, elastic = "crater", ("linear", "mie_gruneisen"), True
    deck_file, data_file = DECK, DATA

    def write_data(self, scene, path: Path) -> None:
        write_data_file(scene, path)

    def context(self, scene) -> dict:
        return deck_context(scene)

    def read(self, workdir: Path, scene, steps):
        return read_crater_output(workdir, scene, steps)
