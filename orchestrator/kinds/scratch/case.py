"""The grain scratch case (kind "scratch"): a hard, angular grain (a clump of spheres, one corner leading) shot
obliquely into the top of a Johnson-Cook box whose bottom rests on held particle layers (Nutto et al., section
II-B, Fig. 1). The box's top face is z = 0, its long side along x; the grain moves in the x-z plane towards +x and
-z. SI units (m, kg, s, Pa, K), angles in degrees.

[material] is the target's johnson_cook material (kinds/sph_flow/case_solids.py); with [material.solid.failure]
the target fails (eqs. 13-14) and the run counts the removed particles and chips, without it the target only
deforms.
"""

from __future__ import annotations

from pydantic import Field, model_validator

from orchestrator.case.common import CaseMeta, Frozen, Name, Positive
from orchestrator.kinds.sph_flow.case_impact import (
    ImpactNumerics,
    ImpactSimulation,
    ImpactTarget,
)
from orchestrator.kinds.sph_flow.case_solids import SolidBody, check_solid_table


class Grain(Frozen):
    """The ideally hard grain: a central sphere and four corner spheres at the corners of a tetrahedron, one
    corner leading: forward and down, halfway between the velocity and -z (scene.leading)."""

    size: Positive = Field(description="the grain's extent D, the diameter of the sphere round its clump, m")
    corner: float = Field(0.3, gt=0.0, lt=1.0, description="a corner sphere's radius over the central sphere's "
                          "(their outer points reach D/2 from the centre), -")
    density: Positive = Field(description="density of the grain, kg/m^3")
    speed: Positive = Field(le=2000.0, description="impact speed, m/s")
    angle: float = Field(gt=0.0, le=90.0, description="angle of incidence measured from the surface (90: normal "
                         "impact), deg")


class Target(ImpactTarget):
    """The box: its size (each a whole number of numerics.dx), where the grain's lowest point meets its top face,
    and the held layers under it."""

    entry: Positive = Field(description="distance from the box's -x face to where the grain's lowest point meets "
                            "the top face, m")


class TargetMaterial(SolidBody):
    """The target's Johnson-Cook solid, with or without its failure table."""

    name: Name = Field("target", description="the material's name (it reaches the deck)")
    fails: bool = Field(True, description="false: the solid's failure table is left out of the run (the target "
                        "only deforms), -")

    def case_material(self) -> dict:
        """The solid as an sph_flow case's [[materials]] table (without its failure table unless it fails)."""
        item = super().case_material()
        if not self.fails:
            item["solid"].pop("failure", None)
        return item


class ScratchNumerics(ImpactNumerics):
    """Resolution, kernel, the contact's stiffness and the engine's stop on density."""

    max_density_deviation: float = Field(0.9, gt=0.0, lt=1.0, description="the run stops as unstable when a target "
                                         "particle has |rho/rho0 - 1| above this; failed particles carry no tension, "
                                         "so a chip tearing off thins by 30 % and more, -")


class ScratchCase(Frozen):
    """A validated grain scratch case in SI units."""

    case: CaseMeta
    grain: Grain
    target: Target
    material: TargetMaterial
    numerics: ScratchNumerics
    simulation: ImpactSimulation

    @model_validator(mode="after")
    def _consistent(self):
        check_solid_table("material", self.material.solid)
        self.material.check_impact_speed(self.grain.speed, "grain.speed")
        dx = self.numerics.dx
        self.target.check_lattice(dx)
        corner = self.grain.size * self.grain.corner / (2.0 * (1.0 + self.grain.corner))
        if corner < 0.5 * dx:
            raise ValueError(f"grain.size = {self.grain.size} m gives corner spheres of radius {corner:.4g} m, "
                             f"below half numerics.dx = {dx} m: refine dx or enlarge the grain")
        if self.grain.size > self.target.size[1]:
            raise ValueError(f"grain.size = {self.grain.size} m is wider than the target (target.size along y = "
                             f"{self.target.size[1]} m): the kerf would reach its sides")
        if not 0.5 * self.grain.size <= self.target.entry <= self.target.size[0] - 0.5 * self.grain.size:
            raise ValueError(f"target.entry = {self.target.entry} m puts the first contact less than half the "
                             f"grain ({0.5 * self.grain.size} m) from the box's x faces (0 and "
                             f"{self.target.size[0]} m)")
        return self
