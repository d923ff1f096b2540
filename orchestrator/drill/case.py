"""The tables both drill kinds' cases hold (Canini, Gerken, Biermann & Eberhard): the drill's dimensions ([drill],
defaults = the reconstruction in reference.drill_network.DrillNetwork and drill/geometry.DrillGeometry), the fluid,
the optional physics and what the walls are, the SPH numerics and what is recorded, with the checks they share.
SI units (m, kg, s, Pa, N); flows in m^3/s except where a key says l/min.

Each kind's case (kinds/ejector_drill/case.py, kinds/ejector_feed/case.py) adds its [scene] table and its own checks
to DrillCase. The tool's rotation (n ~ 950 1/min) is not modelled: at the head's rim it moves the wall at 1.5 m/s
against 60 m/s in the gap, and its centrifugal head rho omega^2 r^2 / 2 ~ 0.5 kPa is 1e-4 of the expected 10-20 bar.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Literal

from pydantic import Field, create_model, model_validator

from orchestrator.case.common import CaseMeta, Frozen, Positive
from orchestrator.drill.descriptions import DRILL_DESCRIPTIONS
from orchestrator.drill.geometry import DrillGeometry
from orchestrator.kinds.sph_flow.case_parts import ArtificialViscosity, Fluid
from orchestrator.kinds.sph_flow.case_run import SphNumerics, SphSimulation
from orchestrator.reference.drill_network import DrillNetwork

#: DrillGeometry's own fields (the network's come from DrillNetwork).
GEOMETRY_FIELDS = tuple(f.name for f in dataclasses.fields(DrillGeometry) if f.name != "network")
#: The fewest lattice spacings across a passage the scene holds as fluid (an adduction hole, an ejector nozzle): the
#: coarsest measured scene, feed_quick, ran with 2.5 across its nozzles; below it a passage holds a column or two of
#: particles, whose flow is the lattice's, not the passage's.
MIN_SPACINGS_ACROSS = 2.5


def _drill_fields() -> dict:
    """Every DrillNetwork field and DrillGeometry's own, with their types, defaults (one source of defaults) and
    descriptions (drill/descriptions.py; KeyError for a field without one)."""
    out = {}
    for f in dataclasses.fields(DrillNetwork):
        kind = int if isinstance(f.default, int) else float
        bound = {} if f.name == "p_ambient" else {"gt": 0}
        out[f.name] = (kind, Field(f.default, description=DRILL_DESCRIPTIONS[f.name], **bound))
    for f in dataclasses.fields(DrillGeometry):
        if f.name != "network":
            bound = {"ge": 0} if f.name == "groove_depth" else {"gt": 0}
            out[f.name] = (type(f.default), Field(f.default, description=DRILL_DESCRIPTIONS[f.name], **bound))
    return out


#: The [drill] table: dimensions (m), counts, coefficients and fluid properties of the 1D network and the geometry.
Drill = create_model("Drill", __base__=Frozen, __doc__=(
    "The drill's dimensions, counts, coefficients and fluid properties (the 1D network's and the geometry's); the "
    "defaults are the reconstruction in reference/drill_network.py and drill/geometry.py."), **_drill_fields())


class DrillPenalty(Frozen):
    """The mesh walls' penalty force (eq. 14), scaled with the particle spacing."""

    range_over_dx: Positive = Field(1.0, description="R / dx, -")
    s_over_dx: Positive = Field(0.5, description="s / dx (zero-force distance, < R), -")
    pressure: Positive = Field(description="psi / dx^2: the largest pressure a wall holds against one particle, Pa")

    @model_validator(mode="after")
    def _s_below_r(self):
        if not self.s_over_dx < self.range_over_dx:
            raise ValueError(f"s_over_dx = {self.s_over_dx} must be below range_over_dx = {self.range_over_dx}")
        return self


class DrillPhysics(Frozen):
    """Optional terms beyond continuity, EOS and pressure gradient, and what the walls are."""

    morris_viscosity: bool = Field(True, description="the laminar viscous term (eq. 10) with fluid.viscosity")
    artificial_viscosity: ArtificialViscosity | None = None
    eddy_viscosity: float | None = Field(None, gt=0.0, le=1.0, description=(
        "Smagorinsky's constant cs: the eddy viscosity nu_t = (cs dx)^2 |S| m^2/s beside the laminar one (the "
        "paper's eq. 4 carries Reynolds stresses R); needs morris_viscosity"))
    eddy_viscosity_walls: bool = Field(True, description=(
        "nu_t also against the wall particles; false: between fluid particles only (the quick scenes' one-layer "
        "annular gap does not resolve its walls)"))
    density_diffusion: float | None = Field(None, gt=0.0, le=1.0, description=(
        "delta of the density diffusion between fluid particles (sph_flow's physics.density_diffusion, engine eq. "
        "DD1), -; none: off"))
    walls: Literal["particles", "penalty"] = Field(
        "particles", description="particles: fixed boundary particles on the fluid's lattice inside the solids, "
                                 "each with its nearest point of the wetted surface (no-slip there; drill/walls.py); "
                                 "penalty: the solids' meshes with the penalty force of eq. 14 (wall_penalty)")
    wall_penalty: DrillPenalty = Field(default_factory=lambda: DrillPenalty(pressure=5.0e7),
                                       description="the penalty walls' force (only with walls = 'penalty')")

    @model_validator(mode="after")
    def _eddy_needs_morris(self):
        if self.eddy_viscosity is not None and not self.morris_viscosity:
            raise ValueError("physics.eddy_viscosity needs physics.morris_viscosity = true (nu_t adds to its nu)")
        return self


