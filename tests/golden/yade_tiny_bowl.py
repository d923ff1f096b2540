# Yade script for the drag-finishing scene (Uhlmann, Eulitz, Dethlefs 2015).
# Rendered by orchestrator from orchestrator/kinds/drag_finishing/templates/yade.py.j2; edit the
# case file, not this script. Runs in Yade's own python (numpy, no h5py) and
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
# --resume: the scene below is built as always (same materials, bodies and ids), then replaced by the last
# checkpoint's saved one (O.load), and the script's own state is read back from output/checkpoint.json
RESUME = "--resume" in sys.argv
CHECKPOINT_EVERY = None  # s of process time between checkpoints (None: none)

# ---- materials ----
# E is multiplied by the settling stiffness scale (0.001) here; before the process
# every contact is stiffened to numerics.stiffness_scale = 0.001 (see stiffen()).
MATERIAL_ID = {}
MATERIAL_ID["ceramic"] = O.materials.append(FrictMat(
    young=77000000.0, poisson=0.19, density=2656.0,
    frictionAngle=0.3277385067805555, label="ceramic"))
MATERIAL_ID["steel"] = O.materials.append(FrictMat(
    young=210000000.0, poisson=0.3, density=7610.0,
    frictionAngle=0.3277385067805555, label="steel"))


def pair_table(rows):
    return tuple((MATERIAL_ID[a], MATERIAL_ID[b], value) for a, b, value in rows)


# Restitution and friction per material pair (paper section 5). Yade's
# MindlinPhys turns en/es into its own damping coefficient; see the README.
EN = pair_table((('ceramic', 'ceramic', 0.86), ('ceramic', 'steel', 0.68)))
ES = pair_table((('ceramic', 'ceramic', 0.86), ('ceramic', 'steel', 0.68)))
FRICTION_ANGLE = pair_table((('ceramic', 'ceramic', 0.3277385067805555), ('ceramic', 'steel', 0.2730087030867106)))

# ---- bodies ----
scene_data = np.load("scene.npz")
SPHERE_IDS = [
    O.bodies.append(utils.sphere(tuple(p), float(r), material=MATERIAL_ID["ceramic"]))
    for p, r in zip(scene_data["positions"], scene_data["radii"])
]


def add_mesh(prefix, material):
    vertices = scene_data[prefix + "_vertices"]
    faces = scene_data[prefix + "_faces"]
    return [
        O.bodies.append(utils.facet([tuple(vertices[i]) for i in face], fixed=True, wire=False,
                                    material=MATERIAL_ID[material]))
        for face in faces
    ]


BOWL_IDS = add_mesh("bowl", "steel")
ROD_IDS = add_mesh("rod", "steel")
ROLE = {}
ROLE.update((i, 1) for i in BOWL_IDS)
ROLE.update((i, 2) for i in ROD_IDS)

# ---- engines ----
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb()]),
    InteractionLoop(
        # hertzian=True: a ball on a facet is Hertz's sphere on a flat (R_eq = R); Yade's default
        # treats the facet as a sphere of radius 2R (R_eq = 2R/3, an 18 % softer contact).
        [Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom(hertzian=True)],
        [Ip2_FrictMat_FrictMat_MindlinPhys(
            en=MatchMaker(matches=EN), es=MatchMaker(matches=ES),
            frictAngle=MatchMaker(matches=FRICTION_ANGLE))],
        [Law2_ScGeom_MindlinPhys_Mindlin()],
    ),
    TranslationEngine(ids=ROD_IDS, translationAxis=(0, 0, -1), velocity=0.05,
                      dead=True, label="push"),
    RotationEngine(ids=ROD_IDS, rotationAxis=(0, 0, 1), rotateAroundZero=True, zeroPoint=(0, 0, 0),
                   angularVelocity=2.0, dead=True, label="drag"),
    NewtonIntegrator(damping=0.4, gravity=(0.0, 0.0, -9.81), label="newton"),
    PyRunner(iterPeriod=36, command="control()", label="controller"),
    PyRunner(iterPeriod=72, command="record()", label="recorder"),
    PyRunner(iterPeriod=1, command="impacts()", dead=True, label="impacter"),
]
DT_SETTLE = 2.794444601978471e-05  # s, while settling, inserting and relaxing at the settling stiffness
DT = 2.794444601978471e-05  # s, from the stiffening on (the process)
O.dt = DT_SETTLE
STIFFEN = False  # settling stiffness or step differ from the process ones
STIFFEN_FACTOR = 1.0
STIFFEN_TIME = 0.02
YOUNG_SETTLE = dict((m.id, m.young) for m in O.materials)

