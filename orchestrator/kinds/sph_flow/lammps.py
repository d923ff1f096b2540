"""LAMMPS runs SPH flows with its SPH package: the deck (templates/lammps.in.j2), the data file of the particles, and
what LAMMPS SPH cannot run (check_scene). The dump reader is lammps_output.py; engines.lammps starts the program.

The mapping onto LAMMPS, in one place (deck_context):

- particles: type 1 fluid (`fix sph`), 2 fixed boundary particles (`fix sph/stationary`: their density follows the
  continuity equation, they do not move), 3 moving boundary particles (`fix sph` with zero force: they keep their
  block's velocity); one mass per type (rho0 dx^D, 2D per metre of depth as ours);
- Tait EOS with gamma = 7 and no background pressure (`pair_style sph/taitwater`, B = rho0 c0^2 / 7);
- the Lucy kernel with LAMMPS's cutoff = our support 2h;
- Morris viscosity: `sph/taitwater/morris` takes the dynamic viscosity mu = rho0 nu, Pa s;
- Monaghan's artificial viscosity: LAMMPS writes mu_ab with its cutoff where eq. 12 has h, so its alpha is
  ours x h / cutoff = alpha / 2 for the same Pi_ab (beta = 0);
- a fixed time step: the case's numerics.dt, or the step our adaptive rule gives at rest (SphScene.timestep), shortened
  so that a whole number of steps ends at simulation.duration;
- wall velocity: LAMMPS's Morris term sees the boundary particles' own velocity (0, or the plate's), where ours
  mirrors the fluid's (Adami et al. 2012): the no-slip plane sits differently (docs/verify_sph.md measures it).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.errors import OrchestratorError
from orchestrator.kinds.base import Adapter
from orchestrator.kinds.sph_flow.lammps_output import DUMP, planned_steps, read_lammps_output, run_step
from orchestrator.templating import render

TEMPLATE = Path(__file__).resolve().parent / "templates" / "lammps.in.j2"
DECK = "in.lammps"
DATA = "particles.data"
#: Particle types of the data file.
FLUID_TYPE, WALL_TYPE, PLATE_TYPE = 1, 2, 3
#: Neighbour skin as a fraction of the cutoff (LAMMPS rebuilds the lists when a particle moved half of it).
SKIN_FRACTION = 0.1
#: Progress lines per run.
PROGRESS_LINES = 100
#: The optional terms LAMMPS SPH has (continuity, Tait EOS and the pressure gradient are always on).
LAMMPS_TERMS = ("morris_viscosity", "artificial_viscosity", "body_force")


class LammpsSphFlow(Adapter):
    """SPH flows as a LAMMPS deck (templates/lammps.in.j2) with a data file of the particles."""

    engine = "lammps"
    templates = (TEMPLATE,)

    def check_scene(self, profile, scene) -> None:
        """OrchestratorError naming what LAMMPS SPH lacks for this scene (exit 2 at the command line)."""
        reason = refusal(scene)
        if reason:
            raise OrchestratorError(f"{scene.case.case.name}: LAMMPS SPH cannot run this scene: {reason}; run it "
                                    "with --engine sph")

    def write_input(self, profile, scene, workdir: Path) -> None:
        workdir = Path(workdir)
        write_data_file(scene, workdir / DATA)
        (workdir / DECK).write_text(render(TEMPLATE, deck_context(scene)))

    def command(self, profile, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        return profile.command(DECK)

    def read_output(self, profile, scene, workdir: Path):
        return read_lammps_output(Path(workdir), scene)

    def planned_steps(self, profile, scene) -> int:
        return planned_steps(scene)


def refusal(scene) -> str:
    """Why LAMMPS SPH cannot run the scene ('' when it can): the physics it does not have."""
    case = scene.case
    fluid, physics = case.fluid, case.physics
    reasons = {
        "[[materials]]": bool(case.materials),
        "wall meshes with penalty forces (eq. 14)": bool(case.walls),
        "open boundaries (inlets, outlets)": bool(case.inlets or case.outlets),
        "a Lees-Edwards cell": case.lees_edwards is not None,
        "wall points of curved walls": scene.wall_point is not None,
        "flow planes": bool(case.output.flow_planes),
        f"a Tait exponent gamma = {fluid.gamma:g} (LAMMPS's is 7)": fluid.gamma != 7.0,
        "a background pressure": fluid.background_pressure != 0.0,
        "a cavitation floor (fluid.min_pressure)": fluid.min_pressure is not None,
        "the viscosity correction": physics.viscosity_correction,
        "an eddy viscosity": physics.eddy_viscosity is not None,
        "Morris and artificial viscosity together": {"morris_viscosity", "artificial_viscosity"} <= set(physics.terms),
    }
    reasons.update({f"the term {term!r}": True for term in physics.terms if term not in LAMMPS_TERMS})
    av = physics.artificial_viscosity
    if av is not None:
        reasons["a quadratic artificial viscosity (beta > 0)"] = av.beta > 0.0
        reasons["an artificial viscosity on fluid pairs only (walls = false)"] = not av.walls
    masses = np.asarray(scene.masses, dtype=float)
    reasons["particles of different masses"] = bool(len(masses)) and bool(np.ptp(masses) > 1e-12 * masses.max())
    moving = _block_velocities(scene)
    reasons["moving boundary blocks of different velocities"] = len({tuple(v) for v in moving.values()}) > 1
    return "; ".join(text for text, applies in reasons.items() if applies)


def _block_velocities(scene) -> dict[int, list[float]]:
    """{block index: velocity} of the boundary blocks that move, m/s."""
    return {k: list(b.velocity) for k, b in enumerate(scene.case.blocks)
            if b.kind == "boundary" and b.velocity is not None and any(b.velocity)}


def particle_types(scene) -> np.ndarray:
    """Each particle's LAMMPS type (FLUID_TYPE, WALL_TYPE, PLATE_TYPE), int."""
    kind = np.asarray(scene.kind)
    moving = np.isin(np.asarray(scene.block), list(_block_velocities(scene)))
    return np.where(kind == 0, FLUID_TYPE, np.where(moving, PLATE_TYPE, WALL_TYPE)).astype(int)