class DrillOutput(Frozen):
    """Frames, series and the times of the sectional pictures."""

    frame_interval: Positive = Field(description="time between particle frames, s")
    series_interval: Positive = Field(description="time between series records (flow planes, probes), s")
    picture_times: tuple[Positive, ...] = Field((), description="times of the sectional pictures, s (each a "
                                                                "multiple of frame_interval)")


def check_fits(width: float, dx: float, what: str) -> None:
    """ValueError naming numerics.dx when a channel of `width` (m; `what` names it) is narrower than one spacing."""
    if width < dx * (1 - 1e-9):
        raise ValueError(f"numerics.dx = {dx:g} m does not fit in {what} = {width:g} m (the inlet's channel); "
                         f"allowed: dx <= {width:g} m")


def check_resolved(d: float, dx: float, key: str) -> None:
    """ValueError naming drill.<key> when a passage of diameter d (m) is fewer than MIN_SPACINGS_ACROSS spacings dx
    (m) across."""
    if d < MIN_SPACINGS_ACROSS * dx * (1 - 1e-9):
        raise ValueError(f"drill.{key} = {d * 1e3:g} mm is {d / dx:.3g} particle spacings across at numerics.dx = "
                         f"{dx * 1e3:g} mm; a passage the scene holds needs at least {MIN_SPACINGS_ACROSS:g}; allowed: "
                         f"drill.{key} >= {MIN_SPACINGS_ACROSS * dx * 1e3:.4g} mm or numerics.dx <= "
                         f"{d / MIN_SPACINGS_ACROSS * 1e3:.4g} mm")


class DrillCase(Frozen):
    """What a validated drill case of either kind holds besides its [scene] (SI units); the checks they share."""

    case: CaseMeta
    drill: Drill = Field(default_factory=Drill)
    fluid: Fluid
    physics: DrillPhysics
    numerics: SphNumerics
    simulation: SphSimulation
    output: DrillOutput

    @model_validator(mode="after")
    def _shared_checks(self):
        try:
            self.geometry()
        except ValueError as exc:
            raise ValueError(f"drill.{exc}") from None
        if self.physics.morris_viscosity != (self.fluid.viscosity is not None):
            raise ValueError("fluid.viscosity is given exactly when physics.morris_viscosity = true")
        t_end = self.simulation.duration
        for key in ("frame_interval", "series_interval"):
            if getattr(self.output, key) > t_end:
                raise ValueError(f"output.{key} = {getattr(self.output, key)} s is longer than simulation.duration "
                                 f"= {t_end} s")
        for i, t in enumerate(self.output.picture_times):
            k = t / self.output.frame_interval
            if t > t_end * (1 + 1e-9) or abs(k - round(k)) > 1e-6 * max(1.0, k):
                raise ValueError(f"output.picture_times[{i}] = {t} s is not a frame time (a multiple of "
                                 f"output.frame_interval = {self.output.frame_interval} s up to simulation.duration)")
        return self

    def scene_fluid(self) -> Fluid:
        """The fluid the scene runs with (a kind whose scene lifts the rest pressure says so), SI units."""
        return self.fluid

    def network(self) -> DrillNetwork:
        """The 1D network of these dimensions (reference.drill_network)."""
        values = self.drill.model_dump()
        return DrillNetwork(**{f.name: values[f.name] for f in dataclasses.fields(DrillNetwork)})

    def geometry(self) -> DrillGeometry:
        """The parametric geometry (drill/geometry.DrillGeometry) of these dimensions."""
        values = self.drill.model_dump()
        return DrillGeometry(network=self.network(), **{k: values[k] for k in GEOMETRY_FIELDS})

    @property
    def c0(self) -> float:
        """Reference sound speed, m/s (fluid.c0)."""
        return self.fluid.c0

    @property
    def timestep_at_rest(self) -> float:
        """The CFL step with the fluid at rest, cfl h / c0 (bounded by the viscous step), s."""
        dt = self.numerics.adaptive["cfl"] * self.numerics.h / self.c0
        if self.fluid.viscosity is not None:
            dt = min(dt, self.numerics.adaptive["viscous"] * self.numerics.h ** 2 / self.fluid.viscosity)
        return dt

    @property
    def fastest_speed(self) -> float:
        """The speed (m/s) the run's step is planned with; each kind's case says which (its scene's fastest flow)."""
        return self.fluid.max_speed

    @property
    def planned_steps(self) -> int:
        """Steps of the run at the CFL step with the fastest speed, cfl h / (c0 + fastest_speed) (the engine's
        bound), -."""
        dt = self.numerics.adaptive["cfl"] * self.numerics.h / (self.c0 + self.fastest_speed)
        return math.ceil(self.simulation.duration / min(dt, self.timestep_at_rest))