SETTLE_MAX_TIME = 1.0
SETTLE_UNBALANCED = 0.01
SETTLE_MAX_SPEED = 0.005
RELAX_TIME = 0.1
SUBMERSION_DEPTH = 0.008
PATH_RADIUS = 0.005
PROCESS_DURATION = 0.1
NETWORK_TIMES = [0.05]
BOWL_RADIUS = 0.02
BOWL_HEIGHT = 0.05
PLANNED_STEPS = 53349
PHASES = ("settle", "insert", "relax", "process")

state = {"phase": 0, "t_phase": 0.0, "bed_height": None, "settled": None, "tip_target": None,
         "t_process": None, "next_network": 0, "status": "ok", "message": "", "last_progress": 0.0,
         "last_record": -1.0, "record_interval": DT_SETTLE * 72,
         "relax_stage": 0, "t_stage": 0.0, "applied_factor": 1.0, "probe_done": False, "planned": PLANNED_STEPS, "probe_start": None, "phase_wall": {},
         "checkpoints": 0}
rod_intensity = np.zeros(len(ROD_IDS))  # accumulated |F| dt per rod facet, N s
rod_contact_count = np.zeros(len(ROD_IDS), dtype=np.int64)  # facet-samples in contact
if RESUME:
    with open(os.path.join(OUT, "checkpoint.json")) as fh:
        checkpoint = json.load(fh)
    O.load(checkpoint["scene"])  # bodies, interactions, engines (labels bound again), time, step, dt
    state.update(checkpoint["state"])
    state["probe_done"], state["last_progress"] = True, 0.0
    rod_intensity[:] = checkpoint["rod_intensity"]
    rod_contact_count[:] = checkpoint["rod_contact_count"]
    print("RESUMED t=%.6g s step=%d from %s" % (O.time, O.iter, checkpoint["scene"]), flush=True)
# the orchestrator dropped rows recorded after the checkpoint before a resumed run appends
# contact starts on the rod in IMPACT_WINDOW (s of process; None: off), as the LIGGGHTS deck finds them
# (orchestrator/kinds/drag_finishing/impacts.py): the rod is a prism of IMPACT_SEGMENTS sides (apothem
# IMPACT_APOTHEM m, flat tip) carried about the bowl axis; g is a ball's gap to it, u = -dg/dt its normal
# approach speed; a contact starts where g <= 0 < g + u dt
IMPACT_WINDOW = (0.0, 0.1)
IMPACT_SEGMENTS = 8
IMPACT_ALPHA0 = 0.39269908169872425
IMPACT_APOTHEM = 0.002309698831278217
IMPACT_SECTOR = 0.7853981633974483
impact_file = open(os.path.join(OUT, "impacts.csv"), "a" if RESUME else "w") if IMPACT_WINDOW else None
if impact_file is not None and not RESUME:
    impact_file.write("time,id,radius,x,y,z,vx,vy,vz,gap,speed,step\n")
series = open(os.path.join(OUT, "series.csv"), "a" if RESUME else "w")
if not RESUME:
    series.write("time,phase,wf_normal,wf_tangential,wf_vertical,rod_fx,rod_fy,rod_fz,"
                 "bowl_fx,bowl_fy,bowl_fz,kinetic_energy,unbalanced_force,n_contacts,rod_tip_z,step\n")