def box_bounds(scene) -> tuple[list[float], list[float]]:
    """(lo, hi) of the simulation box, m, in 3 components: the domain along periodic axes, the particles' extent
    widened by the cutoff along the others (shrink-wrapped by LAMMPS), and +-cutoff/2 along z in 2D."""
    case = scene.case
    x = np.asarray(scene.positions, dtype=float)
    cutoff = 2.0 * scene.h
    lo, hi = [], []
    for axis in range(scene.dimension):
        if axis in case.domain.periodic:
            lo.append(float(case.domain.lo[axis]))
            hi.append(float(case.domain.hi[axis]))
        else:
            lo.append(float(x[:, axis].min()) - cutoff)
            hi.append(float(x[:, axis].max()) + cutoff)
    if scene.dimension == 2:
        lo.append(-0.5 * cutoff)
        hi.append(0.5 * cutoff)
    return lo, hi


def write_data_file(scene, path: Path) -> None:
    """The LAMMPS data file (atom_style sph: id type rho esph cv x y z; Velocities: id vx vy vz), numbers as repr."""
    x = np.asarray(scene.positions, dtype=float)
    v = np.asarray(scene.velocities, dtype=float)
    if scene.dimension == 2:
        x = np.column_stack([x, np.zeros(len(x))])
        v = np.column_stack([v, np.zeros(len(v))])
    types = particle_types(scene)
    rho = np.asarray(scene.densities, dtype=float)
    mass = float(np.asarray(scene.masses, dtype=float)[0])
    lo, hi = box_bounds(scene)
    lines = [f"LAMMPS data file of the sph_flow scene {scene.case.case.name}", "",
             f"{len(x)} atoms", "3 atom types", ""]
    lines += [f"{lo[a]!r} {hi[a]!r} {'xyz'[a]}lo {'xyz'[a]}hi" for a in range(3)]
    lines += ["", "Masses", ""] + [f"{t} {mass!r}" for t in (FLUID_TYPE, WALL_TYPE, PLATE_TYPE)]
    lines += ["", "Atoms # sph", ""]
    lines += [f"{i + 1} {t} {r!r} 0.0 1.0 {p[0]!r} {p[1]!r} {p[2]!r}" for i, (t, r, p) in
              enumerate(zip(types.tolist(), rho.tolist(), x.tolist()))]
    lines += ["", "Velocities", ""]
    lines += [f"{i + 1} {u[0]!r} {u[1]!r} {u[2]!r}" for i, u in enumerate(v.tolist())]
    Path(path).write_text("\n".join(lines) + "\n")


def record_every(scene) -> int:
    """Steps between two dumps: the series interval (the frame interval without one) in steps, at least 1."""
    output = scene.case.output
    interval = output.series_interval or output.frame_interval
    return max(1, min(round(interval / run_step(scene)), planned_steps(scene)))


def deck_context(scene) -> dict:
    """The template's values for a scene (SI units): numbers as repr, words chosen here; see the module's mapping."""
    case = scene.case
    fluid, physics = case.fluid, case.physics
    num = repr
    cutoff = 2.0 * scene.h
    if "morris_viscosity" in physics.terms:
        pair, viscosity = "sph/taitwater/morris", fluid.density * fluid.viscosity
        meaning = "Morris viscosity, dynamic viscosity rho0 nu in Pa s"
    else:
        av = physics.artificial_viscosity
        pair, viscosity = "sph/taitwater", 0.0 if av is None else av.alpha * scene.h / cutoff
        meaning = "Monaghan's artificial viscosity, alpha h / cutoff"
    gravity = None
    if "body_force" in physics.terms and physics.body_force is not None:
        g = [float(c) for c in physics.body_force] + [0.0] * (3 - case.dimension)
        magnitude = math.sqrt(sum(c * c for c in g))
        if magnitude > 0.0:
            gravity = {"magnitude": num(magnitude), "x": num(g[0] / magnitude), "y": num(g[1] / magnitude),
                       "z": num(g[2] / magnitude)}
    steps = planned_steps(scene)
    return {
        "title": f"sph_flow scene {case.case.name}",
        "dimension": int(case.dimension),
        "boundary": " ".join("p" if a in case.domain.periodic or a >= case.dimension else "s" for a in range(3)),
        "data_file": DATA,
        "pair_style": pair,
        "viscosity_meaning": meaning,
        "rho0": num(float(fluid.density)),
        "c0": num(float(scene.c0)),
        "viscosity": num(float(viscosity)),
        "cutoff": num(cutoff),
        "skin": num(SKIN_FRACTION * cutoff),
        "plates": bool(np.any(particle_types(scene) == PLATE_TYPE)),
        "gravity": gravity,
        "dt": num(run_step(scene)),
        "steps": int(steps),
        "series_every": int(record_every(scene)),
        "progress_every": int(max(1, steps // PROGRESS_LINES)),
        "max_density_deviation": num(float(case.numerics.max_density_deviation)),
        "dump_file": DUMP,
    }
