"""The cantilever plate's scene: an sph_flow scene (one johnson_cook material in 2D plane strain) of the plate's
lattice on 0 < x < L and its clamp, `clamp_layers` columns of fixed boundary particles on the same rows left of
x = 0, with every plate particle given v_y = V c0 f(x) of the first mode (theory.py). The sph_flow case gives a
block one velocity; the mode's velocity field is written into the scene's particle array afterwards, which is what
the engine's particle file carries. SI units."""

from __future__ import annotations

import dataclasses

import numpy as np

from orchestrator.kinds.cantilever_plate.case import CantileverPlateCase
from orchestrator.kinds.cantilever_plate.theory import mode_shape, plate_theory
from orchestrator.kinds.sph_flow.case import SphFlowCase
from orchestrator.kinds.sph_flow.scene import FLUID, SphScene, build_sph_flow


def flow_case(case: CantileverPlateCase) -> SphFlowCase:
    """The sph_flow case of the plate (block 'plate', at rest) and its clamp (block 'clamp', boundary)."""
    plate, dx, m = case.plate, case.numerics.dx, case.material
    theory = plate_theory(case)
    duration = case.simulation.periods * theory["period"]
    frame = theory["period"] / case.simulation.frames_per_period
    half = 0.5 * plate.thickness
    clamp = plate.clamp_layers * dx
    reach = half + plate.length  # room for any swing: the domain only bounds the cell list
    material = {"name": m.name, "model": "johnson_cook", "density": m.density,
                "solid": m.solid.model_dump(exclude_none=True)}
    av = case.numerics.artificial_viscosity
    physics = {"terms": []}
    if av.alpha > 0.0 or av.beta > 0.0:
        physics = {"terms": ["artificial_viscosity"], "artificial_viscosity": {"alpha": av.alpha, "beta": av.beta}}
    data = {
        "case": {"kind": "sph_flow", "name": case.case.name, "engine": "sph",
                 "description": case.case.description or "cantilever plate"},
        "domain": {"dimension": 2, "lo": [-clamp - 4.0 * dx, -reach], "hi": [plate.length + 4.0 * dx, reach]},
        "fluid": {"max_speed": theory["tip_speed"]},
        "materials": [material],
        "physics": physics,
        "blocks": _blocks(case),
        "numerics": {"dx": dx, "h_over_dx": case.numerics.h_over_dx, "cfl": case.numerics.cfl,
                     "threads": case.numerics.threads},
        "simulation": {"duration": duration},
        "output": {"frame_interval": frame, "series_interval": frame},
    }
    return SphFlowCase.model_validate(data)


def _blocks(case: CantileverPlateCase) -> list[dict]:
    """The plate's block (x > 0, moving) and the clamp's (x < 0, fixed boundary particles), on the same rows."""
    plate, dx, name = case.plate, case.numerics.dx, case.material.name
    half, clamp = 0.5 * plate.thickness, plate.clamp_layers * dx
    return [{"name": "plate", "kind": "fluid", "material": name, "lo": [0.0, -half], "hi": [plate.length, half]},
            {"name": "clamp", "kind": "boundary", "material": name, "lo": [-clamp, -half], "hi": [0.0, half]}]


def build_cantilever_plate(case: CantileverPlateCase) -> SphScene:
    """The plate's particles (swinging in the first mode), its clamp and the deck's settings (an sph_flow scene)."""
    scene = build_sph_flow(flow_case(case))
    velocities = np.zeros_like(scene.positions)
    plate = scene.kind == FLUID
    x = scene.positions[plate, 0]
    velocities[plate, 1] = plate_theory(case)["tip_speed"] * mode_shape(x, case.plate.length)
    return dataclasses.replace(scene, velocities=velocities)