def rod_tip_z():
    return min(min(O.bodies[i].state.pos[2] + v[2] for v in O.bodies[i].shape.vertices) for i in ROD_IDS)


def vectors(values):
    """minieigen vectors as an (n, 3) array, component by component: tuple() of one costs about 15 us (it
    iterates until an IndexError crosses into Python), an index about 0.1 us."""
    return np.array([(q[0], q[1], q[2]) for q in values], dtype=float).reshape(-1, 3)


# the balls the impact test looks at, with their State objects (live views of the scene, so emptied when the
# scene is reloaded) and radii; rebuilt every IMPACT_MARGIN / IMPACT_SPEED of simulated time (5 ms); every ball's
# State and radius are gathered once per scene (a rebuild reads only their positions)
impact_near = {}
# a ball further than this from the rod at a rebuild cannot touch it before the next one: it would need 3 mm in
# 5 ms, 0.6 m/s, where the fastest contact starts are about 0.1 m/s
IMPACT_MARGIN = 3e-3
IMPACT_SPEED = 0.6


def rod_gaps(p, r, th, tip):
    """The balls' gaps to the rod (see IMPACT_WINDOW above), m: to the side nearest in angle, gs, whose outward
    normal points at angle a (rad), and to the tip, ga; th (rad) is the carousel's turn."""
    c, s = math.cos(th), math.sin(th)
    dx, dy = p[:, 0] - PATH_RADIUS * c, p[:, 1] - PATH_RADIUS * s
    phi = np.arctan2(dy * c - dx * s, dx * c + dy * s)
    a = th + IMPACT_ALPHA0 + IMPACT_SECTOR * np.floor((phi - IMPACT_ALPHA0) / IMPACT_SECTOR + 0.5)
    return dx * np.cos(a) + dy * np.sin(a) - IMPACT_APOTHEM - r, tip - p[:, 2] - r, a


def impacts():
    """Every step in IMPACT_WINDOW: the balls that start touching the rod (see IMPACT_WINDOW above)."""
    t_p = O.time - state["t_process"]
    if t_p < IMPACT_WINDOW[0]:
        return
    if t_p >= IMPACT_WINDOW[1]:
        impacter.dead = True
        impact_file.flush()
        return
    axis, angle = O.bodies[ROD_IDS[0]].state.ori.toAxisAngle()  # the carousel's turn so far
    th = angle if axis[2] >= 0 else -angle
    if O.time >= state.get("impact_refresh", -1.0) or not impact_near:
        if "all_states" not in impact_near:
            every = [O.bodies[i] for i in SPHERE_IDS]
            impact_near.update(all_states=[b.state for b in every], all_radii=np.array([b.shape.radius for b in every]))
        tip, every, r = rod_tip_z(), impact_near["all_states"], impact_near["all_radii"]
        gs, ga, _ = rod_gaps(vectors([x.pos for x in every]), r, th, tip)
        near = np.flatnonzero(np.maximum(gs, ga) < IMPACT_MARGIN)
        impact_near.update(ids=[SPHERE_IDS[k] for k in near], states=[every[k] for k in near], radius=r[near], tip=tip)
        state["impact_refresh"] = O.time + IMPACT_MARGIN / IMPACT_SPEED
    ids, states, r = impact_near["ids"], impact_near["states"], impact_near["radius"]
    if not ids:
        return
    p = vectors([x.pos for x in states])
    v = vectors([x.vel for x in states])
    gs, ga, a = rod_gaps(p, r, th, impact_near["tip"])
    us = -((v[:, 0] + 2.0 * p[:, 1]) * np.cos(a) + (v[:, 1] - 2.0 * p[:, 0]) * np.sin(a))
    side = gs > ga
    g, u = np.where(side, gs, ga), np.where(side, us, v[:, 2])
    for k in np.flatnonzero((g <= 0) & (g + u * O.dt > 0)):
        impact_file.write("%.17g,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d\n" % (
            O.time, ids[k], r[k], p[k, 0], p[k, 1], p[k, 2], v[k, 0], v[k, 1], v[k, 2], g[k], u[k], O.iter))


