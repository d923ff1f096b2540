"""The crater's scene: the target box as an SPH case of kind sph_flow (one johnson_cook material on a cubic
lattice, its top face at z = 0, on `held_layers` layers of fixed particles) and the sphere as a rigid impactor
(engines/sph/README.md, "Rigid impactors") starting a quarter dx above the top particles' extent, moving -z. SI
units."""

from __future__ import annotations

from orchestrator.kinds.crater.case import CraterCase
from orchestrator.kinds.sph_flow.case import SphFlowCase
from orchestrator.kinds.sph_flow.scene import SphScene, build_sph_flow

#: The gap between the sphere and the top particles' extent at the start, in dx.
START_GAP = 0.25
#: The engine's stop on |rho / rho0 - 1|: a solid under a contact compresses by p / K, up to 10 % and more in a
#: soft one (the fluids' 10 % is a blow-up detector for a weakly compressible liquid).
MAX_DENSITY_DEVIATION = 0.4


def sphere_centre_z(case: CraterCase) -> float:
    """The sphere's starting centre height, m (the top particles reach z = 0)."""
    return 0.5 * case.sphere.diameter + START_GAP * case.numerics.dx


def flow_case(case: CraterCase) -> SphFlowCase:
    """The sph_flow case of the target, its held support and the sphere."""
    dx, m, (lx, ly, lz) = case.numerics.dx, case.material, case.target.size
    support = case.target.held_layers * dx
    top = sphere_centre_z(case) + 0.5 * case.sphere.diameter
    duration = case.simulation.duration
    frame = duration / case.simulation.frames
    av = case.numerics.artificial_viscosity
    data = {
        "case": {"kind": "sph_flow", "name": case.case.name, "engine": "sph",
                 "description": case.case.description or "Hutchings crater"},
        "domain": {"dimension": 3, "lo": [-0.5 * lx - 2 * dx, -0.5 * ly - 2 * dx, -lz - support - 2 * dx],
                   "hi": [0.5 * lx + 2 * dx, 0.5 * ly + 2 * dx, top + 2 * dx]},
        "fluid": {"max_speed": case.sphere.speed},
        "materials": [m.case_material()],
        "physics": {"terms": ["artificial_viscosity"],
                    "artificial_viscosity": {"alpha": av.alpha, "beta": av.beta}},
        "blocks": [{"name": "target", "kind": "fluid", "material": m.name, "lo": [-0.5 * lx, -0.5 * ly, -lz],
                    "hi": [0.5 * lx, 0.5 * ly, 0.0]},
                   {"name": "support", "kind": "boundary", "material": m.name,
                    "lo": [-0.5 * lx, -0.5 * ly, -lz - support], "hi": [0.5 * lx, 0.5 * ly, -lz]}],
        "impactors": [{"name": "sphere", "spheres": [[0.0, 0.0, sphere_centre_z(case), 0.5 * case.sphere.diameter]],
                       "density": case.sphere.density, "velocity": [0.0, 0.0, -case.sphere.speed],
                       "kinematic": case.sphere.kinematic, "stiffness_factor": case.numerics.contact_stiffness}],
        "numerics": {"dx": dx, "h_over_dx": case.numerics.h_over_dx, "threads": case.numerics.threads,
                     "max_density_deviation": MAX_DENSITY_DEVIATION},
        "simulation": {"duration": duration},
        "output": {"frame_interval": frame, "series_interval": frame / case.simulation.series_per_frame},
    }
    return SphFlowCase.model_validate(data)


def build_crater(case: CraterCase) -> SphScene:
    """The target's particles, the sphere and the deck's settings (an sph_flow scene)."""
    return build_sph_flow(flow_case(case))
