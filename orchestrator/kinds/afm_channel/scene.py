"""The channel's scene: an SPH case of kind sph_flow (kinds/sph_flow) on one cubic lattice. Where blocks overlap
the first one that covers a site takes it, so the workpiece, its supporting wall and the walls are listed before
the medium, which fills the rest of the gap. The bottom wall under the workpiece and its support is of the
workpiece's material (it holds the solid), the rest of the walls of the medium's. The grain is carved from the
medium's sites inside its sphere (case_grains.py) and touches the workpiece through eq. G8. A flow plane across
the whole gap upstream of the grain's start records the medium's flow rate. SI units."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from orchestrator.kinds.afm_channel.case import AfmChannelCase
from orchestrator.kinds.afm_channel.medium import developed_state, developed_velocity
from orchestrator.kinds.sph_flow.case import SphFlowCase
from orchestrator.kinds.sph_flow.scene import SphScene, build_sph_flow

#: How far (in dx) the floor of the workpiece's material reaches upstream of its front face: beyond the kernel's
#: support, so that no workpiece particle has a wall particle of the medium's material within reach.
FLOOR_AHEAD = 3
#: The medium's material name in the sph_flow case.
MEDIUM = "medium"
#: The grain's name (series grain_grain_*).
GRAIN = "grain"
#: The flow plane's name (series flow_rate_section).
SECTION = "section"


def blocks(case: AfmChannelCase) -> list[dict]:
    """The sph_flow blocks, first-come on shared sites: workpiece, support, the walls, the medium."""
    c, w, dx = case.channel, case.workpiece, case.numerics.dx
    wall = c.wall_layers * dx
    top, end = case.height() - wall, case.support_end()

    def box(name, kind, material, lo, hi):
        return {"name": name, "kind": kind, "material": material, "lo": list(lo), "hi": list(hi)}

    return [
        box("workpiece", "fluid", w.name, (w.front, 0.0, wall), (w.front + w.length, c.width, wall + w.height)),
        box("support", "boundary", w.name, (w.front + w.length, 0.0, wall), (end, c.width, wall + w.height)),
        box("floor_under_workpiece", "boundary", w.name, (w.front - FLOOR_AHEAD * dx, 0.0, 0.0), (end, c.width, wall)),
        box("bottom_wall", "boundary", MEDIUM, (0.0, 0.0, 0.0), (c.length, c.width, wall)),
        box("top_wall", "boundary", MEDIUM, (0.0, 0.0, top), (c.length, c.width, case.height())),
        box(MEDIUM, "fluid", MEDIUM, (0.0, 0.0, wall), (c.length, c.width, top)),
    ]


def flow_case(case: AfmChannelCase) -> SphFlowCase:
    """The sph_flow case of the channel, its workpiece and the grain (z shifted by the bottom wall's thickness)."""
    c, m, g, dx = case.channel, case.medium, case.grain, case.numerics.dx
    wall, s = c.wall_layers * dx, case.numerics.inertia_scaling
    av = case.numerics.artificial_viscosity
    frame = case.simulation.duration / case.simulation.frames
    data = {
        "case": {"kind": "sph_flow", "name": case.case.name, "engine": "sph",
                 "description": case.case.description or "abrasive-flow channel with a grain and a workpiece"},
        "domain": {"dimension": 3, "lo": [0.0, 0.0, 0.0], "hi": [c.length, c.width, case.height()],
                   "periodic": [0, 1]},
        "fluid": {"max_speed": case.max_speed()},
        "materials": [medium_material(case), case.workpiece.case_material()],
        "physics": {"terms": ["morris_viscosity", "artificial_viscosity", "body_force"],
                    "body_force": [m.body_force / s, 0.0, 0.0], "body_force_on": "fluids",
                    "artificial_viscosity": {"alpha": av.alpha, "beta": av.beta}},
        "blocks": blocks(case),
        "grains": [{"name": GRAIN, "radius": 0.5 * g.diameter, "density": g.density * s,
                    "centre": [g.start, 0.5 * c.width, wall + g.height], "velocity": [grain_speed(case), 0.0, 0.0]}],
        "grain_contact": {"solid_stiffness_factor": case.numerics.contact_stiffness},
        "numerics": {"dx": dx, "h_over_dx": case.numerics.h_over_dx, "threads": case.numerics.threads,
                     "max_density_deviation": case.numerics.max_density_deviation}
                    | ({"dt": case.timestep()} if m.modes else {}),
        "simulation": {"duration": case.simulation.duration},
        "output": {"frame_interval": frame, "series_interval": frame / case.simulation.series_per_frame,
                   "flow_planes": [{"name": SECTION, "center": [section_x(case), 0.5 * c.width, wall + 0.5 * c.gap],
                                    "normal": [1.0, 0.0, 0.0], "half_extents": [0.5 * c.width, 0.5 * c.gap],
                                    "u": [0.0, 1.0, 0.0]}]},
    }
    return SphFlowCase.model_validate(data)


def medium_material(case: AfmChannelCase) -> dict:
    """The medium's [[materials]] table: Newtonian, or PTT with its solvent as the Morris term and a background
    pressure of the steady flow's largest stress (the first normal stress difference: tension along the streamlines
    beyond the pressure is SPH's tensile instability; a periodic PTT channel without it went unstable within 10
    relaxation times even at Wi 0.8, and held with it); its density times numerics.inertia_scaling."""
    m, rho = case.medium, case.scaled_density()
    if not m.modes:
        return {"name": MEDIUM, "model": "newtonian", "density": rho, "viscosity": m.viscosity / rho,
                "sound_speed": case.sound_speed()}
    return {"name": MEDIUM, "model": "ptt", "density": rho, "sound_speed": case.sound_speed(), "epsilon": m.epsilon,
            "solvent_viscosity": m.viscosity, "background_pressure": case.steady_stress(),
            "modes": [{"relaxation_time": k.relaxation_time, "viscosity": k.viscosity} for k in m.modes]}


def grain_speed(case: AfmChannelCase) -> float:
    """The grain's starting speed along x, m/s: 0 in a medium at rest, else the steady flow's at its centre."""
    if not case.medium.steady_start:
        return 0.0
    flow = case.cell()
    return float(developed_velocity(case.medium.law(), case.grain.height, flow.wide_gap, flow.wide_gradient))


def steady_start(case: AfmChannelCase, scene: SphScene) -> SphScene:
    """The scene with the medium in the cell's steady flow (medium.py): each medium particle at the developed
    profile of its part (the passage over the workpiece and its support, or the wide part) and, with modes, each
    mode's steady stresses (tau_xz, tau_xx) at its shear rate (the grain's speed is set in flow_case). The pressure is left
    at rest: it settles within a sound crossing of the cell."""
    c, w, dx = case.channel, case.workpiece, case.numerics.dx
    wall, flow, law = c.wall_layers * dx, case.cell(), case.medium.law()
    x = np.asarray(scene.positions)
    medium = (np.asarray(scene.material) == 0) & (np.asarray(scene.kind) == 0)  # the grain moves as set in flow_case
    over = (x[:, 0] > w.front) & (x[:, 0] < case.support_end())
    velocities = np.array(scene.velocities, dtype=float)
    stresses = np.zeros((len(x), len(law.modes), 3, 3))
    for part, gap, gradient, floor in ((over, flow.narrow_gap, flow.narrow_gradient, wall + w.height),
                                       (~over, flow.wide_gap, flow.wide_gradient, wall)):
        rows = medium & part
        velocities[rows, 0], stresses[rows] = developed_state(law, x[rows, 2] - floor, gap, gradient, 3)
    state = {"mode_stress": stresses.reshape(len(x), -1)} if law.modes else None
    return replace(scene, velocities=velocities, state=state)


def section_x(case: AfmChannelCase) -> float:
    """x of the flow plane: half way between the cell's start and the grain's start's upstream side, on the
    lattice's mid-plane between two columns, m."""
    dx = case.numerics.dx
    x = 0.5 * max(case.grain.start - 0.5 * case.grain.diameter, dx)
    return round(x / dx) * dx


def workpiece_mask(case, first: dict) -> np.ndarray:
    """Which rows are the workpiece's (moving particles starting inside its box)."""
    w, wall = case.workpiece, case.channel.wall_layers * case.numerics.dx
    x = np.asarray(first["positions"], dtype=float)
    inside = ((x[:, 0] > w.front) & (x[:, 0] < w.front + w.length) & (x[:, 2] > wall)
              & (x[:, 2] < wall + w.height))
    return inside & (np.asarray(first["kind"]) == 0)


def build_afm_channel(case: AfmChannelCase) -> SphScene:
    """The channel's particles, the grain and the deck's settings (an sph_flow scene)."""
    scene = build_sph_flow(flow_case(case))
    return steady_start(case, scene) if case.medium.steady_start else scene