def summed_force(ids):
    f = Vector3(0, 0, 0)
    for i in ids:
        f += O.forces.f(i)
    return f


def kinetic_energy():
    return sum(0.5 * O.bodies[i].state.mass * O.bodies[i].state.vel.squaredNorm() for i in SPHERE_IDS)


def bed_height():
    """Level of the bed, m: the height a flat bed of the same balls would have at the solid
    fraction measured in the bed's core (0.2 to 0.6 of the highest ball top)."""
    z = np.array([O.bodies[i].state.pos[2] for i in SPHERE_IDS])
    r = np.array([O.bodies[i].shape.radius for i in SPHERE_IDS])
    top = float(np.max(z + r))

    def slab_volume(z0, z1):
        cap = lambda u: np.pi * (r ** 2 * u - u ** 3 / 3.0)  # noqa: E731
        return float(np.sum(cap(np.clip(z1 - z, -r, r)) - cap(np.clip(z0 - z, -r, r))))

    area = math.pi * BOWL_RADIUS ** 2
    core_fraction = slab_volume(0.2 * top, 0.6 * top) / (area * 0.4 * top)
    return float(np.sum(4.0 / 3.0 * np.pi * r ** 3)) / (core_fraction * area)


def workpiece_frame(force):
    """Force on the rod as [along its velocity, horizontal outward, vertical], N."""
    theta = 2.0 * (O.time - state["t_process"])  # the rod starts at angle 0 (+x)
    ev = (-math.sin(theta), math.cos(theta))
    er = (math.cos(theta), math.sin(theta))
    return (force[0] * ev[0] + force[1] * ev[1], force[0] * er[0] + force[1] * er[1], force[2])


def record():
    if O.time <= state["last_record"]:
        return  # already sampled at this step (a phase change records once more)
    state["last_record"] = O.time
    phase = state["phase"]
    fr = summed_force(ROD_IDS)
    fb = summed_force(BOWL_IDS)
    wn, wt, wv = workpiece_frame(fr) if phase == 3 else (float("nan"),) * 3
    if phase >= 1:
        for k, i in enumerate(ROD_IDS):
            f = O.forces.f(i).norm()
            if f > 0:
                rod_intensity[k] += f * state["record_interval"]
                rod_contact_count[k] += 1
    series.write("%.9g,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d,%.9g,%d\n" % (
        O.time, phase, wn, wt, wv, fr[0], fr[1], fr[2], fb[0], fb[1], fb[2], kinetic_energy(),
        utils.unbalancedForce(), O.interactions.countReal(), rod_tip_z(), O.iter))
    series.flush()
    check_stability()


def check_stability():
    for i in SPHERE_IDS:
        p = O.bodies[i].state.pos
        if not (p[0] == p[0] and p[2] == p[2]):
            return stop("unstable", "a ball position became NaN: the time step is too large for the contact stiffness; "
                                    "lower numerics.timestep_factor")
        if p[2] < -0.5 * BOWL_HEIGHT or p[0] ** 2 + p[1] ** 2 > (2 * BOWL_RADIUS) ** 2:
            return stop("unstable", "ball %d left the bowl (at %s m): contacts were too stiff for the time step or "
                                    "a mesh let it through; lower numerics.timestep_factor" % (i, tuple(p)))


