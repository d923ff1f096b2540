"""The channel's scene: an SPH case of kind sph_flow (kinds/sph_flow) on one cubic lattice. Where blocks overlap
the first one that covers a site takes it, so the workpiece, its supporting wall and the walls are listed before
the medium, which fills the rest of the gap. The bottom wall under the workpiece and its support is of the
workpiece's material (it holds the solid), the rest of the walls of the medium's. The grain is carved from the
medium's sites inside its sphere (case_grains.py) and touches the workpiece through eq. G8. A flow plane across
the whole gap upstream of the grain's start records the medium's flow rate. SI units."""

from __future__ import annotations

import numpy as np

from orchestrator.kinds.afm_channel.case import AfmChannelCase
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
    wall = c.wall_layers * dx
    av = case.numerics.artificial_viscosity
    frame = case.simulation.duration / case.simulation.frames
    data = {
        "case": {"kind": "sph_flow", "name": case.case.name, "engine": "sph",
                 "description": case.case.description or "abrasive-flow channel with a grain and a workpiece"},
        "domain": {"dimension": 3, "lo": [0.0, 0.0, 0.0], "hi": [c.length, c.width, case.height()],
                   "periodic": [0, 1]},
        "fluid": {"max_speed": case.max_speed()},
        "materials": [{"name": MEDIUM, "model": "newtonian", "density": m.density,
                       "viscosity": m.viscosity / m.density, "sound_speed": case.sound_speed()}, case.workpiece.case_material()],
        "physics": {"terms": ["morris_viscosity", "artificial_viscosity", "body_force"],
                    "body_force": [m.body_force, 0.0, 0.0], "body_force_on": "fluids",
                    "artificial_viscosity": {"alpha": av.alpha, "beta": av.beta}},
        "blocks": blocks(case),
        "grains": [{"name": GRAIN, "radius": 0.5 * g.diameter, "density": g.density,
                    "centre": [g.start, 0.5 * c.width, wall + g.height]}],
        "grain_contact": {"solid_stiffness_factor": case.numerics.contact_stiffness},
        "numerics": {"dx": dx, "h_over_dx": case.numerics.h_over_dx, "threads": case.numerics.threads,
                     "max_density_deviation": case.numerics.max_density_deviation},
        "simulation": {"duration": case.simulation.duration},
        "output": {"frame_interval": frame, "series_interval": frame / case.simulation.series_per_frame,
                   "flow_planes": [{"name": SECTION, "center": [section_x(case), 0.5 * c.width, wall + 0.5 * c.gap],
                                    "normal": [1.0, 0.0, 0.0], "half_extents": [0.5 * c.width, 0.5 * c.gap],
                                    "u": [0.0, 1.0, 0.0]}]},
    }
    return SphFlowCase.model_validate(data)


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
    return build_sph_flow(flow_case(case))
