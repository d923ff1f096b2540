"""LAMMPS runs impact cases with its GRANULAR package: the deck (templates/lammps.in.j2), the data file of the spheres,
and what LAMMPS cannot run (check_scene). The dump reader is lammps_output.py; engines.lammps starts the program.

The mapping of the paper's law onto ``pair_style granular`` and ``fix wall/gran/region`` is in
orchestrator.dem.lammps_law, in one place; impact_context puts it into the deck:

- one atom type per sphere material, every type pair set by its own pair_coeff (a pair that cannot touch, a
  material with one sphere, gets its material's law undamped and without friction);
- the plane as a region plane, one wall fix per sphere type with the law of that material against the plane's;
- the time step the other engines run: the case's numerics.timestep_factor of the critical step (scene.timestep);
- the dump: every sphere's state, the total force on it and the force of each wall fix on it, at every record
  and, while a contact is on or may start before the next record, every step (as the LIGGGHTS deck; a pair is
  near when LAMMPS lists it within the pair cutoff, widened by how far the spheres can close in one record).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.dem.lammps_law import MAX_ALPHA, GranularLaw, granular_law
from orchestrator.errors import OrchestratorError
from orchestrator.kinds.base import Adapter
from orchestrator.kinds.impact.analysis import EVENT_LIMIT
from orchestrator.kinds.impact.case import RIGID
from orchestrator.kinds.impact.lammps_output import (
    DUMP,
    STATUS,
    dump_columns,
    read_impact_output,
)
from orchestrator.kinds.impact.physics import (
    fastest_closing_speeds,
    poisson_ratio,
    young_modulus,
)
from orchestrator.kinds.impact.yade import domain_radius
from orchestrator.reference.contact import mindlin_stiffness_coefficient
from orchestrator.templating import render

TEMPLATE = Path(__file__).resolve().parent / "templates" / "lammps.in.j2"
DECK = "impact.in"
DATA = "spheres.data"
#: Progress lines per run.
PROGRESS_LINES = 200


class LammpsImpact(Adapter):
    """Impact scenes as a LAMMPS deck (templates/lammps.in.j2) with the spheres in spheres.data."""

    engine = "lammps"
    templates = (TEMPLATE,)

    def check_scene(self, profile, scene) -> None:
        """OrchestratorError naming a contact LAMMPS's damping cannot reach (exit 2 at the command line)."""
        reason = refusal(scene)
        if reason:
            raise OrchestratorError(f"{scene.case.case.name}: LAMMPS cannot run this scene: {reason}; run it on "
                                    "yade or reference")

    def write_input(self, profile, scene, workdir: Path) -> None:
        workdir = Path(workdir)
        (workdir / "output").mkdir(exist_ok=True)
        write_spheres(scene, workdir / DATA)
        (workdir / DECK).write_text(render(TEMPLATE, impact_context(scene)))

    def command(self, profile, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        return profile.command(DECK)

    def read_output(self, profile, scene, workdir: Path):
        return read_impact_output(scene, workdir, lammps_deviations(scene))


def refusal(scene) -> str:
    """Why LAMMPS cannot run the scene ('' when it can): a damping beyond coeff_restitution's reach."""
    reasons = []
    for (a, b), pair in sorted(scene.pairs.items()):
        if pair.alpha is not None and pair.alpha > MAX_ALPHA:
            reasons.append(f"contacts ({a}, {b}): restitution = {pair.restitution} with model.damping = "
                           f"{scene.case.model.damping!r} needs Tsuji's alpha = {pair.alpha:.4g}, beyond the "
                           f"{MAX_ALPHA:.4g} that LAMMPS's coeff_restitution damping reaches")
    return "; ".join(reasons)


def lammps_deviations(scene) -> str:
    """What LAMMPS runs differently from what the case asks ('' if nothing)."""
    case = scene.case
    notes = []
    if case.model.coulomb_limit == "elastic" and any(p.friction > 0 for p in scene.pairs.values()):
        notes.append("model.coulomb_limit = 'elastic' asked; LAMMPS's mindlin/force bounds the total tangential "
                     "force (spring plus dash-pot)")
    if case.model.damping == "engine" and any(p.restitution >= 1.0 > p.tangential_restitution
                                              for p in scene.pairs.values()):
        notes.append("LAMMPS scales the tangential damping from the normal one, which e_n = 1 leaves at zero: "
                     "no tangential damping")
    return "; ".join(notes)


def _elastic(case, name) -> tuple[float, float]:
    return young_modulus(case, name), poisson_ratio(case, name)


def _types(scene) -> tuple[list[str], dict[str, int]]:
    kinds = sorted(set(scene.sphere_materials))
    return kinds, {name: k + 1 for k, name in enumerate(kinds)}


def contact_law(scene, a: str, b: str) -> GranularLaw:
    """The granular law of materials a and b (a sphere material against the plane's, or two sphere materials)."""
    case = scene.case
    key = tuple(sorted((a, b)))
    if key not in scene.pairs:  # one sphere of this material: the pair never touches
        young, poisson = _elastic(case, a)
        return granular_law(young / (2.0 * (1.0 - poisson**2)), poisson, 0.0, 0.0, 0.0, 1.0, 1.0)
    pair = scene.pairs[key]
    (young_a, poisson_a), (young_b, poisson_b) = _elastic(case, a), _elastic(case, b)
    shear = float(mindlin_stiffness_coefficient(1.0, young_a, poisson_a, young_b, poisson_b))
    poisson = poisson_a if b == RIGID else poisson_b if a == RIGID else 0.5 * (poisson_a + poisson_b)
    return granular_law(pair.effective_young, poisson, shear, pair.friction, pair.alpha, pair.restitution,
                        pair.tangential_restitution)


def _pairs(scene, kinds: list[str], type_of: dict[str, int], reach_pair: float) -> list[dict]:
    largest = {k: max(r for r, m in zip(scene.radii, scene.sphere_materials) if m == k) for k in kinds}
    return [{"types": f"{type_of[a]} {type_of[b]}", "law": contact_law(scene, a, b).words(),
             "cutoff": repr(float(largest[a] + largest[b] + reach_pair))}
            for i, a in enumerate(kinds) for b in kinds[i:]]


def _plane(scene, kinds: list[str], type_of: dict[str, int]) -> dict | None:
    if scene.plane_material is None:
        return None
    walls = [{"type": type_of[k], "group": f"type_{type_of[k]}", "fix": f"wall_{type_of[k]}",
              "law": contact_law(scene, k, scene.plane_material).words()} for k in kinds]
    return {"point": [repr(float(v)) for v in scene.plane_point],
            "normal": [repr(float(v)) for v in scene.plane_normal],
            "offset": repr(float(scene.plane_point @ scene.plane_normal)), "walls": walls}


def impact_context(scene) -> dict:
    """The template's values for a scene (SI units): numbers as repr, words chosen here; see the module's mapping."""
    case = scene.case
    kinds, type_of = _types(scene)
    dt = scene.timestep
    n_steps = max(1, math.ceil(scene.duration / dt - 1e-9))
    record_every = max(1, round(scene.record_interval / dt))
    horizon = record_every * dt
    wall_speed, pair_speed = fastest_closing_speeds(case)
    g = float(np.linalg.norm(scene.gravity))
    track = scene.n_particles <= EVENT_LIMIT
    track_pairs = track and scene.n_particles > 1
    reach_plane = 2.0 * (float(wall_speed.max()) * horizon + 0.5 * g * horizon**2) + 1e-12
    reach_pair = 2.0 * pair_speed * horizon + 1e-12
    return {
        "title": f"impact scene {case.case.name}: "
                 + ", ".join(f"type {type_of[k]} = {k}" for k in kinds)
                 + (f"; the plane is {scene.plane_material}" if scene.plane_material else ""),
        "deviation": lammps_deviations(scene),
        "data_file": DATA,
        "skin": repr(0.1 * float(scene.radii.min())),
        "pairs": _pairs(scene, kinds, type_of, reach_pair),
        "plane": _plane(scene, kinds, type_of),
        "gravity": repr(g) if g > 0.0 else None,
        "dt": repr(dt),
        "n_steps": n_steps,
        "record_every": record_every,
        "track_events": track,
        "track_pairs": track_pairs,
        "reach_plane": repr(reach_plane),
        "columns": dump_columns([type_of[k] for k in kinds] if scene.plane_material is not None else []),
        "dump_file": DUMP,
        "status_file": STATUS,
        "progress_every": max(1, n_steps // PROGRESS_LINES),
    }


def write_spheres(scene, path: Path) -> None:
    """The read_data file of the spheres (atom_style sphere: id type diameter density x y z; Velocities: id vx vy vz
    wx wy wz), numbers as repr, in a box reaching domain_radius beyond them (a sphere beyond it is lost: the run
    stops)."""
    case = scene.case
    kinds, type_of = _types(scene)
    reach = domain_radius(scene)
    lo = (scene.positions.min(axis=0) - reach).tolist()
    hi = (scene.positions.max(axis=0) + reach).tolist()
    lines = [f"spheres of the impact scene {case.case.name} (SI units)", "", f"{scene.n_particles} atoms",
             f"{len(kinds)} atom types", ""]
    lines += [f"{lo[a]!r} {hi[a]!r} {axis}lo {axis}hi" for a, axis in enumerate("xyz")]
    lines += ["", "Atoms # sphere", ""]
    for i, (name, radius, x) in enumerate(zip(scene.sphere_materials, scene.radii.tolist(),
                                               scene.positions.tolist())):
        density = float(case.materials[name].density)
        lines.append(f"{i + 1} {type_of[name]} {2.0 * radius!r} {density!r} {x[0]!r} {x[1]!r} {x[2]!r}")
    lines += ["", "Velocities", ""]
    for i, (v, w) in enumerate(zip(scene.velocities.tolist(), scene.angular_velocities.tolist())):
        lines.append(f"{i + 1} " + " ".join(repr(c) for c in (*v, *w)))
    Path(path).write_text("\n".join(lines) + "\n")
