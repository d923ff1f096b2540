"""The crater's scene: the target box as an SPH case of kind sph_flow (one johnson_cook material on a cubic
lattice, its top face at z = 0, on `held_layers` layers of fixed particles) and the sphere as a rigid impactor
(engines/sph/README.md, "Rigid impactors") starting a quarter dx above the top particles' extent, moving -z. SI
units."""

from __future__ import annotations

from orchestrator.kinds.crater.case import CraterCase
from orchestrator.kinds.sph_flow.case import SphFlowCase
from orchestrator.kinds.sph_flow.case_impact import impact_case
from orchestrator.kinds.sph_flow.scene import SphScene, build_sph_flow

#: The gap between the sphere and the top particles' extent at the start, in dx.
START_GAP = 0.25


def sphere_centre_z(case: CraterCase) -> float:
    """The sphere's starting centre height, m (the top particles reach z = 0)."""
    return 0.5 * case.sphere.diameter + START_GAP * case.numerics.dx


def flow_case(case: CraterCase) -> SphFlowCase:
    """The sph_flow case of the target, its held support and the sphere."""
    sphere = [0.0, 0.0, sphere_centre_z(case), 0.5 * case.sphere.diameter]
    impactor = {"name": "sphere", "spheres": [sphere], "density": case.sphere.density,
                "velocity": [0.0, 0.0, -case.sphere.speed], "kinematic": case.sphere.kinematic}
    return impact_case(case, impactor, case.sphere.speed, "Hutchings crater")


def build_crater(case: CraterCase) -> SphScene:
    """The target's particles, the sphere and the deck's settings (an sph_flow scene)."""
    return build_sph_flow(flow_case(case))
