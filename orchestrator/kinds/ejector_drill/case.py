"""The ejector deep-hole drill case (kind "ejector_drill"; Canini, Gerken, Biermann & Eberhard): the tables every
drill case holds (drill/case.DrillCase: [drill], [fluid], [physics], [numerics], [simulation], [output]), user meshes
for any part ([parts]) and which of the paper's two SPH scenes to build ([scene]: the flow-exit area or the
drill-head area) with its inlet and outlets. SI units (m, kg, s, Pa, N); flows in m^3/s except where a key says
l/min. The feed with its ejector nozzles is the kind ejector_feed.
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from pydantic import Field, ValidationInfo, field_validator, model_validator

from orchestrator.case.common import Frozen, Positive, mesh_file
from orchestrator.drill.case import DrillCase, check_fits, check_resolved
from orchestrator.kinds.ejector_drill.head import check_head
from orchestrator.kinds.sph_flow.case_parts import Finite, Fluid

#: The geometry's parts a user mesh may replace (drill/geometry.DrillGeometry.meshes).
PARTS = ("workpiece", "head", "outer_tube", "inner_tube", "adduction_holes", "ejector_nozzles")
#: The paper's two scenes (sect. 3.2).
AREAS = ("flow_exit", "drill_head")


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
                    "head clearance -> cutting zone -> chip mouth (Figs. 3-4)")
    inlet_velocity: Positive = Field(
        description="mean inflow speed at the inlet (the laminar annulus profile's columns, peak ~1.5 x), m/s")
    inlet_distance: Positive = Field(
        description="flow_exit: from the holes' axis up the annular gap to the inlet plane; drill_head: from the "
                    "holes' axis forward to the inlet plane in the head clearance, m")
    prefill: float = Field(0.0, ge=0, description="start = 'empty': length of the inlet channel downstream of the "
                                                  "inlet filled with fluid moving at inlet_velocity at t = 0, m")
    start: Literal["empty", "filled"] = Field(
        "empty", description="empty: the scene fills from the inlet (the paper's Fig. 2, a front that strikes the "
                             "walls); filled: every fluid region and the outlets' buffers hold fluid at rest at "
                             "t = 0 and the inlet ramps up over ramp_time (the flow's steady state without the "
                             "filling's water hammer)")
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
                                                      "(the paper's standard rate; the range is 50-80)")

    @field_validator("area", mode="before")
    @classmethod
    def _feed_is_its_own_kind(cls, value):
        if value == "feed":
            raise ValueError("the feed scene is the kind ejector_feed: set case.kind = \"ejector_feed\" and drop "
                             "scene.area (cases/ejector_feed_canini.toml)")
        return value


class DrillHead(Frozen):
    """The drill head's guide pads and cutting edges (head.py); angles from the main cutting edge, counted against
    the tool's rotation. Empty angle lists leave the head a plain body of revolution."""

    pad_angles: tuple[float, ...] = Field((), description="the guide pads' middle angles behind the main cutting "
                                                         "edge (empty: no pads), deg")
    pad_width: Positive = Field(5.0e-3, description="a guide pad's width, the arc it covers at the bore, m")
    pad_length: Positive = Field(12.0e-3, description="a guide pad's axial length, m")
    pad_offset: float = Field(0.0, ge=0.0, description="from the head's face rearward to the pads' front ends, m")
    pad_height: Positive | None = Field(None, description="a pad's radial height above the head body (none: to "
                                                          "the bore, bearing on it as guide pads do), m")
    edge_angles: tuple[float, ...] = Field((), description="the cutting edges' angles, the main edge at 0 (empty: "
                                                          "no cutting edges), deg")
    edge_width: Positive = Field(4.0e-3, description="a cutting edge's blade (insert) thickness, the arc at the "
                                                     "bore; the blade, a sector, is thinner toward the axis, m")
    edge_mouth_angle: Positive = Field(40.0, lt=180.0, description="the angle each edge's chip mouth spans ahead of "
                                                                   "its rake face, deg")
    edge_mouth_radius: Positive = Field(11.0e-3, description="the outer radius of each edge's chip mouth in the "
                                                             "head's face, m")
    edge_mouth_depth: Positive = Field(2.0e-3, description="each edge's chip mouth's depth into the face, where it "
                                                           "opens into the central chip mouth, m")


