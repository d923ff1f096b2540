"""The ejector deep-hole drill case (kind "ejector_drill"; Canini, Gerken, Biermann & Eberhard): the drill's
dimensions ([drill], defaults = the reconstruction in reference.drill_network.DrillNetwork and
kinds/ejector_drill/case_geometry.DrillGeometry), user meshes for any part ([parts]), which of the paper's two SPH
scenes to build ([scene]: the flow-exit area or the drill-head area), the fluid, the SPH numerics and what is
recorded. SI units (m, kg, s, Pa, N); flows in m^3/s except where a key says l/min.

The tool's rotation (n ~ 950 1/min) is not modelled: at the head's rim it moves the wall at 1.5 m/s against
60 m/s in the gap, and its centrifugal head rho omega^2 r^2 / 2 ~ 0.5 kPa is 1e-4 of the expected 10-20 bar.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import Literal

from pydantic import Field, ValidationInfo, create_model, field_validator, model_validator

from orchestrator.case.common import CaseMeta, Frozen, Positive, mesh_file
from orchestrator.kinds.ejector_drill.case_geometry import DrillGeometry
from orchestrator.kinds.sph_flow.case_parts import ArtificialViscosity, Finite, Fluid, SphNumerics, SphSimulation
from orchestrator.reference.drill_network import DrillNetwork

#: The geometry's parts a user mesh may replace (DrillGeometry.meshes).
PARTS = ("workpiece", "head", "outer_tube", "inner_tube", "adduction_holes", "ejector_nozzles")
#: The paper's two scenes (sect. 3.2) and the feed (the ejector nozzles, C1 and C2 of Fig. 5: feed_layout.py).
AREAS = ("flow_exit", "drill_head", "feed")
#: DrillGeometry's own fields (the network's come from DrillNetwork).
GEOMETRY_FIELDS = tuple(f.name for f in dataclasses.fields(DrillGeometry) if f.name != "network")


def _drill_fields() -> dict:
    """Every DrillNetwork field and DrillGeometry's own, with their types and defaults (one source of defaults)."""
    out = {}
    for f in dataclasses.fields(DrillNetwork):
        kind = int if isinstance(f.default, int) else float
        out[f.name] = (kind, Field(f.default, gt=0) if f.name not in ("p_ambient",) else Field(f.default))
    for f in dataclasses.fields(DrillGeometry):
        if f.name != "network":
            out[f.name] = (type(f.default), Field(f.default, ge=0) if f.name == "groove_depth" else
                           Field(f.default, gt=0))
    return out


#: The [drill] table: dimensions (m), counts, coefficients and fluid properties of the 1D network and the geometry.
Drill = create_model("Drill", __base__=Frozen, **_drill_fields())


class PartMesh(Frozen):
    """A user mesh replacing one part of the parametric geometry (watertight; STL, OBJ, PLY, OFF)."""

    file: Path = Field(description="mesh file, relative to the case file")
    scale: Positive = Field(1.0, description="factor to metres (1e-3 for a file in mm), -")

    @field_validator("file")
    @classmethod
    def _exists(cls, value: Path, info: ValidationInfo) -> Path:
        return mesh_file(value, (info.context or {}).get("base_dir", "."))


