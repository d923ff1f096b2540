"""The open boundaries of an SPH flow case (kind "sph_flow"): velocity inlets (plug or a laminar profile, buffer
pressure by summation or extrapolated) and outlets (optionally holding a reference pressure). SI units."""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from orchestrator.case.common import Name, NonNegative, Positive
from orchestrator.kinds.sph_flow.case_parts import Finite, Patch


class Inlet(Patch):
    """A velocity inlet: fluid enters through the patch along `normal` at `velocity`."""

    velocity: Positive = Field(description="inflow speed along the normal (plug), or the mean speed of a profile, m/s "
                                           "(the profile's peak at most fluid.max_speed)")
    layers: int = Field(3, ge=1, le=100, description="buffer layers behind the patch (layers dx must cover 2h), -")
    profile: Literal["plug", "parabolic", "annular"] = Field(
        "plug", description="plug: velocity everywhere; parabolic: pipe Poiseuille on a disc (peak 2 velocity), plane "
                            "Poiseuille across u on a rectangle or 2D segment (peak 1.5 velocity); annular: the "
                            "laminar annulus profile on a disc with inner_radius (peak below 2 velocity)")
    inner_radius: Positive | None = Field(None, description="inner radius of an annular profile, m (< radius)")
    pressure: Literal["summation", "extrapolated"] = Field(
        "summation", description="the buffer's density: its summation density, or the mean density of the fluid just "
                                 "ahead of the patch (extrapolated pressure, for long open flows)")

    material: Name | None = Field(None, description="name of the [[materials]] table of the fluid it makes "
                                                    "(default: the first)")
    ramp_time: float = Field(0.0, ge=0, description="the speed rises as (1 - cos(pi t / ramp_time)) / 2 of its value "
                                                    "until ramp_time, s (a scene filled at rest starts without a "
                                                    "water hammer); 0: full speed from the start")

    @model_validator(mode="after")
    def _annulus(self):
        if (self.profile == "annular") != (self.inner_radius is not None):
            raise ValueError("inner_radius is given exactly with profile = 'annular'")
        if self.inner_radius is not None and (self.radius is None or self.inner_radius >= self.radius):
            raise ValueError("an annular profile needs a disc patch (radius) with inner_radius < radius")
        return self

    @property
    def peak_speed(self) -> float:
        """The profile's largest speed, m/s (an upper bound for the annulus)."""
        disc = self.radius is not None and len(self.center) == 3
        return self.velocity * (1.0 if self.profile == "plug" else 2.0 if disc else 1.5)

    def deck_options(self) -> dict:
        """The profile, pressure, material and ramp keys of the engine deck, only where they differ from the
        defaults."""
        out = {"profile": self.profile, "inner_radius": self.inner_radius, "pressure": self.pressure,
               "material": self.material, "ramp_time": self.ramp_time or None}
        return {k: v for k, v in out.items() if v not in ("plug", None, "summation")}


class Outlet(Patch):
    """An outlet: fluid crossing the patch along `normal` is removed `layers` dx downstream."""

    layers: int = Field(3, ge=1, le=100, description="buffer layers after the patch (layers dx must cover 2h), -")
    pressure: Finite | None = Field(None, description="reference pressure held in the buffer (its particles then move "
                                                      "at the fluid's speed before the patch), Pa; default none")
    backflow: bool = Field(False, description="a pressure opening: the buffer may move inward too, and fluid at the "
                                              "held pressure enters where the fluid inside draws it (needs pressure)")
    column_length: Positive | None = Field(
        None, description="a column outlet (engine eq. OB5): beyond the patch a liquid column this long runs to the held "
                          "pressure, its inertia and loss holding the outflow back (needs pressure), m; default none")
    column_loss: NonNegative = Field(0.0, description="the column's loss coefficient K on its mean speed, -")
    column_area: Positive | None = Field(None, description="the column's cross-section, m^2; default the patch's")

    @model_validator(mode="after")
    def _backflow_needs_pressure(self):
        if self.backflow and self.pressure is None:
            raise ValueError(f"outlet {self.name!r}: backflow needs a pressure (what enters takes the held pressure)")
        if self.column_length is None and (self.column_loss or self.column_area is not None):
            raise ValueError(f"outlet {self.name!r}: column_loss and column_area need a column_length")
        if self.column_length is not None and self.pressure is None:
            raise ValueError(f"outlet {self.name!r}: a column (column_length) needs a pressure (where it ends)")
        return self

    def deck_options(self) -> dict:
        """The pressure, backflow and column keys of the engine deck when set."""
        out = {} if self.pressure is None else {"pressure": float(self.pressure)}
        out |= {"backflow": True} if self.backflow else {}
        if self.column_length is not None:
            out |= {"column_length": float(self.column_length), "column_loss": float(self.column_loss)}
            out |= {} if self.column_area is None else {"column_area": float(self.column_area)}
        return out
