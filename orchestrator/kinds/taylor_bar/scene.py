"""The Taylor bar's scene: the bar as an SPH case of kind sph_flow (one johnson_cook material, a cubic lattice cut
to the cylinder, every particle at -speed along z) above a penalty wall at z = 0 that pushes along its normal only
(frictionless). The wall's stiffness is set from the elastic impact pressure, so that its range stays one dx at
any resolution. SI units."""

from __future__ import annotations

import math

from orchestrator.kinds.sph_flow.case import SphFlowCase
from orchestrator.kinds.sph_flow.scene import SphScene, build_sph_flow
from orchestrator.kinds.taylor_bar.case import TaylorBarCase


def wall_penalty(case: TaylorBarCase) -> dict:
    """The wall's eq. 14 (range R = dx, zero force at s = 0.99 R so that it barely pulls, F(0) = psi):
    psi = wall_load_factor x rho0 c_L v dx^2, N, with c_L the longitudinal wave speed."""
    m, dx = case.material, case.numerics.dx
    # the run's impedance: f rho0 and c_L / sqrt(f) with a mass scaling f
    load = m.inertial_density() * m.solid.wave_speed(m.density) / m.mass_scaling**0.5 * case.bar.speed * dx**2
    return {"range": dx, "s": 0.99 * dx, "psi": case.numerics.wall_load_factor * load}


def flow_case(case: TaylorBarCase) -> SphFlowCase:
    """The sph_flow case of the bar and its wall. The bar's bottom layer starts one dx above the wall (at the edge
    of the wall's range); the lattice is symmetric about the axis."""
    bar, dx, m = case.bar, case.numerics.dx, case.material
    half = (math.floor(bar.radius / dx) + 1) * dx  # the lattice's half-width: sites at +-(k + 1/2) dx
    reach = 3.0 * bar.radius + 4.0 * dx  # the mushroomed face stays well inside
    duration = case.simulation.duration
    frame = duration / case.simulation.frames
    av = case.numerics.artificial_viscosity
    data = {
        "case": {"kind": "sph_flow", "name": case.case.name, "engine": "sph",
                 "description": case.case.description or "Taylor bar"},
        "domain": {"dimension": 3, "lo": [-reach, -reach, -4.0 * dx], "hi": [reach, reach, 1.3 * bar.length]},
        "fluid": {"max_speed": bar.speed},
        "materials": [m.case_material()],
        "physics": {"terms": ["artificial_viscosity", "wall_penalty"],
                    "artificial_viscosity": {"alpha": av.alpha, "beta": av.beta},
                    "wall_penalty": wall_penalty(case)},
        "blocks": [{"name": "bar", "kind": "fluid", "material": m.name, "lo": [-half, -half, 0.5 * dx],
                    "hi": [half, half, 0.5 * dx + bar.length], "velocity": [0.0, 0.0, -bar.speed],
                    "cylinder": {"axis": 2, "center": [0.0, 0.0, 0.0], "radius": bar.radius}}],
        "walls": [{"shape": "plane", "name": "wall", "center": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0],
                   "u": [1.0, 0.0, 0.0], "half_extents": [reach, reach]}],
        "numerics": {"dx": dx, "h_over_dx": case.numerics.h_over_dx, "threads": case.numerics.threads},
        "simulation": {"duration": duration},
        "output": {"frame_interval": frame, "series_interval": frame / case.simulation.series_per_frame},
    }
    return SphFlowCase.model_validate(data)


def build_taylor_bar(case: TaylorBarCase) -> SphScene:
    """The bar's particles, its wall mesh and the deck's settings (an sph_flow scene)."""
    return build_sph_flow(flow_case(case))