def write_network(index):
    id1, id2, fn, fn_vec, ft, p1, p2, role2 = [], [], [], [], [], [], [], []
    for I in O.interactions:
        if not I.isReal:
            continue
        a, b = I.id1, I.id2
        if a in ROLE and b not in ROLE:
            a, b = b, a
        point_a = O.bodies[a].state.pos
        point_b = O.bodies[b].state.pos if b not in ROLE else I.geom.contactPoint
        sign = 1.0 if a == I.id1 else -1.0
        id1.append(a)
        id2.append(b)
        fn.append(I.phys.normalForce.dot(I.geom.normal))  # > 0 in compression
        fn_vec.append(tuple(sign * I.phys.normalForce))
        ft.append(tuple(sign * I.phys.shearForce))
        p1.append(tuple(point_a))
        p2.append(tuple(point_b))
        role2.append(ROLE.get(b, 0))
    np.savez(os.path.join(OUT, "network_%d.npz" % index), time=O.time, process_time=O.time - state["t_process"],
             id1=np.array(id1, dtype=np.int64), id2=np.array(id2, dtype=np.int64),
             normal_force=np.array(fn, dtype=float), normal_force_vector=np.array(fn_vec).reshape(-1, 3),
             tangential_force=np.array(ft).reshape(-1, 3),
             point1=np.array(p1).reshape(-1, 3), point2=np.array(p2).reshape(-1, 3),
             body2_role=np.array(role2, dtype=np.int8))
    write_frame("frame_%d.npz" % index)


def write_frame(name):
    np.savez(os.path.join(OUT, name), time=O.time,
             positions=np.array([tuple(O.bodies[i].state.pos) for i in SPHERE_IDS]),
             velocities=np.array([tuple(O.bodies[i].state.vel) for i in SPHERE_IDS]),
             radii=np.array([O.bodies[i].shape.radius for i in SPHERE_IDS]),
             rod_vertices=np.array([[tuple(O.bodies[i].state.pos + O.bodies[i].state.ori * v)
                                     for v in O.bodies[i].shape.vertices] for i in ROD_IDS]).reshape(-1, 3, 3),
             rod_intensity=rod_intensity, rod_contact_count=rod_contact_count)


def write_status():
    with open(os.path.join(OUT, "status.json"), "w") as fh:
        json.dump({"status": state["status"], "message": state["message"], "n_steps": O.iter, "dt": O.dt,
                   "time": O.time, "phase": PHASES[state["phase"]], "bed_height": state["bed_height"],
                   "settled": state["settled"], "process_start_time": state["t_process"],
                   "wall_time_s": time.time() - WALL_START,
                   "phase_wall_s": state["phase_wall"], "yade_version": yade.config.version}, fh, indent=1)


def stop(status, message):
    state["status"], state["message"] = status, message
    if impact_file is not None:
        impact_file.flush()
    print("STATUS %s %s" % (status, message), flush=True)
    write_frame("final.npz")
    write_status()
    halt_after_this_step()


def halt_after_this_step():
    """Stop the loop once the running step is complete. O.pause() from an engine would stop it too, but O.wait()
    then returns at once, while the step's later engines and its iter/time update still run in Yade's worker
    thread: a checkpoint saved then caught the scene mid-step or after it, as the threads happened to be
    scheduled, and a resumed run left the uninterrupted one at the next checkpoint."""
    O.stopAtIter = O.iter + 1


def next_phase(new_phase):
    state["phase_wall"][PHASES[state["phase"]]] = time.time() - WALL_START
    state["phase"], state["t_phase"] = new_phase, O.time
    print("PHASE %s t=%.6g s step=%d" % (PHASES[new_phase], O.time, O.iter), flush=True)


def report_progress():
    now = time.time()
    if state["phase"] == 3 and not state["probe_done"]:
        if state["probe_start"] is None:
            state["probe_start"] = (now, O.iter)
        elif O.iter - state["probe_start"][1] >= 500:
            per_step = (now - state["probe_start"][0]) / (O.iter - state["probe_start"][1])
            estimate = now - WALL_START + per_step * (state["planned"] - O.iter)
            print("TIMING s_per_step=%.6g planned_steps=%d estimate_s=%.6g" % (per_step, state["planned"], estimate),
                  flush=True)
            state["probe_done"] = True
    if now - state["last_progress"] > 1.0:
        print("PROGRESS step=%d of %d phase=%s t=%.6g" % (O.iter, state["planned"], PHASES[state["phase"]], O.time),
              flush=True)
        state["last_progress"] = now