class EjectorDrillCase(DrillCase):
    """A validated ejector-drill case (the flow-exit or the drill-head scene) in SI units."""

    parts: dict[Literal[PARTS], PartMesh] = Field(default_factory=dict)
    scene: DrillScene
    head: DrillHead = Field(default_factory=DrillHead)

    @model_validator(mode="after")
    def _consistent(self):
        if self.parts and self.physics.walls == "particles":
            raise ValueError(f"parts.{next(iter(self.parts))}: user meshes need physics.walls = 'penalty' (the "
                             "boundary particles are cut from the parametric solids in closed form)")
        if self.scene.inlet_velocity > self.fluid.max_speed:
            raise ValueError(f"scene.inlet_velocity = {self.scene.inlet_velocity} m/s is above fluid.max_speed = "
                             f"{self.fluid.max_speed} m/s")
        net, dx = self.network(), self.numerics.dx
        if self.scene.area == "flow_exit":
            check_fits(0.5 * net.d_diff, dx, "the annular gap's radial width d_diff / 2")
            check_resolved(net.d_hole, dx, "d_hole")
        else:
            check_fits(0.5 * (net.d_bore - net.d_head_body), dx, "the head clearance (d_bore - d_head_body) / 2")
        self._check_start()
        g = self.geometry()
        if self.scene.area == "flow_exit":
            check_head(self, g.hole_z - 0.5 * net.d_hole, "the adduction holes' lower edge")
        else:
            check_head(self, g.hole_z - self.scene.inlet_distance - self.scene.prefill, "the inlet's prefill")
        return self

    def _check_start(self) -> None:
        """The start, the ramp, the prefill and the columns agree (ValueError naming the key)."""
        sc, t_end = self.scene, self.simulation.duration
        if sc.column_inertia != 1.0 and not sc.columns:
            raise ValueError(f"scene.column_inertia = {sc.column_inertia:g} needs scene.columns = true (plain "
                             "outlets have no column whose inertia it scales)")
        if sc.start == "filled" and sc.prefill > 0.0:
            raise ValueError("scene.prefill is for start = 'empty' (with 'filled' every region holds fluid at rest): "
                             "set scene.prefill = 0")
        if sc.start == "filled" and not sc.ramp_time > 0.0:
            hammer = self.fluid.density * self.c0 * sc.inlet_velocity / 1e5
            raise ValueError(f"scene.start = 'filled' needs scene.ramp_time > 0 s: the inlet started at full speed "
                             f"against fluid at rest is a water hammer of rho0 c0 v_in = {hammer:.0f} bar")
        if sc.ramp_time > t_end:
            raise ValueError(f"scene.ramp_time = {sc.ramp_time} s is longer than simulation.duration = {t_end} s")
        if sc.prefill > sc.inlet_distance:
            raise ValueError(f"scene.prefill = {sc.prefill} m is longer than scene.inlet_distance = "
                             f"{sc.inlet_distance} m")

    def scene_fluid(self) -> Fluid:
        """The fluid with the scene's back pressure (Pa) added to its rest pressure (eq. 6's p_B); the vapour
        floor (min_pressure) stays where it is."""
        if not self.scene.back_pressure:
            return self.fluid
        return self.fluid.model_copy(update={"background_pressure": self.fluid.background_pressure
                                             + self.scene.back_pressure})

    @property
    def fastest_speed(self) -> float:
        """The inflow speed, m/s: an upper bound of the step's speed while nothing in the scene runs faster."""
        return self.scene.inlet_velocity
