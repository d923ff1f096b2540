"""The open boundaries of an SPH flow case (kind "sph_flow"): velocity inlets (plug or a laminar profile, the
buffer's pressure extrapolated from the fluid or by summation) and outlets (holding a reference pressure, by default
the fluid's rest pressure, or free). SI units.

The defaults are the pair that keeps an open channel steady (Tafuni et al. 2018: velocity imposed at the inlet with
the pressure extrapolated from the fluid, pressure imposed at the outlet). With a free outlet and a summation inlet a
plane channel fed by a plug between no-slip plates (tests/kinds/sph_flow/test_sph_open_defaults.py) gained up to 3 % in mean density
and 8-10 % where the plug meets the plates; three of four such runs (2D, 3D) stopped unstable within 1.2-1.9
flow-through times."""

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
    pressure: Literal["extrapolated", "summation"] = Field(
        "extrapolated", description="the buffer's density: the mean density of the fluid just ahead of the patch "
                                    "(extrapolated pressure: the inflow enters at the pressure of the fluid it joins), "
                                    "or the buffer's own summation density (a plug then piles fluid up where it meets "
                                    "no-slip walls)")

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
        deck's own defaults (plug, summation: a summation inlet's deck carries no pressure key)."""
        out = {"profile": self.profile, "inner_radius": self.inner_radius, "pressure": self.pressure,
               "material": self.material, "ramp_time": self.ramp_time or None}
        return {k: v for k, v in out.items() if v not in ("plug", None, "summation")}


class Outlet(Patch):
    """An outlet: fluid crossing the patch along `normal` is removed `layers` dx downstream."""

    layers: int = Field(3, ge=1, le=100, description="buffer layers after the patch (layers dx must cover 2h), -")
    pressure: Finite | Literal["free"] | None = Field(
        None, description="reference pressure held in the buffer (its particles then move at the fluid's speed before "
                          "the patch), Pa; default the fluid's background pressure p_B (its rest density rho0); "
                          "\"free\": none held, each buffer particle keeps the density and speed it crossed with (the "
                          "fluid's mean density may drift)")
    backflow: bool = Field(False, description="a pressure opening: the buffer may move inward too, and fluid at the "
                                              "held pressure enters where the fluid inside draws it (needs pressure)")
    column_length: Positive | None = Field(
        None, description="a column outlet (engine eq. OB5): beyond the patch a liquid column this long runs to the held "
                          "pressure, its inertia and loss holding the outflow back (needs pressure), m; default none")
    column_loss: NonNegative = Field(0.0, description="the column's loss coefficient K on its mean speed, -")
    column_area: Positive | None = Field(None, description="the column's cross-section, m^2; default the patch's")

    @model_validator(mode="after")
    def _backflow_needs_pressure(self):
        # an opening's or a column's pressure is what drives the flow through it: it is given, never a default
        given = isinstance(self.pressure, float)
        if self.backflow and not given:
            raise ValueError(f"outlet {self.name!r}: backflow needs a pressure (what enters takes the held pressure), "
                             "e.g. pressure = 0.0")
        if self.column_length is None and (self.column_loss or self.column_area is not None):
            raise ValueError(f"outlet {self.name!r}: column_loss and column_area need a column_length")
        if self.column_length is not None and not given:
            raise ValueError(f"outlet {self.name!r}: a column (column_length) needs a pressure (where it ends), "
                             "e.g. pressure = 0.0")
        return self

    def held_pressure(self, rest_pressure: float | None) -> float | None:
        """The pressure the buffer holds, Pa: the one given, else the fluid's rest pressure `rest_pressure` (Pa);
        None for a free outlet."""
        if self.pressure == "free":
            return None
        if self.pressure is None and rest_pressure is None:
            raise ValueError(f"outlet {self.name!r}: the materials' background pressures differ, so it has no rest "
                             "pressure to hold; give pressure (Pa) or pressure = \"free\"")
        return float(rest_pressure if self.pressure is None else self.pressure)

    def deck_options(self, rest_pressure: float | None) -> dict:
        """The pressure, backflow and column keys of the engine deck; `rest_pressure` (Pa) is the fluid's rest
        pressure p_B (rest_pressure(case)), held when no pressure is given."""
        held = self.held_pressure(rest_pressure)
        out = {} if held is None else {"pressure": held}
        out |= {"backflow": True} if self.backflow else {}
        if self.column_length is not None:
            out |= {"column_length": float(self.column_length), "column_loss": float(self.column_loss)}
            out |= {} if self.column_area is None else {"column_area": float(self.column_area)}
        return out


def rest_pressure(case) -> float | None:
    """The fluid's rest pressure, Pa: eq. 6 at rho0 gives the background pressure p_B, of [fluid] or shared by every
    [[materials]] table; None when the materials' differ."""
    if not case.materials:
        return float(case.fluid.background_pressure)
    values = {float(m.background_pressure) for m in case.materials}
    return values.pop() if len(values) == 1 else None


def check_outlet_pressures(case) -> None:
    """Every outlet has a pressure to hold (ValueError naming the key): one left out needs a rest pressure, which a
    case of materials with different background pressures does not have."""
    rest = rest_pressure(case)
    for i, outlet in enumerate(case.outlets):
        if outlet.pressure is None and rest is None:
            listed = ", ".join(f"{m.name}: {m.background_pressure:g} Pa" for m in case.materials)
            raise ValueError(f"outlets[{i}].pressure is left out, but the materials' background pressures differ "
                             f"({listed}); give the pressure the outlet holds (Pa) or pressure = \"free\"")