def control():
    report_progress()
    phase = state["phase"]
    if phase == 0:
        vmax = max(O.bodies[i].state.vel.norm() for i in SPHERE_IDS)
        at_rest = O.time > 0.05 and utils.unbalancedForce() < SETTLE_UNBALANCED and vmax < SETTLE_MAX_SPEED
        if at_rest or O.time >= SETTLE_MAX_TIME:
            state["settled"] = bool(at_rest)
            state["bed_height"] = bed_height()
            record()
            write_frame("settled.npz")
            newton.damping = 0.0
            # Park the rod 1 mm above the highest ball, then push it in.
            top = max(O.bodies[i].state.pos[2] + O.bodies[i].shape.radius for i in SPHERE_IDS)
            shift = top + 1e-3 - rod_tip_z()
            for i in ROD_IDS:
                O.bodies[i].state.pos += Vector3(0, 0, shift)
            state["tip_target"] = state["bed_height"] - SUBMERSION_DEPTH
            push.dead = False
            travel = top + 1e-3 - state["tip_target"]
            remaining = (travel / 0.05 + RELAX_TIME) / DT_SETTLE + PROCESS_DURATION / DT
            if STIFFEN:
                remaining += (STIFFEN_TIME + RELAX_TIME) / DT
            state["planned"] = O.iter + int(remaining)
            next_phase(1)
    elif phase == 1:
        if rod_tip_z() <= state["tip_target"]:
            push.dead = True
            for i in ROD_IDS:
                O.bodies[i].state.vel = Vector3(0, 0, 0)
            next_phase(2)
    elif phase == 2:
        stage, elapsed = state["relax_stage"], O.time - state["t_stage"]
        if stage == 0 and O.time - state["t_phase"] >= RELAX_TIME and STIFFEN:
            start_stiffening()
        elif stage == 1:
            stiffen(min(1.0, elapsed / STIFFEN_TIME))
            if elapsed >= STIFFEN_TIME:
                newton.damping = 0.0
                state["relax_stage"], state["t_stage"] = 2, O.time
                print("STIFFENED t=%.6g s step=%d: relaxing undamped for %g s" % (O.time, O.iter, RELAX_TIME), flush=True)
        elif (stage == 0 and O.time - state["t_phase"] >= RELAX_TIME) or (stage == 2 and elapsed >= RELAX_TIME):
            state["t_process"] = O.time
            drag.dead = False
            impacter.dead = not IMPACT_WINDOW
            next_phase(3)
    elif phase == 3:
        t_p = O.time - state["t_process"]
        while state["next_network"] < len(NETWORK_TIMES) and t_p >= NETWORK_TIMES[state["next_network"]] - 0.5 * O.dt:
            write_network(state["next_network"])
            state["next_network"] += 1
        if t_p >= PROCESS_DURATION - 0.5 * O.dt:
            state["phase_wall"]["process"] = time.time() - WALL_START
            stop("ok", "")
        elif CHECKPOINT_EVERY and t_p >= (state["checkpoints"] + 1) * CHECKPOINT_EVERY - 0.5 * O.dt:
            state["checkpoint_due"] = True
            halt_after_this_step()  # the scene is saved between two steps (write_checkpoint)


