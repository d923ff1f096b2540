"""LIGGGHTS backend, drag finishing: the deck's context (the phases and
numbers of the Yade script: same cloud, same settling criteria, same rod
motion, same damping alpha), the files it reads, and the reader that turns
what the deck wrote into the run.h5 names of Yade's runs (series
workpiece_force in the workpiece frame, rod_force, bowl_force,
kinetic_energy, unbalanced_force, n_contacts, rod_tip_z, phase; frames;
interaction networks; the rod's per-face contact intensity).

Where the deck differs from the Yade script (besides the contact law, see
orchestrator.dem.liggghts_law):
- the rest criterion's mean contact force is the mean *normal* force (from
  the per-atom virial for ball-ball contacts, the stored wall force for
  ball-wall ones); Yade's includes the tangential part (at most 6 % more at
  mu = 0.34), so LIGGGHTS's unbalanced ratio reads a little higher;
- the rod is pushed in for exactly the steps that bring its tip to the
  target, and the snapshots and the end fall on the exact step; Yade
  checks at its control period (1 ms);
- stiffening (settling.stiffness_scale) changes E in the same stages as
  Yade's control steps; LIGGGHTS recomputes every contact from E, so a
  sticking contact's tangential force grows with the stiffness at once where
  Yade's keeps the force it had.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.dem.liggghts_law import liggghts_beta, restitution_for_beta
from orchestrator.dem.yade_law import yade_native_alpha
from orchestrator.engines.liggghts_files import write_data_file, write_stl_ascii
from orchestrator.errors import OrchestratorError
from orchestrator.kinds.drag_finishing.impacts import ROD_GAP, rod_prism, template_values
from orchestrator.kinds.drag_finishing.schedule import every, schedule

TEMPLATE = Path(__file__).resolve().parent / "templates" / "liggghts.in.j2"
DATA_FILE = "balls.data"
#: What the LIGGGHTS run does differently from Yade's drag-finishing script (run.h5 attribute "deviation").
DEVIATION = ("LIGGGHTS keeps the total tangential displacement (F_t = -k_t(delta) s) where Yade increments the "
             "force; settling damps forces only (Yade also torques); the rest criterion uses the mean contact "
             "normal force")
PHASES = ("settle", "insert", "relax", "process")
#: Steps of the first process chunk, after which the deck prints its TIMING line (as Yade's script).
TIMING_STEPS = 500
#: Columns of the network dumps (compute pair/gran/local and wall/gran/local: pos id force force_normal
#: force_tangential).
NETWORK_COLUMNS = ("x1", "y1", "z1", "x2", "y2", "z2", "id1", "id2", "id3", "fx", "fy", "fz", "fnx", "fny", "fnz",
                   "ftx", "fty", "ftz")


def damping_restitution(restitution: float) -> float:
    """coefficientRestitution e* that gives LIGGGHTS the damping Yade's drag script runs for e_n, -."""
    return restitution_for_beta(liggghts_beta(yade_native_alpha(restitution)))




