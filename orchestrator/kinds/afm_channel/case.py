"""The grain-scale abrasive-flow channel case (kind "afm_channel", Nutto et al., section IV, Fig. 5): a Newtonian
medium driven along x by a body force on the fluid only, between two walls, periodic along x and y; one hard
spherical grain carried by it; a Johnson-Cook workpiece on the bottom wall, held by a supporting wall at its
downstream face, whose upstream top edge lies in the grain's path.

Coordinates: x along the flow from the cell's start, y across (periodic), z up from the bottom wall's face (the
bottom wall below z = 0, the top wall above z = channel.gap). SI units (m, kg, s, Pa, K).

[workpiece] is the workpiece's johnson_cook material (kinds/sph_flow/case_solids.py) and where it sits;
`workpiece.mass_scaling` is the stated scaling of its inertia that brings its stable step to the medium's
(docs/afm_channel.md measures its error).
"""

from __future__ import annotations

import math

from pydantic import Field, model_validator

from orchestrator.case.common import CaseMeta, Frozen, Name, Positive
from orchestrator.kinds.sph_flow.case_impact import ImpactSimulation
from orchestrator.kinds.sph_flow.case_solids import SMOOTHING_BESIDE_FLUID, ImpactViscosity, SolidBody, check_solid_table


#: The medium's largest density variation the sound speed is chosen for (AfmChannelCase.sound_speed), -.
DENSITY_VARIATION = 0.01


class Channel(Frozen):
    """The periodic cell of the channel: its length and width (periodic) and the gap between its walls."""

    length: Positive = Field(description="extent along x, the flow (periodic), m")
    width: Positive = Field(description="extent along y (periodic), m")
    gap: Positive = Field(description="height of the fluid between the walls' faces, m")
    wall_layers: int = Field(3, ge=1, le=6, description="layers of fixed particles of each wall, -")


class Medium(Frozen):
    """The Newtonian medium and what drives it."""

    density: Positive = Field(description="density rho, kg/m^3")
    viscosity: Positive = Field(description="dynamic viscosity eta, Pa s")
    body_force: Positive = Field(description="body force per unit mass along +x on the fluid only (a pressure "
                                 "gradient rho f; the grain and the workpiece take none), m/s^2")

    def centreline_speed(self, gap: float) -> float:
        """The plane Poiseuille flow's centreline speed f H^2 / (8 nu) in the empty channel of gap H (m), m/s."""
        return self.body_force * gap**2 * self.density / (8.0 * self.viscosity)


class ChannelGrain(Frozen):
    """The hard spherical grain and where it starts (at rest)."""

    diameter: Positive = Field(description="diameter d, m")
    density: Positive = Field(description="density, kg/m^3")
    start: Positive = Field(description="x of its centre at the start, m")
    height: Positive = Field(description="z of its centre at the start, above the bottom wall's face, m")


class Workpiece(SolidBody):
    """The Johnson-Cook workpiece: a box on the bottom wall, across the whole width, its upstream face at x =
    front; its top edge there is the edge the grain meets. A wall of `support_layers` fixed particles of its
    material holds its downstream face, and the bottom wall under both is of its material."""

    name: Name = Field("workpiece", description="the material's name (it reaches the deck)")
    front: Positive = Field(description="x of its upstream face (the edge), m")
    length: Positive = Field(description="extent along x, m")
    height: Positive = Field(description="extent along z from the bottom wall's face, m")
    support_layers: int = Field(3, ge=1, le=6, description="layers of the supporting wall at its downstream face, -")


class ChannelNumerics(Frozen):
    """Resolution, kernel, artificial viscosity, the grain's contact spring and the engine's stop on density."""

    dx: Positive = Field(description="particle spacing, m")
    h_over_dx: float = Field(1.3, ge=1.0, le=3.0, description="smoothing length over spacing, -")
    artificial_viscosity: ImpactViscosity = ImpactViscosity(alpha=0.5, beta=0.0)
    contact_stiffness: float = Field(1.0, gt=0.0, le=20.0, description="the grain's spring on each workpiece "
                                     "particle (eq. G8) over rho0 c_L^2 dx of the workpiece, -")
    max_density_deviation: float = Field(0.4, gt=0.0, lt=1.0, description="the run stops as unstable when a "
                                         "particle has |rho/rho0 - 1| above this, -")
    threads: int = Field(2, ge=1, le=256, description="OpenMP threads of the engine")


