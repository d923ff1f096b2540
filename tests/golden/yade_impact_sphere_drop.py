# Yade script for an impact scene (a few spheres, optionally one flat wall).
# Rendered by orchestrator from orchestrator/kinds/impact/templates/yade.py.j2; edit the case
# file, not this script. Runs in Yade's own python (numpy, no h5py) and
# writes plain files into output/; the orchestrator turns them into run.h5.
# Units: SI (m, kg, s, N, Pa).
import json
import math
import os
import sys
import time

import numpy as np
import yade
from yade import *  # noqa: F401,F403  (Yade's engines and O)
from yade import utils
from yade.minieigenHP import Vector3

OUT = "output"
os.makedirs(OUT, exist_ok=True)
WALL_START = time.time()

# ---- materials (E already multiplied by numerics.stiffness_scale = 1.0) ----
# The rigid wall (E = inf in the case) is 1000000.0 times stiffer than the stiffest sphere:
# its compliance then changes E_eq by less than 1e-6 of itself.
MATERIAL_ID = {}
MATERIAL_ID["ceramic"] = O.materials.append(FrictMat(
    young=77000000000.0, poisson=0.19, density=2656.0, frictionAngle=0.0,
    label="ceramic"))
MATERIAL_ID["steel"] = O.materials.append(FrictMat(
    young=210000000000.0, poisson=0.3, density=7610.0, frictionAngle=0.0,
    label="steel"))


def pair_table(rows):
    return tuple((MATERIAL_ID[a], MATERIAL_ID[b], value) for a, b, value in rows)


FRICTION_ANGLE = pair_table((('ceramic', 'steel', 0.2730087030867106),))
# The paper's damping c_n = c_t = alpha sqrt(m_eq k_n) delta^(1/4) with the case's alpha, as Yade
# parameters: Yade 2023 computes c_n = 2 betan sqrt(m_eq 3/2 k_n delta^(1/2)), so betan = alpha / sqrt(6),
# and c_t = 2 betas sqrt(m_eq k_t0 delta^(1/2)), so betas = alpha / 2 sqrt(k_n / k_t0).
BETAN = pair_table((('ceramic', 'steel', 0.12137322951838744),))
BETAS = pair_table((('ceramic', 'steel', 0.11645767707055929),))
PHYSICS = Ip2_FrictMat_FrictMat_MindlinPhys(betan=MatchMaker(matches=BETAN), betas=MatchMaker(matches=BETAS),
                                            frictAngle=MatchMaker(matches=FRICTION_ANGLE))
# The paper's eq. 5 k_t0 / sqrt(R_eq) = 4 G_m / (2 - nu_m) per pair (Yade 2023 uses Mindlin's 8 G*, which
# differs for unlike materials); set on each new contact by track() (its first step keeps Yade's value).
KSO_PER_SQRT_R = {(MATERIAL_ID[a], MATERIAL_ID[b]): value for a, b, value in (('ceramic', 'steel', 128914156063.47734),)}
KSO_PER_SQRT_R.update({(b, a): value for (a, b), value in list(KSO_PER_SQRT_R.items())})

# ---- bodies ----
scene_data = np.load("scene.npz")
SPHERE_IDS = []
for p, v, w, r, m in zip(scene_data["positions"], scene_data["velocities"], scene_data["angular_velocities"],
                         scene_data["radii"], scene_data["materials"]):
    body = utils.sphere(tuple(p), float(r), material=MATERIAL_ID[str(m)])
    body.state.vel = Vector3(*v)
    body.state.angVel = Vector3(*w)
    SPHERE_IDS.append(O.bodies.append(body))
