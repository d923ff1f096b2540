"""The ejector-feed case (kind "ejector_feed"; Canini, Gerken, Biermann & Eberhard, Fig. 5): the tables every drill
case holds (drill/case.DrillCase: [drill], [fluid], [physics], [numerics], [simulation], [output]) and the feed
scene's [scene]: the annular gap down to the ejector nozzles, the inner tube with C1 before and C2 behind them, its
inlets and outlets carrying the 1D network's state at network_flow (network.py). SI units (m, kg, s, Pa, N); flows
in l/min where a key says so.
"""

from __future__ import annotations

import math

from pydantic import Field, model_validator

from orchestrator.case.common import Frozen, Positive
from orchestrator.drill.case import DrillCase, check_fits, check_resolved


class FeedScene(Frozen):
    """Where the feed scene's inlets, outlets and sensors sit (layout.py) and the network state they carry."""

    inlet_distance: Positive = Field(description="from the nozzle ring up the gap to the feed inlet, m")
    backflow: bool = Field(False, description="the outlets are pressure openings: fluid at their held pressure also "
                                              "enters through them where the scene draws it; false: fluid only "
                                              "leaves")
    network_flow: Positive = Field(60.0, description="feed flow of the 1D network whose state the inlets and "
                                                      "outlets carry and which is shown beside the SPH, l/min (the "
                                                      "paper's standard rate; the range is 50-80)")
    c1_distance: Positive = Field(2.0e-3, description="C1 (and B, the discs AG_all and IB) this far before the "
                                                      "nozzle ring, toward the head, m")
    c2_distance: Positive = Field(16.0e-3, description="C2 (and the disc 'mixed') this far behind the nozzle ring "
                                                       "in the inner tube, m; the tube outlet 2h + 2dx beyond")


class EjectorFeedCase(DrillCase):
    """A validated ejector-feed case in SI units."""

    scene: FeedScene

    @model_validator(mode="after")
    def _consistent(self):
        if self.physics.walls != "particles":
            raise ValueError(f"physics.walls = {self.physics.walls!r}: the feed scene is built with boundary "
                             "particles from its closed-form solids only; allowed: 'particles'")
        net, dx = self.network(), self.numerics.dx
        check_fits(0.5 * net.d_diff, dx, "the annular gap's radial width d_diff / 2")
        check_resolved(net.d_ejector_nozzle, dx, "d_ejector_nozzle")
        # the engine bounds its inlets' profile peaks (annular: 2 x the mean) by v_max
        v = self.scene.network_flow * 1e-3 / 60.0 / (0.25 * math.pi * (net.d_outer_tube_id ** 2
                                                                      - net.d_inner_tube_od ** 2))
        if 2.0 * v > self.fluid.max_speed:
            raise ValueError(f"fluid.max_speed = {self.fluid.max_speed:g} m/s is below the feed inlet's peak 2 x "
                             f"{v:.4g} m/s (scene.network_flow = {self.scene.network_flow:g} l/min over the gap); "
                             f"allowed: fluid.max_speed >= {2.0 * v:.4g} m/s")
        n_gap, n_tube = round(net.d_outer_tube_id / dx), round(net.d_inner_tube_id / dx)
        if (n_gap - n_tube) % 2:
            raise ValueError(f"numerics.dx = {dx:g} m puts the feed inlet's columns (round(d_outer_tube_id / dx) = "
                             f"{n_gap}) and the tube inlet's ({n_tube}) on different lattices (the engine centres an "
                             "even count off the axis, an odd one on it); allowed: a dx that makes both even or both "
                             "odd")
        return self

    @property
    def fastest_speed(self) -> float:
        """fluid.max_speed, m/s: the feed's fastest flow is its jets (~75 m/s at 60 l/min), not its inflow."""
        return self.fluid.max_speed
