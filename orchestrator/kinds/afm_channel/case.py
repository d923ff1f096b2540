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
from typing import Literal

import numpy as np
from pydantic import Field, model_validator

from orchestrator.case.common import CaseMeta, Frozen, Name, NonNegative, Positive
from orchestrator.kinds.afm_channel.medium import CellFlow, MediumLaw, cell_flow, developed_velocity
from orchestrator.kinds.sph_flow.case_impact import ImpactSimulation
from orchestrator.kinds.sph_flow.case_materials import MAX_MODES, PttMode
from orchestrator.kinds.sph_flow.case_solids import SMOOTHING_BESIDE_FLUID, ImpactViscosity, SolidBody, check_solid_table
from orchestrator.reference.maxwell import Mode


#: The medium's largest density variation the sound speed is chosen for (AfmChannelCase.sound_speed), -.
DENSITY_VARIATION = 0.01
#: The largest Reynolds number of the grain that numerics.inertia_scaling may give the run (creeping flow), -.
MAX_SCALED_REYNOLDS = 0.1


class Channel(Frozen):
    """The periodic cell of the channel: its length and width (periodic) and the gap between its walls."""

    length: Positive = Field(description="extent along x, the flow (periodic), m")
    width: Positive = Field(description="extent along y (periodic), m")
    gap: Positive = Field(description="height of the fluid between the walls' faces, m")
    wall_layers: int = Field(3, ge=1, le=6, description="layers of fixed particles of each wall, -")


