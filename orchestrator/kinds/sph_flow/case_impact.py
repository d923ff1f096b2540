"""What the solid impact scenes share (the crater, the grain scratch): a Johnson-Cook box on held particle layers,
its top face at z = 0, with a rigid impactor over it (case_impactors.py); the numerics and the run's length; and
the sph_flow case they make. SI units.

A kind's case holds `case` (CaseMeta), `target` (ImpactTarget or a subclass), `material`
(case_solids.SolidBody), `numerics` (ImpactNumerics) and `simulation` (ImpactSimulation).
"""

from __future__ import annotations

import numpy as np
from pydantic import Field

from orchestrator.case.common import Frozen, Positive
from orchestrator.kinds.sph_flow.case import SphFlowCase
from orchestrator.kinds.sph_flow.case_solids import ImpactViscosity


class ImpactTarget(Frozen):
    """The box: its size (each a whole number of numerics.dx) and the held layers under it."""

    size: tuple[Positive, Positive, Positive] = Field(description="x, y and z extent of the box, m")
    held_layers: int = Field(3, ge=1, le=10, description="layers of fixed particles under the box (the support), -")

    def check_lattice(self, dx: float) -> None:
        """ValueError naming target.size unless every extent is a whole number of dx (m)."""
        for axis, length in zip("xyz", self.size):
            layers = length / dx
            if abs(layers - round(layers)) > 1e-6 * layers:
                raise ValueError(f"target.size along {axis} = {length} m is not a whole number of numerics.dx = "
                                 f"{dx} m ({layers:.4g} layers)")


class ImpactNumerics(Frozen):
    """Resolution, kernel, the contact's stiffness and the engine's stop on density."""

    dx: Positive = Field(description="particle spacing, m")
    h_over_dx: float = Field(1.5, ge=1.0, le=3.0, description="smoothing length over spacing, -")
    artificial_viscosity: ImpactViscosity = ImpactViscosity()
    contact_stiffness: float = Field(1.0, gt=0.0, le=20.0, description="the impactor's contact spring over rho0 "
                                     "c_L^2 dx of the target (engines/sph/README.md, eq. I1), -")
    max_density_deviation: float = Field(0.4, gt=0.0, lt=1.0, description="the run stops as unstable when a "
                                         "target particle has |rho/rho0 - 1| above this: a solid under contact "
                                         "compresses by p / K, 10 % and more in a soft one, -")
    threads: int = Field(1, ge=1, le=256, description="OpenMP threads of the engine")


class ImpactSimulation(Frozen):
    """How long the impact runs and what it records."""

    duration: Positive = Field(description="simulated time, s")
    frames: int = Field(8, ge=1, le=1000, description="particle frames over the run (and the start), -")
    series_per_frame: int = Field(20, ge=1, le=1000, description="series records per frame interval, -")


def impact_case(case, impactor: dict, speed: float, description: str) -> SphFlowCase:
    """The sph_flow case of the target box (top face z = 0, centred on the z axis), its held support and one
    impactor ([[impactors]] table of case_impactors.Impactor); speed: the impactor's, m/s (the case's v_max);
    description: the default when the case gives none."""
    dx, m, (lx, ly, lz) = case.numerics.dx, case.material, case.target.size
    support = case.target.held_layers * dx
    spheres = np.asarray(impactor["spheres"], dtype=float)
    lo = np.minimum((spheres[:, :3] - spheres[:, 3:]).min(axis=0), [-0.5 * lx, -0.5 * ly, -lz - support])
    hi = np.maximum((spheres[:, :3] + spheres[:, 3:]).max(axis=0), [0.5 * lx, 0.5 * ly, 0.0])
    frame = case.simulation.duration / case.simulation.frames
    av = case.numerics.artificial_viscosity
    data = {
        "case": {"kind": "sph_flow", "name": case.case.name, "engine": "sph",
                 "description": case.case.description or description},
        "domain": {"dimension": 3, "lo": (lo - 2 * dx).tolist(), "hi": (hi + 2 * dx).tolist()},
        "fluid": {"max_speed": speed},
        "materials": [m.case_material()],
        "physics": {"terms": ["artificial_viscosity"],
                    "artificial_viscosity": {"alpha": av.alpha, "beta": av.beta}},
        "blocks": [{"name": "target", "kind": "fluid", "material": m.name, "lo": [-0.5 * lx, -0.5 * ly, -lz],
                    "hi": [0.5 * lx, 0.5 * ly, 0.0]},
                   {"name": "support", "kind": "boundary", "material": m.name,
                    "lo": [-0.5 * lx, -0.5 * ly, -lz - support], "hi": [0.5 * lx, 0.5 * ly, -lz]}],
        "impactors": [{**impactor, "stiffness_factor": case.numerics.contact_stiffness}],
        "numerics": {"dx": dx, "h_over_dx": case.numerics.h_over_dx, "threads": case.numerics.threads,
                     "max_density_deviation": case.numerics.max_density_deviation},
        "simulation": {"duration": case.simulation.duration},
        "output": {"frame_interval": frame, "series_interval": frame / case.simulation.series_per_frame},
    }
    return SphFlowCase.model_validate(data)
