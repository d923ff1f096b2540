"""The Taylor bar case (kind "taylor_bar"): a cylindrical bar of a Johnson-Cook solid shot along its axis onto a
rigid, frictionless wall (Taylor 1948), the standard check of a strength model at large plastic strain. The bar
runs along z with its impact face down; the wall is the plane z = 0. SI units (m, kg, s, Pa, K).

[material] is a johnson_cook material of an SPH case (kinds/sph_flow/case_solids.py: density and a
[material.solid] table); [reference] holds a published solution's ranges, which the [[expected]] rows check.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from orchestrator.case.common import CaseMeta, Frozen, Name, Positive
from orchestrator.kinds.sph_flow.case_solids import ImpactViscosity, SolidBody, check_solid_table

#: The quantities a [[expected]] row can check against [reference] (analysis.QUANTITIES has their units), and
#: energy_balance, checked against 0 (conservation of kinetic plus internal energy).
CHECKED = ("final_length", "face_diameter", "face_plastic_strain", "face_temperature", "energy_balance")


class Bar(Frozen):
    """The bar: a cylinder of `radius` and `length` along z moving at `speed` towards the wall at z = 0."""

    length: Positive = Field(description="length L0, m (a whole number of numerics.dx)")
    radius: Positive = Field(description="radius R0, m")
    speed: Positive = Field(le=2000.0, description="impact speed, m/s")


class BarMaterial(SolidBody):
    """The bar's Johnson-Cook solid."""

    name: Name = Field("bar", description="the material's name (it reaches the deck)")



class TaylorNumerics(Frozen):
    """Resolution, kernel and the wall's penalty stiffness."""

    dx: Positive = Field(description="particle spacing, m (a cubic lattice cut to the bar's radius)")
    h_over_dx: float = Field(1.5, ge=1.0, le=3.0, description="smoothing length over spacing, -")
    artificial_viscosity: ImpactViscosity = ImpactViscosity()
    wall_load_factor: float = Field(16.0, ge=2.0, le=1000.0, description="the wall's penalty force at zero distance "
                                    "over the impact load of one face particle, rho0 c_L v dx^2 (the elastic impact "
                                    "pressure): 16 holds that load at half the range, -")
    threads: int = Field(1, ge=1, le=256, description="OpenMP threads of the engine")


class TaylorSimulation(Frozen):
    """How long the impact runs."""

    duration: Positive = Field(description="simulated time, s")
    frames: int = Field(8, ge=1, le=1000, description="particle frames over the run (and the start), -")
    series_per_frame: int = Field(10, ge=1, le=1000, description="series records per frame interval, -")


class Range(Frozen):
    """A published range [low, high] of one quantity."""

    low: float = Field(description="lower end (the quantity's unit)")
    high: float = Field(description="upper end (the quantity's unit)")

    @model_validator(mode="after")
    def _ordered(self):
        if not self.low <= self.high:
            raise ValueError(f"low = {self.low} is above high = {self.high}")
        return self


class TaylorReference(Frozen):
    """A published solution: its source and the ranges it gives (m, m, -, K)."""

    source: str = Field(description="who computed it, e.g. 'DynELA and Abaqus (axisymmetric and 3D)'")
    final_length: Range | None = Field(None, description="final length, m")
    face_diameter: Range | None = Field(None, description="final diameter of the impact face, m")
    face_plastic_strain: Range | None = Field(None, description="equivalent plastic strain at the face centre, -")
    face_temperature: Range | None = Field(None, description="temperature at the face centre, K")


class TaylorExpected(Frozen):
    """One [[expected]] row: a quantity against [reference]'s range (energy_balance: against 0), passing within
    tolerance of it."""

    quantity: Literal[CHECKED] = Field(description="the checked quantity")
    tolerance: float = Field(gt=0, lt=1, description="largest relative distance to the range, -")


class TaylorBarCase(Frozen):
    """A validated Taylor bar case in SI units."""

    case: CaseMeta
    bar: Bar
    material: BarMaterial
    numerics: TaylorNumerics
    simulation: TaylorSimulation
    reference: TaylorReference | None = Field(None, description="the published solution the checks use")
    expected: tuple[TaylorExpected, ...] = Field((), description="the verification checks (verify solids)")

    @model_validator(mode="after")
    def _consistent(self):
        check_solid_table("material", self.material.solid)
        self.material.check_impact_speed(self.bar.speed, "bar.speed")
        layers = self.bar.length / self.numerics.dx
        if abs(layers - round(layers)) > 1e-6 * layers:
            raise ValueError(f"bar.length = {self.bar.length} m is not a whole number of numerics.dx = "
                             f"{self.numerics.dx} m ({layers:.4g} layers)")
        if self.bar.radius < 2.0 * self.numerics.dx:
            raise ValueError(f"bar.radius = {self.bar.radius} m holds fewer than 2 particles of numerics.dx = "
                             f"{self.numerics.dx} m: refine dx")
        for row in self.expected:
            if row.quantity == "energy_balance":
                continue
            if self.reference is None or getattr(self.reference, row.quantity) is None:
                raise ValueError(f"expected: {row.quantity} needs reference.{row.quantity} (its published range)")
        return self