class AfmChannelCase(Frozen):
    """A validated abrasive-flow channel case in SI units."""

    case: CaseMeta
    channel: Channel
    medium: Medium
    grain: ChannelGrain
    workpiece: Workpiece
    numerics: ChannelNumerics
    simulation: ImpactSimulation

    def max_speed(self) -> float:
        """The speed the run allows for (the medium's sound speed is 10 times it): 1.2 x the empty channel's
        centreline speed, m/s."""
        return 1.2 * self.medium.centreline_speed(self.channel.gap)

    def sound_speed(self) -> float:
        """The medium's sound speed c0, m/s: 10 x max_speed (Mach 0.1), and enough that the whole cell's drive rho
        f L standing on the workpiece and the grain compresses the medium by at most DENSITY_VARIATION (c0^2 >= f L
        / delta; Morris et al. 1997's body-force criterion)."""
        drive = self.medium.body_force * self.channel.length / DENSITY_VARIATION
        return max(10.0 * self.max_speed(), math.sqrt(drive))

    def height(self) -> float:
        """The domain's height: the gap and both walls, m."""
        return self.channel.gap + 2 * self.channel.wall_layers * self.numerics.dx

    def support_end(self) -> float:
        """x of the supporting wall's downstream face, m."""
        w = self.workpiece
        return w.front + w.length + w.support_layers * self.numerics.dx

    @model_validator(mode="after")
    def _consistent(self):
        check_solid_table("workpiece", self.workpiece.solid)
        self._check_lattice()
        self._check_grain()
        w, dx = self.workpiece, self.numerics.dx
        if w.solid.smoothing is None or w.solid.smoothing < SMOOTHING_BESIDE_FLUID:
            raise ValueError(f"workpiece.solid.smoothing = {w.solid.smoothing}: a workpiece in the medium needs eq. "
                             f"SS1's smoothing of at least {SMOOTHING_BESIDE_FLUID} (docs/solids.md)")
        if self.support_end() > self.channel.length - 2 * dx + 1e-6 * dx:
            raise ValueError(f"workpiece.front + workpiece.length + its support ({self.support_end():.4g} m) reaches "
                             f"beyond channel.length - 2 dx = {self.channel.length - 2 * dx:.4g} m: the medium needs "
                             "a passage behind the support")
        if w.height > self.channel.gap - self.grain.diameter - 2 * dx:
            raise ValueError(f"workpiece.height = {w.height:g} m leaves {self.channel.gap - w.height:.4g} m over it, "
                             f"less than grain.diameter + 2 dx = {self.grain.diameter + 2 * dx:.4g} m: the grain "
                             "cannot pass over the workpiece")
        self.workpiece.check_impact_speed(self.max_speed(), "1.2 x the centreline speed of medium.body_force",
                                          "workpiece")
        return self

    def _check_lattice(self) -> None:
        dx = self.numerics.dx
        for key, length in (("channel.length", self.channel.length), ("channel.width", self.channel.width),
                            ("channel.gap", self.channel.gap), ("workpiece.front", self.workpiece.front),
                            ("workpiece.length", self.workpiece.length), ("workpiece.height", self.workpiece.height)):
            layers = length / dx
            if abs(layers - round(layers)) > 1e-6 * layers:
                raise ValueError(f"{key} = {length:g} m is not a whole number of numerics.dx = {dx:g} m "
                                 f"({layers:.4g} spacings)")

    def _check_grain(self) -> None:
        g, c, w, dx = self.grain, self.channel, self.workpiece, self.numerics.dx
        r = 0.5 * g.diameter
        if g.diameter >= min(c.gap, c.width):
            raise ValueError(f"grain.diameter = {g.diameter:g} m is not smaller than the channel (channel.gap = "
                             f"{c.gap:g} m, channel.width = {c.width:g} m)")
        if r < 2.0 * dx:
            raise ValueError(f"grain.diameter = {g.diameter:g} m gives a grain of {r / dx:.3g} spacings' radius; "
                             f"it needs at least 2 (numerics.dx = {dx:g} m)")
        if not (r <= g.height <= c.gap - r):
            raise ValueError(f"grain.height = {g.height:g} m puts the grain (radius {r:g} m) outside the fluid: its "
                             f"centre must lie between {r:g} and {c.gap - r:g} m above the bottom wall's face")
        if not (r <= g.start <= c.length - r):
            raise ValueError(f"grain.start = {g.start:g} m puts the grain (radius {r:g} m) outside the cell: its "
                             f"centre must lie between {r:g} and {c.length - r:g} m along x")
        # The distance from the grain's centre to the workpiece with its support (a box), against eq. G8's reach.
        dxw = max(w.front - g.start, 0.0, g.start - self.support_end())
        dzw = max(g.height - w.height, 0.0)
        gap = math.hypot(dxw, dzw) - r
        if gap < 0.5 * dx:
            raise ValueError(f"grain.start = {g.start:g} m, grain.height = {g.height:g} m: the grain overlaps the "
                             f"workpiece (or comes within dx/2 of it, where eq. G8 pushes); start it upstream of "
                             f"workpiece.front = {w.front:g} m by more than its radius {r:g} m")