INDEX = {body_id: k for k, body_id in enumerate(SPHERE_IDS)}
RADII = np.array([O.bodies[i].shape.radius for i in SPHERE_IDS])
MASSES = np.array([O.bodies[i].state.mass for i in SPHERE_IDS])
INERTIA = np.array([O.bodies[i].state.inertia[0] for i in SPHERE_IDS])
WALL_IDS = []
PLANE_POINT = np.array((0.0, 0.0, 0.0))
PLANE_NORMAL = np.array((0.0, 0.0, 1.0))
# an axis-aligned plane: Yade's infinite wall, touching spheres on the normal's side only
WALL_IDS.append(O.bodies.append(utils.wall(0.0, axis=2, sense=1,
                                           material=MATERIAL_ID["steel"])))

# ---- engines ----
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb(), Bo1_Facet_Aabb()]),
    InteractionLoop(
        # hertzian=True: a sphere on a wall or facet is Hertz's sphere on a flat (R_eq = R); Yade's
        # default takes the wall as a sphere of radius 2R (R_eq = 2R/3, an 18 % softer contact).
        [Ig2_Sphere_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom(hertzian=True), Ig2_Facet_Sphere_ScGeom(hertzian=True)],
        [PHYSICS],
        [Law2_ScGeom_MindlinPhys_Mindlin()],
    ),
    # both runners see the forces of this step at the positions they were computed for (time O.time)
    PyRunner(iterPeriod=1, command="track()", dead=True, label="tracker"),
    PyRunner(iterPeriod=617, command="record()", label="recorder"),
    NewtonIntegrator(damping=0.0, gravity=(0.0, 0.0, -9.81)),
]
O.dt = 1.621569463599656e-07

N_STEPS = 955865
DURATION = 0.155
GRAVITY = np.array((0.0, 0.0, -9.81))
RECORD_EVERY = 617
MAX_OVERLAP_FRACTION = 0.2
ENERGY_GROWTH = 0.01
ENERGY_SCALE = 3.81618207582326e-05  # J, what the scene can release: kinetic energy plus falls onto the plane
DOMAIN_RADIUS = 0.4056981044601707
# Contact events are tracked every step in scenes of a few spheres (impacts); a dense scene's contacts
# are not impacts, and tracking hundreds of them in python every step would cost more than the physics.
TRACK_EVENTS = len(SPHERE_IDS) <= 50
START = np.array([tuple(O.bodies[i].state.pos) for i in SPHERE_IDS])

state = {"status": "ok", "message": "", "last_progress": 0.0, "energy0": None, "stopped": False}
open_events = {}
closed_events = []
series_columns = (["time", "kinetic_energy", "potential_energy", "normal_force", "max_overlap", "n_contacts",
                   "wall_fx", "wall_fy", "wall_fz"]
                  + ["%s_%d_%s" % (name, k, c) for name in ("pos", "vel", "spin")
                     for k in range(len(SPHERE_IDS)) for c in "xyz"])
with open(os.path.join(OUT, "series.json"), "w") as fh:
    json.dump({"columns": series_columns, "n_spheres": len(SPHERE_IDS)}, fh)
series = open(os.path.join(OUT, "series.bin"), "wb")


def approach_rate(I):
    """Normal approach speed of the two bodies at the contact point, m/s (> 0 closing)."""
    point = I.geom.contactPoint
    a, b = O.bodies[I.id1].state, O.bodies[I.id2].state
    va = a.vel + a.angVel.cross(point - a.pos)
    vb = b.vel + b.angVel.cross(point - b.pos)
    return float((va - vb).dot(I.geom.normal))


def event_bodies(I):
    """(sphere index, other kind 0 sphere / 1 plane, other index), as the reference DEM numbers them."""
    if I.id1 in INDEX and I.id2 in INDEX:
        a, b = sorted((INDEX[I.id1], INDEX[I.id2]))
        return a, 0, b
    sphere = I.id1 if I.id1 in INDEX else I.id2
    return INDEX[sphere], 1, 0