def write_checkpoint():
    """The whole scene (O.save, two files in turn: one is always whole) and the script's state, then
    checkpoint.json renamed into place: 'orchestrator run --resume' continues from here."""
    state["checkpoints"] += 1
    state["checkpoint_due"] = False
    path = os.path.join(OUT, "checkpoint_%d.yade.gz" % (state["checkpoints"] % 2))
    series.flush()
    if impact_file is not None:
        impact_file.flush()
    O.save(path)
    tmp = os.path.join(OUT, "checkpoint.tmp")
    with open(tmp, "w") as fh:
        json.dump({"scene": path, "step": O.iter, "time": O.time, "state": state,
                   "rod_intensity": rod_intensity.tolist(), "rod_contact_count": rod_contact_count.tolist()}, fh)
    os.replace(tmp, os.path.join(OUT, "checkpoint.json"))
    # go on from the file, as 'run --resume' would: O.load rebuilds the collider's bounds and lists, and a run
    # that went on from its memory instead would sum the forces of later contacts in another order (round-off
    # the granular bed amplifies); so a resumed run is the uninterrupted one, step for step
    O.load(path)
    impact_near.clear()  # its State objects belong to the scene before the reload




def start_stiffening():
    """From the settling stiffness and step to the process ones: the new step and sampling periods
    now, the contact stiffness over STIFFEN_TIME with numerical damping (stiffen())."""
    O.dt = DT
    controller.iterPeriod = 36
    recorder.iterPeriod = 72
    state["record_interval"] = DT * 72
    newton.damping = 0.4
    state["relax_stage"], state["t_stage"] = 1, O.time
    print("STIFFEN x%g over %g s from t=%.6g s, dt %g -> %g s" % (STIFFEN_FACTOR, STIFFEN_TIME, O.time,
                                                                DT_SETTLE, DT), flush=True)


def stiffen(fraction):
    """Scale every contact's Hertz-Mindlin stiffness (kno, kso; both proportional to E) and the
    materials' E (for contacts made from now on) to STIFFEN_FACTOR**fraction of the settling values.
    Damping ratios (betan, betas) do not depend on E and stay."""
    factor = STIFFEN_FACTOR ** fraction
    ratio = factor / state["applied_factor"]
    if ratio == 1.0:
        return
    for I in O.interactions:
        if I.isReal:
            I.phys.kno *= ratio
            I.phys.kso *= ratio
    for m in O.materials:
        m.young = YOUNG_SETTLE[m.id] * factor
    state["applied_factor"] = factor


def run_probe(steps):
    """Timing probe: the balls on a touching simple-cubic lattice (about the coordination of a
    settled bed), a few steps, then the estimated wall time of the whole run."""
    r = max(O.bodies[i].shape.radius for i in SPHERE_IDS)
    d = 2.0 * r * (1.0 - 1e-5)
    xs = np.arange(-BOWL_RADIUS + r, BOWL_RADIUS - r, d)
    layer = [(x, y) for x in xs for y in xs if x * x + y * y <= (BOWL_RADIUS - r) ** 2]
    for n, i in enumerate(SPHERE_IDS):
        x, y = layer[n % len(layer)]
        O.bodies[i].shape.radius = r
        O.bodies[i].state.pos = Vector3(x, y, r + d * (n // len(layer)))
        O.bodies[i].state.vel = Vector3(0, 0, 0)
    controller.dead = recorder.dead = True
    O.run(50, True)
    start = time.time()
    O.run(steps, True)
    per_step = (time.time() - start) / steps
    print("TIMING s_per_step=%.6g planned_steps=%d estimate_s=%.6g" % (per_step, PLANNED_STEPS,
                                                                      per_step * PLANNED_STEPS), flush=True)


if "--probe" in sys.argv:
    run_probe(int(sys.argv[sys.argv.index("--probe") + 1]))
    sys.exit(0)

O.run()
O.wait()
while state.get("checkpoint_due"):
    write_checkpoint()
    O.run()
    O.wait()
series.close()
if state["status"] == "ok" and state["phase"] != 3:
    stop("failed", "the run ended before the process phase finished")
sys.exit(0 if state["status"] == "ok" else 3)
