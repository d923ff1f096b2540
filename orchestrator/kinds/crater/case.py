"""The Hutchings crater case (kind "crater"): a hard sphere shot normally onto the top of a Johnson-Cook box whose
bottom rests on a held particle layer (Nutto et al., section III, Fig. 4). The box's top face is z = 0, its axis
the z axis through the sphere's centre. SI units (m, kg, s, Pa, K).

[material] is the target's johnson_cook material (kinds/sph_flow/case_solids.py); [sweep] lists the impact speeds
`verify solids` runs (one run each, sphere.speed set to it); [[expected]] rows check each run against Hutchings'
eq. 20 with the measured mean contact pressure and against energy conservation.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from orchestrator.case.common import CaseMeta, Frozen, Name, Positive
from orchestrator.kinds.sph_flow.case_impact import (
    ImpactNumerics,
    ImpactSimulation,
    ImpactTarget,
)
from orchestrator.kinds.sph_flow.case_solids import SolidBody, check_solid_table

#: The quantities an [[expected]] row can check (analysis.QUANTITIES has their meaning).
CHECKED = ("hutchings_diameter", "energy_balance", "hertz_modulus", "speed_exponent")


class Sphere(Frozen):
    """The ideally hard sphere: its size, density and impact speed (it starts just clear of the top, moving -z)."""

    diameter: Positive = Field(description="diameter 2r, m")
    density: Positive = Field(description="density rho_s, kg/m^3 (it enters eq. 20 through the sphere's energy)")
    speed: Positive = Field(le=2000.0, description="impact speed v, m/s")
    kinematic: bool = Field(False, description="true: an indenter that keeps its speed throughout (the force it "
                                               "needs is recorded: Hertz's check); false: a free sphere")


class TargetMaterial(SolidBody):
    """The target's Johnson-Cook solid."""

    name: Name = Field("target", description="the material's name (it reaches the deck)")


class Sweep(Frozen):
    """The impact speeds of the verification (one run each)."""

    speeds: tuple[Positive, ...] = Field(min_length=1, max_length=20, description="impact speeds, m/s")


class CraterReference(Frozen):
    """What the paper reports beside the checks."""

    source: str = Field(description="where the numbers come from")
    diameter_at_100: Positive | None = Field(None, description="the crater diameter at 100 m/s, m")


class CraterExpected(Frozen):
    """One [[expected]] row: a quantity against its reference, passing within tolerance."""

    quantity: Literal[CHECKED] = Field(description="hutchings_diameter: the crater's rim crest against eq. 20 "
                                       "with the measured mean contact pressure; energy_balance: against 0; "
                                       "hertz_modulus: the contact modulus E* fitted to the force (over the glued "
                                       "block's bonded-layer factor, Dimitriadis et al. 2002) against "
                                       "penetration, against E / (1 - nu^2) of the target; speed_exponent: the "
                                       "slope of log volume_diameter (the cap of the sphere's radius holding the "
                                       "crater's volume) against log speed over the [sweep], against eq. 20's 1/2 "
                                       "(a dynamic hardness that does not change with speed), when the sweep has "
                                       "two speeds or more")
    tolerance: float = Field(gt=0, lt=1, description="largest relative error, - (speed_exponent: of the slope "
                                                     "against 1/2, so 0.1 is 0.5 +- 0.05)")


class CraterCase(Frozen):
    """A validated Hutchings crater case in SI units."""

    case: CaseMeta
    sphere: Sphere
    target: ImpactTarget
    material: TargetMaterial
    numerics: ImpactNumerics
    simulation: ImpactSimulation
    sweep: Sweep | None = Field(None, description="the speeds verify solids runs")
    reference: CraterReference | None = None
    expected: tuple[CraterExpected, ...] = Field((), description="the verification checks (verify solids)")

    @model_validator(mode="after")
    def _consistent(self):
        check_solid_table("material", self.material.solid)
        self.material.check_impact_speed(self.sphere.speed, "sphere.speed")
        if self.sweep is not None:
            self.material.check_impact_speed(max(self.sweep.speeds), "the fastest of sweep.speeds")
        dx = self.numerics.dx
        self.target.check_lattice(dx)
        radius = 0.5 * self.sphere.diameter
        if radius < 4.0 * dx:
            raise ValueError(f"sphere.diameter = {self.sphere.diameter} m spans fewer than 8 particles of "
                             f"numerics.dx = {dx} m: refine dx")
        if not self.sphere.kinematic and 2.0 * radius > min(self.target.size[:2]):
            raise ValueError(f"sphere.diameter = {self.sphere.diameter} m is wider than the target "
                             f"({min(self.target.size[:2])} m): the crater would reach its sides")
        if any(row.quantity == "hertz_modulus" for row in self.expected):
            if not self.sphere.kinematic or self.material.solid.yield_stress is not None:
                raise ValueError("expected: hertz_modulus needs sphere.kinematic = true and an elastic target "
                                 "(no material.solid.yield_stress)")
        return self