def track():
    """Every step while contacts are near: the life of each contact (first touch to separation)."""
    seen = set()
    for I in O.interactions:
        if not I.isReal:
            continue
        key = (I.id1, I.id2)
        seen.add(key)
        overlap = float(I.geom.penetrationDepth)
        rate = approach_rate(I)
        force = float(I.phys.normalForce.norm())
        event = open_events.get(key)
        if event is None:
            sphere, kind, other = event_bodies(I)
            event = open_events[key] = {
                "sphere": sphere, "other_kind": kind, "other": other,
                "start_time": O.time - overlap / rate if rate > 0 else O.time, "impact_speed": rate,
                "peak_normal_force": -1.0, "peak_time": O.time, "max_overlap": 0.0}
            coefficient = KSO_PER_SQRT_R.get((O.bodies[I.id1].material.id, O.bodies[I.id2].material.id))
            if coefficient is not None:
                r1, r2 = I.geom.refR1, I.geom.refR2
                I.phys.kso = coefficient * math.sqrt(r1 * r2 / (r1 + r2))
        if force > event["peak_normal_force"]:
            event["peak_normal_force"], event["peak_time"] = force, O.time
        event["max_overlap"] = max(event["max_overlap"], overlap)
        event["last"] = (O.time, overlap, rate)
        if not overlap == overlap or overlap > MAX_OVERLAP_FRACTION * contact_radius(I):
            return stop("unstable", "a contact overlap reached %.3g of the sphere radius at t = %.6g s (allowed %.2g)"
                        % (overlap / contact_radius(I), O.time, MAX_OVERLAP_FRACTION))
    for key in [k for k in open_events if k not in seen]:
        event = open_events.pop(key)
        t_last, overlap, rate = event.pop("last")
        separating = -rate
        event["end_time"] = t_last + (overlap / separating if separating > 0 else 0.0)
        event["rebound_speed"] = separating
        closed_events.append(event)
        write_events()


def contact_radius(I):
    """The smaller radius of the spheres in a contact, m."""
    return min(RADII[INDEX[i]] for i in (I.id1, I.id2) if i in INDEX)


def gaps():
    """Smallest gap to any other body of each sphere, m, and each sphere's speed, m/s."""
    pos = np.array([tuple(O.bodies[i].state.pos) for i in SPHERE_IDS])
    speed = np.array([O.bodies[i].state.vel.norm() for i in SPHERE_IDS])
    gap = np.full(len(SPHERE_IDS), np.inf)
    if PLANE_NORMAL is not None:
        gap = np.minimum(gap, (pos - PLANE_POINT) @ PLANE_NORMAL - RADII)
    if len(SPHERE_IDS) > 1:
        distance = np.linalg.norm(pos[:, None, :] - pos[None, :, :], axis=2) - RADII[:, None] - RADII[None, :]
        np.fill_diagonal(distance, np.inf)
        gap = np.minimum(gap, distance.min(axis=1))
    return pos, speed, gap


def contact_near(speed, gap):
    """True if a contact may start before the next record (closing at twice the fastest speed, plus gravity)."""
    horizon = RECORD_EVERY * O.dt
    reach = 2.0 * (speed.max() * horizon + 0.5 * np.linalg.norm(GRAVITY) * horizon ** 2) + 1e-12
    return bool(np.any(gap < reach))


def energies(pos):
    velocity = np.array([tuple(O.bodies[i].state.vel) for i in SPHERE_IDS])
    spin = np.array([tuple(O.bodies[i].state.angVel) for i in SPHERE_IDS])
    kinetic = 0.5 * float(np.sum(MASSES * np.sum(velocity ** 2, axis=1)) + np.sum(INERTIA * np.sum(spin ** 2, axis=1)))
    potential = -float(np.sum(MASSES * (pos @ GRAVITY)))
    return kinetic, potential, velocity, spin


