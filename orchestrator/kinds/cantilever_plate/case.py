"""The oscillating cantilever plate case (kind "cantilever_plate"), after Gray, Monaghan & Swift (2001): a 2D
plane-strain elastic plate of `length` and `thickness`, clamped at its left end, set swinging in its first bending
mode by an initial transverse velocity v_y(x) = V c0 f(x), with c0 = sqrt(K / rho0) and f the first cantilever
mode shape (f(0) = f'(0) = 0, f(L) = 1). The plate lies along x on 0 < x < length, -thickness/2 < y <
thickness/2; the clamp is a block of `clamp_layers` columns of fixed boundary particles on -clamp_layers dx < x <
0, so the plate's free length is measured from x = 0, the face between the clamp and the plate. SI units (m, kg,
s, Pa).

[material] is a johnson_cook material of an SPH case (kinds/sph_flow/case_solids.py); without a yield_stress it is
elastic, as the plate is. Its artificial_stress table switches on Monaghan's artificial stress.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from orchestrator.case.common import CaseMeta, Frozen, Name, NonNegative, Positive
from orchestrator.kinds.sph_flow.case_solids import SolidMaterial, check_solid_table

#: The quantities an [[expected]] row can check: the period against thin-plate theory (rel_error the relative
#: difference), the clumping (rel_error = 1 - the smallest distance between two plate particles over dx).
CHECKED = ("period", "clumping")


class Plate(Frozen):
    """The plate: `length` along x from the clamp's face at x = 0, `thickness` along y, and its initial swing."""

    length: Positive = Field(description="free length L from the clamp's face, m (a whole number of numerics.dx)")
    thickness: Positive = Field(description="thickness H, m (a whole number of numerics.dx)")
    speed_factor: float = Field(0.01, gt=0.0, le=0.2, description="V of the initial v_y = V c0 f(x), c0 = "
                                "sqrt(K / rho0): the tip's initial speed over c0, -")
    clamp_layers: int = Field(4, ge=2, le=20, description="columns of fixed boundary particles that hold the "
                              "plate's left end (at least the kernel's reach, 2 h / dx), -")


class PlateMaterial(Frozen):
    """The plate's solid (elastic without yield_stress)."""

    name: Name = Field("plate", description="the material's name (it reaches the deck)")
    density: Positive = Field(description="reference density rho0, kg/m^3")
    solid: SolidMaterial = Field(description="elasticity, equation of state, artificial stress (strength and "
                                             "failure allowed, unused by a plate that stays elastic)")


class ArtificialViscosity(Frozen):
    """Monaghan's artificial viscosity (eqs. 11-12 of the engine); alpha = beta = 0 switches it off."""

    alpha: NonNegative = Field(0.1, description="linear coefficient alpha, -")
    beta: NonNegative = Field(0.0, description="quadratic coefficient beta, -")


class PlateNumerics(Frozen):
    """Resolution, kernel, time step and threads."""

    dx: Positive = Field(description="particle spacing, m (a square lattice)")
    h_over_dx: float = Field(1.5, ge=1.0, le=3.0, description="smoothing length over spacing, -")
    cfl: float = Field(0.25, gt=0.0, le=1.0, description="the adaptive step's dt <= cfl h / (c_L + |v|max), -")
    artificial_viscosity: ArtificialViscosity = ArtificialViscosity()
    threads: int = Field(1, ge=1, le=256, description="OpenMP threads of the engine")


class PlateSimulation(Frozen):
    """How long the plate swings and how often it is recorded."""

    periods: float = Field(10.0, gt=0.0, le=100.0, description="simulated time in periods of thin-plate theory, -")
    frames_per_period: int = Field(16, ge=8, le=200, description="particle frames per theoretical period (the "
                                   "tip's displacement is read from them), -")


class PlateExpected(Frozen):
    """One [[expected]] row: period against thin-plate theory, or clumping (the smallest particle distance)."""

    quantity: Literal[CHECKED] = Field(description="the checked quantity")
    tolerance: float = Field(gt=0, lt=1, description="largest relative error, -")


class CantileverPlateCase(Frozen):
    """A validated cantilever plate case in SI units."""

    case: CaseMeta
    plate: Plate
    material: PlateMaterial
    numerics: PlateNumerics
    simulation: PlateSimulation = PlateSimulation()
    expected: tuple[PlateExpected, ...] = Field((), description="the verification checks (verify solids)")

    @model_validator(mode="after")
    def _consistent(self):
        check_solid_table("material", self.material.solid)
        dx = self.numerics.dx
        for key in ("length", "thickness"):
            value = getattr(self.plate, key)
            count = value / dx
            if abs(count - round(count)) > 1e-6 * count:
                raise ValueError(f"plate.{key} = {value} m is not a whole number of numerics.dx = {dx} m "
                                 f"({count:.4g} spacings)")
        if self.plate.thickness < 4.0 * dx:
            raise ValueError(f"plate.thickness = {self.plate.thickness} m holds fewer than 4 particles of "
                             f"numerics.dx = {dx} m: refine dx")
        if self.plate.length < 4.0 * self.plate.thickness:
            raise ValueError(f"plate.length = {self.plate.length} m is below 4 x plate.thickness: thin-plate theory "
                             "does not describe so stubby a plate")
        reach = 2.0 * self.numerics.h_over_dx
        if self.plate.clamp_layers < reach - 1e-9:
            raise ValueError(f"plate.clamp_layers = {self.plate.clamp_layers} is below the kernel's reach 2 h / dx = "
                             f"{reach:g}: the plate's first particles would see the clamp's far side")
        return self