class Medium(Frozen):
    """The medium and what drives it: Newtonian, or a multi-mode linear PTT medium (the modes of `calibrate
    maxwell` or Table III, with `viscosity` its Newtonian solvent), at rest or in its steady flow at the start."""

    density: Positive = Field(description="density rho, kg/m^3")
    viscosity: Positive = Field(description="dynamic viscosity eta of a Newtonian medium, or the solvent's eta_s "
                                "beside modes (the Morris term), Pa s")
    body_force: Positive = Field(description="body force per unit mass along +x on the fluid only (a pressure "
                                 "gradient rho f; the grain and the workpiece take none), m/s^2")
    modes: tuple[PttMode, ...] = Field((), description="a PTT medium's Maxwell modes, [[medium.modes]] tables "
                                       "(relaxation_time s, viscosity Pa s); none: a Newtonian medium")
    epsilon: NonNegative | None = Field(None, description="the PTT extensibility epsilon of every mode, - (needed "
                                        "with modes)")
    start: Literal["rest", "steady"] | None = Field(
        None, description="the medium at the start: at rest, or in the cell's steady flow (medium.py: each part's "
                          "developed profile and mode stresses at one flow rate; the grain at its centre's speed); "
                          "default steady with modes (they relax over seconds), rest without")

    @model_validator(mode="after")
    def _ptt(self):
        if self.modes and self.epsilon is None:
            raise ValueError("medium.epsilon is missing: a PTT medium (medium.modes) needs its extensibility "
                             "(0.1 for MF20 in cases/rheometry/mf20_table3.toml)")
        if not self.modes and self.epsilon is not None:
            raise ValueError("medium.epsilon is a key of a PTT medium: give medium.modes or remove it")
        if len(self.modes) > MAX_MODES:
            raise ValueError(f"medium.modes has {len(self.modes)} modes; allowed: 1 to {MAX_MODES}")
        return self

    @property
    def steady_start(self) -> bool:
        """Whether the medium starts in its steady flow."""
        return (self.start or ("steady" if self.modes else "rest")) == "steady"

    def law(self) -> MediumLaw:
        """The medium's steady shear law (medium.py)."""
        modes = tuple(Mode(m.relaxation_time, m.viscosity) for m in self.modes)
        return MediumLaw(self.viscosity, modes, self.epsilon or 0.0)

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
    inertia_scaling: float = Field(1.0, ge=1.0, le=1.0e6, description="s: the medium and the grain run with s "
                                   "times their densities at the same pressure gradient (the body force over s); "
                                   "creeping flow (Reynolds number x s well below 1) does not see it, and the step "
                                   "grows by sqrt(s) (docs/afm_channel.md), -")
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

    def cell(self) -> CellFlow:
        """The cell's steady flow under the body force (medium.py): the wide part (channel.gap) and the passage
        over the workpiece and its support at one flow rate."""
        c, w, m = self.channel, self.workpiece, self.medium
        narrow = self.support_end() - w.front
        return cell_flow(m.law(), m.density * m.body_force, (c.gap, c.gap - w.height), (c.length - narrow, narrow))

    def steady_speed(self) -> float:
        """The steady cell flow's largest speed, at the middle of the wide part or of the passage, m/s."""
        flow, law = self.cell(), self.medium.law()
        return max(float(developed_velocity(law, 0.5 * gap, gap, gradient))
                   for gap, gradient in ((flow.wide_gap, flow.wide_gradient), (flow.narrow_gap, flow.narrow_gradient)))

    def steady_stress(self) -> float:
        """The steady cell flow's largest stress, the shear stress or the modes' first normal stress difference at
        the walls of the wide part or the passage, Pa."""
        flow, law = self.cell(), self.medium.law()
        out = 0.0
        for gap, gradient in ((flow.wide_gap, flow.wide_gradient), (flow.narrow_gap, flow.narrow_gradient)):
            shear = 0.5 * gap * gradient
            normal = float(law.mode_stresses(law.rate(np.array([shear])))[0, :, 1].sum()) if law.modes else 0.0
            out = max(out, shear, normal)
        return out

    def max_speed(self) -> float:
        """The speed the run allows for (the medium's sound speed is 10 times it), m/s: 1.2 x the empty channel's
        centreline speed for a Newtonian medium at rest, else 1.2 x the steady cell flow's largest speed."""
        if self.medium.steady_start or self.medium.modes:
            return 1.2 * self.steady_speed()
        return 1.2 * self.medium.centreline_speed(self.channel.gap)

    def scaled_density(self) -> float:
        """The medium's density in the run, rho s (numerics.inertia_scaling), kg/m^3."""
        return self.medium.density * self.numerics.inertia_scaling

    def sound_speed(self) -> float:
        """The medium's sound speed c0, m/s: 10 x max_speed (Mach 0.1), and enough that the whole cell's drive rho
        f L standing on the workpiece and the grain compresses the medium by at most DENSITY_VARIATION (c0^2 >= f L
        / delta; Morris et al. 1997's body-force criterion), and with modes that the steady flow's largest stress
        sigma does (rho s c0^2 delta >= sigma): the pressure must carry the normal stresses' differences."""
        s = self.numerics.inertia_scaling
        c2 = self.medium.body_force * self.channel.length / (s * DENSITY_VARIATION)
        if self.medium.modes:
            c2 = max(c2, self.steady_stress() / (self.scaled_density() * DENSITY_VARIATION))
        return max(10.0 * self.max_speed(), math.sqrt(c2))

    def timestep(self) -> float:
        """The fixed step of a PTT medium's run (the engine's adaptive step does not know the modes), s: 0.25 h over
        the fastest wave (the medium's c0, the workpiece's scaled c_L), 0.125 h^2 over the solvent's kinematic
        viscosity, 0.25 sqrt(h / f) of the run's body force; the same bounds as the adaptive step at rest."""
        n, w = self.numerics, self.workpiece
        h = n.h_over_dx * n.dx
        wave = max(self.sound_speed(), w.solid.wave_speed(w.density) / math.sqrt(w.mass_scaling))
        nu = self.medium.viscosity / self.scaled_density()
        force = self.medium.body_force / n.inertia_scaling
        return min(0.25 * h / wave, 0.125 * h * h / nu, 0.25 * math.sqrt(h / force))

    def reynolds_number(self) -> float:
        """rho s U d / eta of the grain in the run: U the largest speed of the flow, eta the medium's lowest
        viscosity (at the walls of the steady cell flow, or the Newtonian one), -."""
        m, flow = self.medium, self.cell()
        eta = m.viscosity
        if m.modes:
            shear = 0.5 * flow.narrow_gap * flow.narrow_gradient
            eta = shear / float(m.law().rate(shear))
        return self.scaled_density() * self.max_speed() / 1.2 * self.grain.diameter / eta

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
        if self.numerics.inertia_scaling > 1.0 and self.reynolds_number() > MAX_SCALED_REYNOLDS:
            raise ValueError(f"numerics.inertia_scaling = {self.numerics.inertia_scaling:g} gives the grain a "
                             f"Reynolds number of {self.reynolds_number():.3g} in the run, above "
                             f"{MAX_SCALED_REYNOLDS:g}: the scaled inertia would change the flow; lower it")
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