class DrillScene(Frozen):
    """Which part of the drill the SPH scene holds, where the fluid enters and where it leaves."""

    area: Literal[AREAS] = Field(
        description="flow_exit: annular gap -> adduction holes -> clearance to the bore (paper Fig. 2); drill_head: "
                    "head clearance -> cutting zone -> chip mouth (Figs. 3-4); feed: annular gap -> ejector nozzles "
                    "-> inner tube with C1 and C2 (Fig. 5; feed_layout.py)")
    inlet_velocity: Positive | None = Field(
        None, description="mean inflow speed at the inlet (the laminar annulus profile's columns, peak ~1.5 x), m/s; "
                          "required for flow_exit and drill_head; feed: not used (its inlet carries the network's "
                          "V_total at network_flow)")
    inlet_distance: Positive = Field(
        description="flow_exit: from the holes' axis up the annular gap to the inlet plane; drill_head: from the "
                    "holes' axis forward to the inlet plane in the head clearance; feed: from the nozzle ring up the "
                    "gap to the feed inlet, m")
    prefill: float = Field(0.0, ge=0, description="start = 'empty': length of the inlet channel downstream of the "
                                                  "inlet filled with fluid moving at inlet_velocity at t = 0, m")
    start: Literal["empty", "filled"] = Field(
        "empty", description="empty: the scene fills from the inlet (the paper's Fig. 2, a front that strikes the "
                             "walls); filled: every fluid region and the outlets' buffers hold fluid at rest at "
                             "t = 0 and the inlet ramps up over ramp_time (the flow's steady state without the "
                             "filling's water hammer). The feed scene always starts filled and moving (feed_build)")
    ramp_time: float = Field(0.0, ge=0, description="the inlet's speed rises as (1 - cos(pi t / ramp_time)) / 2 of "
                                                    "inlet_velocity until ramp_time (engine eq. OB4), s; 0: at once")
    mouth_depth: Positive = Field(5.0e-3, description="the chip-mouth outlet's distance behind the head face, m")
    leak_margin: Positive = Field(3.0e-3, description="flow_exit: the leak outlet's distance behind the inlet "
                                                      "plane in the tube/bore clearance, m")
    mouth_pressure: Finite = Field(0.0, description="gauge pressure held at the chip-mouth outlet, Pa")
    leak_pressure: Finite = Field(0.0, description="gauge pressure held at the leak outlet (flooded work area), Pa")
    backflow: bool = Field(False, description="the outlets are pressure openings: fluid at their held pressure also "
                                              "enters through them where the scene draws it (a jet's entrainment), "
                                              "instead of leaving voids; false: fluid only leaves")
    columns: bool = Field(False, description="the leak and chip-mouth outlets stand for the passages beyond them as "
                                             "liquid columns with their inertia and friction (engine eq. OB5; "
                                             "lengths and losses from the network: columns.py); false: plain "
                                             "outlets at their held pressures")
    back_pressure: Finite = Field(0.0, ge=0.0, description=(
        "added to the fluid's rest pressure and to both outlets' held pressures, Pa: the liquid's flow depends on "
        "pressure differences only, so it is the same flow with the SPH's acoustic noise (about rho c0 dv, a bar) "
        "kept above the vapour floor (fluid.min_pressure); the analysis subtracts it from every pressure"))
    column_inertia: float = Field(1.0, gt=0.0, le=1.0, description=(
        "with columns: the fraction of each passage's length the column keeps for its inertia (and chamber); its "
        "loss stays the whole passage's, so a steady state is the same, reached sooner (columns.py), -"))
    network_flow: Positive = Field(60.0, description="feed flow of the 1D network shown beside the SPH, l/min "
                                                      "(the paper's standard rate; the range is 50-80); feed: the "
                                                      "network state the inlets and outlets carry")
    c1_distance: Positive = Field(2.0e-3, description="feed: C1 (and B, the discs AG_all and IB) this far before "
                                                      "the nozzle ring, toward the head, m")
    c2_distance: Positive = Field(16.0e-3, description="feed: C2 (and the disc 'mixed') this far behind the nozzle "
                                                       "ring in the inner tube, m; the tube outlet 2h + 2dx beyond")


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
    walls: Literal["particles", "penalty"] = Field(
        "particles", description="particles: fixed boundary particles on the fluid's lattice inside the solids, "
                                 "each with its nearest point of the wetted surface (no-slip there; walls.py); "
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


class EjectorDrillCase(Frozen):
    """A validated ejector-drill case in SI units."""

    case: CaseMeta
    drill: Drill = Field(default_factory=Drill)
    parts: dict[Literal[PARTS], PartMesh] = Field(default_factory=dict)
    scene: DrillScene
    fluid: Fluid
    physics: DrillPhysics
    numerics: SphNumerics
    simulation: SphSimulation
    output: DrillOutput

    @model_validator(mode="after")
    def _consistent(self):
        try:
            self.geometry()
        except ValueError as exc:
            raise ValueError(f"drill: {exc}") from None
        if self.scene.area == "feed" and (self.parts or self.physics.walls != "particles"):
            raise ValueError("scene.area = 'feed' is built with boundary particles from the parametric solids only "
                             "(physics.walls = 'particles', no [parts])")
        if self.parts and self.physics.walls == "particles":
            raise ValueError(f"parts.{next(iter(self.parts))}: user meshes need physics.walls = 'penalty' (the "
                             "boundary particles are cut from the parametric solids in closed form)")
        if self.physics.morris_viscosity != (self.fluid.viscosity is not None):
            raise ValueError("fluid.viscosity is given exactly when physics.morris_viscosity = true")
        if self.scene.inlet_velocity is None and self.scene.area != "feed":
            raise ValueError(f"scene.inlet_velocity is required for scene.area = '{self.scene.area}'")
        if (self.scene.inlet_velocity or 0.0) > self.fluid.max_speed:
            raise ValueError(f"scene.inlet_velocity = {self.scene.inlet_velocity} m/s is above fluid.max_speed = "
                             f"{self.fluid.max_speed} m/s")
        net, dx = self.network(), self.numerics.dx
        gap, what = (0.5 * net.d_diff, "the annular gap's radial width d_diff / 2") if self.scene.area != "drill_head" \
            else (0.5 * (net.d_bore - net.d_head_body), "the head clearance (d_bore - d_head_body) / 2")
        if gap < dx * (1 - 1e-9):
            raise ValueError(f"numerics.dx = {dx:g} m does not fit in {what} = {gap:g} m (the inlet's channel); "
                             f"allowed: dx <= {gap:g} m")
        if self.scene.area == "feed":  # the engine bounds its inlets' profile peaks (annular: 2 x the mean) by v_max
            v = self.scene.network_flow * 1e-3 / 60.0 / (0.25 * math.pi * (net.d_outer_tube_id ** 2
                                                                          - net.d_inner_tube_od ** 2))
            if 2.0 * v > self.fluid.max_speed:
                raise ValueError(f"fluid.max_speed = {self.fluid.max_speed:g} m/s is below the feed inlet's peak 2 x "
                                 f"{v:.4g} m/s (scene.network_flow = {self.scene.network_flow:g} l/min over the gap); "
                                 f"allowed: fluid.max_speed >= {2.0 * v:.4g} m/s")
        n_gap, n_tube = round(net.d_outer_tube_id / dx), round(net.d_inner_tube_id / dx)
        if self.scene.area == "feed" and (n_gap - n_tube) % 2:
            raise ValueError(f"numerics.dx = {dx:g} m puts the feed inlet's columns (round(d_outer_tube_id / dx) = "
                             f"{n_gap}) and the tube inlet's ({n_tube}) on different lattices (the engine centres an "
                             "even count off the axis, an odd one on it); allowed: a dx that makes both even or both "
                             "odd")
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
        if self.scene.area == "feed" and (self.scene.start == "filled" or self.scene.ramp_time > 0.0):
            raise ValueError("scene.start and scene.ramp_time are for the flow-exit and drill-head scenes: the feed "
                             "scene starts filled and moving with its inlets' flows")
        if self.scene.column_inertia != 1.0 and not self.scene.columns:
            raise ValueError(f"scene.column_inertia = {self.scene.column_inertia:g} needs scene.columns = true (plain "
                             "outlets have no column whose inertia it scales)")
        if self.scene.area == "feed" and self.scene.back_pressure:
            raise ValueError("scene.back_pressure is for the flow-exit and drill-head scenes: the feed scene starts "
                             "from the network's pressures at its own outlets (feed_build.py)")
        if self.scene.start == "filled" and self.scene.prefill > 0.0:
            raise ValueError("scene.prefill is for start = 'empty' (with 'filled' every region holds fluid at rest): "
                             "set scene.prefill = 0")
        if self.scene.start == "filled" and not self.scene.ramp_time > 0.0:
            hammer = self.fluid.density * self.c0 * self.scene.inlet_velocity / 1e5
            raise ValueError(f"scene.start = 'filled' needs scene.ramp_time > 0 s: the inlet started at full speed "
                             f"against fluid at rest is a water hammer of rho0 c0 v_in = {hammer:.0f} bar")
        if self.scene.ramp_time > t_end:
            raise ValueError(f"scene.ramp_time = {self.scene.ramp_time} s is longer than simulation.duration = "
                             f"{t_end} s")
        if self.scene.prefill > self.scene.inlet_distance:
            raise ValueError(f"scene.prefill = {self.scene.prefill} m is longer than scene.inlet_distance = "
                             f"{self.scene.inlet_distance} m")
        return self

    def scene_fluid(self) -> Fluid:
        """The fluid with the scene's back pressure (Pa) added to its rest pressure (eq. 6's p_B); the vapour
        floor (min_pressure) stays where it is."""
        if not self.scene.back_pressure:
            return self.fluid
        return self.fluid.model_copy(update={"background_pressure": self.fluid.background_pressure
                                             + self.scene.back_pressure})

    def network(self) -> DrillNetwork:
        """The 1D network of these dimensions (reference.drill_network)."""
        values = self.drill.model_dump()
        return DrillNetwork(**{f.name: values[f.name] for f in dataclasses.fields(DrillNetwork)})

    def geometry(self):
        """The parametric geometry (case_geometry.DrillGeometry) of these dimensions."""
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
    def planned_steps(self) -> int:
        """Steps of the run at the CFL step with the inflow speed, cfl h / (c0 + v_in) (the engine's bound), -."""
        # the feed scene's fastest flow is its jets (~75 m/s at 60 l/min), not its inflow: fluid.max_speed there
        speed = self.fluid.max_speed if self.scene.area == "feed" else self.scene.inlet_velocity
        dt = self.numerics.adaptive["cfl"] * self.numerics.h / (self.c0 + speed)
        return math.ceil(self.simulation.duration / min(dt, self.timestep_at_rest))