def record():
    if state["stopped"]:
        return
    pos, speed, gap = gaps() if TRACK_EVENTS else (np.array([tuple(O.bodies[i].state.pos) for i in SPHERE_IDS]),
                                                    None, None)
    kinetic, potential, velocity, spin = energies(pos)
    real = [I for I in O.interactions if I.isReal]
    wall_force = Vector3(0, 0, 0)
    for i in WALL_IDS:
        wall_force += O.forces.f(i)
    normal_force = sum(float(I.phys.normalForce.norm()) for I in real)
    overlap = max([float(I.geom.penetrationDepth) for I in real] or [0.0])
    row = np.concatenate([[O.time, kinetic, potential, normal_force, overlap, len(real),
                           wall_force[0], wall_force[1], wall_force[2]], pos.ravel(), velocity.ravel(), spin.ravel()])
    series.write(row.astype("<f8").tobytes())
    series.flush()
    tracker.dead = not TRACK_EVENTS or not (real or open_events or contact_near(speed, gap))
    report_progress()
    if not np.all(np.isfinite(row)):
        return stop("unstable", "a sphere position or velocity became NaN at t = %.6g s" % O.time)
    deepest = max([float(I.geom.penetrationDepth) / contact_radius(I) for I in real] or [0.0])
    if deepest > MAX_OVERLAP_FRACTION:
        return stop("unstable", "a contact overlap reached %.3g of the sphere radius at t = %.6g s (allowed %.2g)"
                    % (deepest, O.time, MAX_OVERLAP_FRACTION))
    if state["energy0"] is None:
        state["energy0"] = kinetic + potential
    elif kinetic + potential - state["energy0"] > ENERGY_GROWTH * ENERGY_SCALE:
        # kinetic + potential energy can only fall (dissipation) or go into the contacts' springs
        return stop("unstable", "the kinetic plus potential energy grew by %.3g J, %.3g %% of what the scene can "
                    "release, by t = %.6g s" % (kinetic + potential - state["energy0"],
                                                100.0 * (kinetic + potential - state["energy0"]) / ENERGY_SCALE,
                                                O.time))
    far = np.linalg.norm(pos - START, axis=1).max()
    if far > DOMAIN_RADIUS:
        return stop("unstable", "a sphere left the domain (%.3g m from its start, farther than the scene's energy "
                    "allows, %.3g m) at t = %.6g s" % (far, DOMAIN_RADIUS, O.time))


def report_progress():
    now = time.time()
    if now - state["last_progress"] > 1.0:
        print("PROGRESS step=%d of %d phase=impact t=%.6g" % (O.iter, N_STEPS, O.time), flush=True)
        state["last_progress"] = now


def write_events():
    if not TRACK_EVENTS:
        return
    rows = closed_events + [dict(event, end_time=float("nan"), rebound_speed=float("nan"))
                            for event in open_events.values()]
    columns = ("sphere", "other_kind", "other", "start_time", "end_time", "impact_speed", "rebound_speed",
               "peak_normal_force", "peak_time", "max_overlap")
    np.savez(os.path.join(OUT, "events.npz"), **{c: np.array([row[c] for row in rows], dtype=float) for c in columns})


def write_status():
    with open(os.path.join(OUT, "status.json"), "w") as fh:
        json.dump({"status": state["status"], "message": state["message"], "n_steps": O.iter, "dt": O.dt,
                   "time": O.time, "wall_time_s": time.time() - WALL_START, "yade_version": yade.config.version}, fh,
                  indent=1)


def stop(status, message):
    state["status"], state["message"], state["stopped"] = status, message, True
    print("STATUS %s %s" % (status, message), flush=True)
    write_events()
    write_status()
    O.stopAtIter = O.iter + 1  # the loop stops once this step is complete (O.pause() would let O.run's wait return
    # while the step's later engines still run)


record()  # the state at t = 0
O.run(N_STEPS, True)
if not state["stopped"]:
    record()  # the state at t = duration (forces of the last step)
    if not state["stopped"]:
        stop("ok", "")
series.close()
sys.exit(0 if state["status"] == "ok" else 3)