def drag_context(scene) -> dict:
    """Plain values the drag-finishing deck needs (SI units)."""

    case = scene.case
    scale, soft = case.numerics.stiffness_scale, case.settling_stiffness_scale
    names = (case.media.material, case.bowl.material, case.workpiece.material)
    mats = [case.materials[n] for n in names]
    restitution = np.ones((3, 3))
    friction = np.zeros((3, 3))
    for k in (0, 1, 2):  # media-media, media-bowl, media-rod
        pair = case.contact(names[0], names[k])
        restitution[0, k] = restitution[k, 0] = damping_restitution(pair.restitution)
        friction[0, k] = friction[k, 0] = pair.friction
    plan = schedule(scene)
    dt, dt_settle, stiffen, control_every = plan.dt, plan.dt_settle, plan.stiffen, plan.control_every
    return {
        "media_material": names[0], "bowl_material": names[1], "rod_material": names[2],
        "stiffness_scale": repr(scale),
        "settling_stiffness_scale": repr(soft),
        "young_settle": [repr(m.young_modulus * soft) for m in mats],
        "poisson": [repr(m.poisson_ratio) for m in mats],
        "restitution": [repr(float(v)) for v in restitution.ravel()],
        "friction": [repr(float(v)) for v in friction.ravel()],
        "skin": repr(0.2 * case.media.radius),
        "solid_volume": repr(float(np.sum(4.0 / 3.0 * np.pi * scene.radii**3))),
        "settling_damping": repr(case.settling.damping),
        "settle_max_time": repr(case.settling.max_time),
        "settle_unbalanced": repr(case.settling.unbalanced_force),
        "settle_max_speed": repr(case.settling.max_speed),
        "tip_start": repr(float(np.asarray(scene.meshes["rod"].mesh.vertices)[:, 2].min())),
        "submersion_depth": repr(case.workpiece.submersion_depth),
        "insertion_speed": repr(case.workpiece.insertion_speed),
        "angular_velocity": repr(case.angular_velocity),
        "rotation_period": repr(2.0 * math.pi / case.angular_velocity),
        "dt": repr(dt), "dt_settle": repr(dt_settle),
        "stiffen": stiffen, "stiffen_factor": repr(scale / soft), "stiffen_time": repr(case.settling.stiffen_time),
        "stiffen_stages": plan.stiffen_stages, "stage_steps": control_every,
        "relax_time": repr(case.settling.relax_time),
        "relax_steps_settle": plan.relax_steps_settle, "relax_steps": plan.relax_steps,
        "record_every": plan.record_every, "record_every_settle": plan.record_every_settle,
        "control_every_settle": plan.control_every_settle,
        "progress_every": max(100, plan.planned_steps // 400),
        "steps_after_insert": plan.steps_after_insert,
        "planned_steps": plan.planned_steps,
        "process_chunks": process_chunks(plan.process_steps, [round(t / dt) for t in case.output.network_times],
                                         checkpointevery(case, dt), impact_steps(case, dt)),
        "resume": None,
        "path_radius": repr(case.workpiece.path_radius),
        "impact_frictionless": bool(friction[0, 2] == 0.0),
        **impact_values(scene),
    }


def impact_values(scene) -> dict:
    """impacts.template_values, after checking that no ball can touch the rod and the bowl's side at once (the
    deck records the starts of any wall contact and the reader keeps those on the rod): the bowl's inner radius
    less the rod's reach from the bowl axis (its mesh's, which may be wider than workpiece.radius) exceeds a ball
    diameter by impacts.ROD_GAP. OrchestratorError otherwise."""
    values = template_values(scene)
    if values["impact_window"] is None:
        return values
    case = scene.case
    rod = np.asarray(scene.meshes["rod"].mesh.vertices)
    prism = rod_prism(rod, scene.meshes["rod"].mesh.faces)
    reach = float(np.hypot(*prism["axis"]) + np.max(np.hypot(*(rod[:, :2] - prism["axis"]).T)))
    r_max = float(np.max(scene.radii))
    clearance = case.bowl.inner_radius - reach
    if clearance <= 2.0 * r_max + ROD_GAP:
        raise OrchestratorError(
            f"output.impact_window needs the rod, {clearance * 1e3:.3g} mm from the bowl's side, to be more than a "
            f"ball diameter ({2e3 * r_max:.3g} mm) from it, so that a ball touches one wall at a time (LIGGGHTS "
            "records the starts of wall contacts); allowed: remove output.impact_window, or a smaller "
            "workpiece.path_radius, workpiece.radius or media.radius")
    return values


def impact_steps(case, dt: float) -> tuple[int, int] | None:
    """output.impact_window (cut to the process) as process steps [start, end), or None."""
    window = case.impact_window
    return None if window is None else (round(window[0] / dt), round(window[1] / dt))


def checkpointevery(case, dt: float) -> int | None:
    """Process steps between checkpoints (output.checkpoint_interval), or None."""
    interval = case.output.checkpoint_interval
    return None if interval is None else every(interval, dt)


def process_chunks(total: int, network_steps: list[int], checkpoint_steps: int | None = None,
                   impact_steps: tuple[int, int] | None = None) -> list[dict]:
    """The process phase as runs: [{steps, timing, networks, checkpoint, impacts}], cut at each network
    snapshot's step (from the process start), after the first TIMING_STEPS steps (the timing line), every
    checkpoint_steps (a restart file is written after a chunk whose checkpoint is True; never after the last one)
    and at the ends of impact_steps (process steps [start, end) in which contact starts are recorded: impacts
    is True for the chunks inside)."""
    checkpoints = set(range(checkpoint_steps, total, checkpoint_steps)) if checkpoint_steps else set()
    window = tuple(min(max(s, 0), total) for s in impact_steps) if impact_steps else ()
    cuts = sorted({min(TIMING_STEPS, total), total, *(min(s, total) for s in network_steps if s > 0), *checkpoints,
                   *(s for s in window if s > 0)})
    chunks, done = [], 0
    for cut in cuts:
        chunks.append({"steps": cut - done, "timing": not chunks,
                       "networks": [k for k, s in enumerate(network_steps) if min(max(s, 0), total) == cut],
                       "checkpoint": cut in checkpoints, "impacts": bool(window) and window[0] <= done < window[1]})
        done = cut
    if 0 in network_steps:  # a snapshot at the start of the process: a zero-step run writes it
        chunks.insert(0, {"steps": 0, "timing": False, "networks": [k for k, s in enumerate(network_steps) if s <= 0],
                          "checkpoint": False, "impacts": False})
    return chunks


def write_drag_files(scene, workdir: Path) -> None:
    """balls.data (the scene's cloud) and bowl.stl, rod.stl (the scene's meshes, ASCII) into workdir."""
    case = scene.case
    workdir = Path(workdir)
    bowl_r, height = case.bowl.inner_radius, case.bowl.height
    rod = np.asarray(scene.meshes["rod"].mesh.vertices)
    top = max(float(np.max(scene.positions[:, 2] + scene.radii)), float(rod[:, 2].max()))
    # a ball outside [-2R, 2R] or below -H/2 has left the bowl (as in the Yade script): LIGGGHTS loses it
    box = np.array([[-2 * bowl_r, 2 * bowl_r], [-2 * bowl_r, 2 * bowl_r], [-0.5 * height, top + 0.5 * height]])
    rho = case.materials[case.media.material].density
    write_data_file(workdir / DATA_FILE, box, 3, np.ones(scene.n_particles, int), scene.radii,
                    np.full(scene.n_particles, rho), scene.positions)
    for name in ("bowl", "rod"):
        mesh = scene.meshes[name].mesh
        write_stl_ascii(workdir / f"{name}.stl", mesh.vertices, mesh.faces, name)
