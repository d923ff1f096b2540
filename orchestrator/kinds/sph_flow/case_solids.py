"""Solid materials of an SPH case: the elastic-plastic Johnson-Cook solid of Nutto et al. (section II-B; the sph
executable's engines/sph/src/materials/johnson_cook_material.h, docs/solids.md), a [[materials]] table of model
"johnson_cook" with its parameters in a [materials.solid] table. SI units (Pa, K, J/(kg K), 1/s).

    [[materials]]
    name = "al6061"
    model = "johnson_cook"
    density = 2703.0              # rho0, kg/m^3

    [materials.solid]
    shear_modulus = 25.9e9        # G, Pa
    eos = "mie_gruneisen"         # or "linear" with bulk_modulus (Pa)
    bulk_sound_speed = 5240.0     # C0, m/s (Steinberg 1996)
    hugoniot_slope = 1.4          # S, -
    gruneisen = 1.97              # Gamma0, -
    yield_stress = 324e6          # A, Pa (without it: elastic, no strength or failure)
    hardening_modulus = 114e6     # B, Pa
    hardening_exponent = 0.42     # n, -
    rate_sensitivity = 0.002      # C, -
    thermal_exponent = 1.34       # m, -
    melting_temperature = 925.0   # Tm, K
    heat_capacity = 896.0         # C_p, J/(kg K)
    heat_fraction = 0.95          # chi, - (0: isothermal)

    [materials.solid.failure]     # Johnson-Cook damage (eq. 14), sigma* tension positive
    d1 = -0.77
    d2 = 1.45
    d3 = -0.47

    [materials.solid.artificial_stress]   # Monaghan (2000), Gray, Monaghan & Swift (2001)
    epsilon = 0.3
    exponent = 4

The engine compiles solids alone with artificial viscosity or none, or in a Lees-Edwards cell, and solids beside
a Newtonian fluid with the Morris viscosity (and artificial viscosity or none): every pair then takes the tensor
path (eq. T1), the fluid's stress is -p I, and a fluid particle beside a solid one takes its own viscosity against
the solid particle's velocity (no slip; the solid takes the reaction). The Morris viscosity is not a solid's term.
"""

from __future__ import annotations

import math

import numpy as np

from pydantic import Field

from orchestrator.case.common import Frozen, Name, NonNegative, Positive
from orchestrator.kinds.sph_flow.case_parts import Finite

#: Equations of state of a solid (engines/sph/src/materials/solid_parameters.h).
SOLID_EOS = ("linear", "mie_gruneisen")

#: The rate factor of eqs. 10 and 14: (1 + epsdot*)^C as the paper prints it, or Johnson and Cook's 1 + C ln epsdot*.
RATE_FORMS = ("power", "log")

#: The momentum sum of a solid: eq. T1 with grad W (plain) or with the kernel-corrected gradient M^-T grad W of
#: eq. KC1 (corrected; Bonet & Lok 1999).
MOMENTUM_SUMS = ("plain", "corrected")

#: The least smoothing delta (eq. SS1) of a solid beside a fluid: an elastic layer under water (dx 5 mm) held still
#: at 0.01 and 0.02 and went unstable at 0.005 (docs/solids.md).
SMOOTHING_BESIDE_FLUID = 0.01

#: Keys of [materials.solid] that only a plastic solid (one with a yield_stress) takes.
STRENGTH_KEYS = ("hardening_modulus", "hardening_exponent", "rate_sensitivity", "thermal_exponent",
                 "reference_rate", "rate_form", "room_temperature", "melting_temperature", "failure")


class SolidFailure(Frozen):
    """Johnson-Cook damage, eq. 14: eps_f = [d1 + d2 exp(d3 sigma*)] R(epsdot*; d4) [1 + d5 T*]."""

    d1: Finite = Field(description="D1, -")
    d2: Finite = Field(description="D2, -")
    d3: Finite = Field(description="D3, - (sigma* = mean stress / von Mises stress, tension positive)")
    d4: Finite = Field(0.0, description="D4, - (rate term, the strength's rate form and reference rate)")
    d5: Finite = Field(0.0, description="D5, - (temperature term)")


class ArtificialStress(Frozen):
    """Monaghan's artificial stress against the tensile instability (Gray, Monaghan & Swift 2001)."""

    epsilon: NonNegative = Field(0.3, description="epsilon of R = -epsilon sigma_tension / rho^2, -")
    exponent: int = Field(4, ge=1, le=8, description="n of f_ab^n, f_ab = W(r_ab) / W(dx), -")


class SolidMaterial(Frozen):
    """[materials.solid]: elasticity, equation of state, Johnson-Cook strength, heating, failure."""

    shear_modulus: Positive = Field(description="shear modulus G, Pa")
    eos: str = Field("linear", description="equation of state: linear (p = K mu) or mie_gruneisen (Hugoniot "
                                           "reference, mu = rho / rho0 - 1)")
    bulk_modulus: Positive | None = Field(None, description="linear eos: bulk modulus K, Pa")
    bulk_sound_speed: Positive | None = Field(None, description="mie_gruneisen: bulk sound speed C0, m/s")
    hugoniot_slope: NonNegative | None = Field(None, description="mie_gruneisen: S of U_s = C0 + S u_p, -")
    gruneisen: NonNegative | None = Field(None, description="mie_gruneisen: Grueneisen parameter Gamma0, -")
    yield_stress: Positive | None = Field(None, description="initial yield stress A of eq. 10, Pa (without it the solid is elastic)")
    hardening_modulus: NonNegative | None = Field(None, description="hardening modulus B, Pa (default 0)")
    hardening_exponent: Positive | None = Field(None, description="hardening exponent n, - (default 1)")
    rate_sensitivity: NonNegative | None = Field(None, description="rate sensitivity C, - (default 0)")
    thermal_exponent: Positive | None = Field(None, description="thermal softening exponent m, - (default 1)")
    reference_rate: Positive | None = Field(None, description="reference rate epsdot_0 of epsdot* = "
                                                              "epsdot_p / epsdot_0, 1/s (default 1)")
    rate_form: str | None = Field(None, description="power ((1 + epsdot*)^C, the paper's eq. 10; default) or log "
                                                    "(1 + C ln epsdot*)")
    room_temperature: Positive | None = Field(None, description="room temperature T0, K (default 293; the start "
                                                                "temperature)")
    melting_temperature: Positive | None = Field(None, description="melting temperature Tm, K (required with "
                                                                   "yield_stress)")
    heat_capacity: Positive | None = Field(None, description="specific heat C_p of eq. 12, J/(kg K) "
                                                             "(required with heat_fraction)")
    heat_fraction: NonNegative = Field(0.0, le=1.0, description="chi of eq. 12, the share of plastic work turned "
                                                               "into heat, - (0: isothermal)")
    failure: SolidFailure | None = Field(None, description="Johnson-Cook damage (eqs. 13-14); needs yield_stress")
    artificial_stress: ArtificialStress | None = Field(None, description="Monaghan's artificial stress (off "
                                                                         "without the table)")
    momentum: str = Field("plain", description="the momentum sum: plain (eq. T1) or corrected (eq. KC1: each "
                                               "particle's stress times its M^-T, the kernel correction of the "
                                               "velocity gradient, from the last evaluation; Bonet & Lok 1999)")
    smoothing: NonNegative | None = Field(None, le=1.0, description="delta of eq. SS1: the density and deviatoric "
                                          "stress diffuse between the material's particles at kappa = delta h c0 "
                                          "(m^2/s), which damps a stress that alternates row by row (the pair sum "
                                          "exerts no force on it); e.g. 0.1, -; none: off")

    def bulk(self, density: float) -> float:
        """The bulk modulus of the reference state, Pa (rho0 C0^2 for mie_gruneisen)."""
        return self.bulk_modulus if self.eos == "linear" else density * self.bulk_sound_speed ** 2

    def wave_speed(self, density: float) -> float:
        """The longitudinal wave speed in uniaxial strain sqrt((K + 4G/3) / rho0), m/s."""
        return math.sqrt((self.bulk(density) + 4.0 / 3.0 * self.shear_modulus) / density)

    def deck(self) -> dict:
        """The solid's keys of the deck's materials entry (engines/sph/README.md), SI units."""
        item = {key: value for key, value in self.model_dump(exclude_none=True).items()
                if key not in ("failure", "artificial_stress", "heat_fraction")}
        if self.heat_fraction > 0.0:
            item["heat_fraction"] = self.heat_fraction
        if self.failure is not None:
            item["failure"] = self.failure.model_dump()
        if self.artificial_stress is not None:
            item["artificial_stress"] = self.artificial_stress.model_dump()
        return item


class SolidBody(Frozen):
    """The Johnson-Cook solid of a solid scene (a Taylor bar, a crater's target): name, density, [solid] table."""

    name: Name = Field("solid", description="the material's name (it reaches the deck)")
    density: Positive = Field(description="reference density rho0, kg/m^3")
    solid: SolidMaterial = Field(description="elasticity, equation of state, strength, heating, failure")
    mass_scaling: float = Field(1.0, ge=1.0, le=1.0e4, description="f: the run gives the solid f times its "
                                "inertia at the same stiffness and heating (density f rho0, mie_gruneisen C0 / "
                                "sqrt(f), C_p / f), so its stable step grows by sqrt(f) while the impact's Mach "
                                "number grows by sqrt(f) too; 1: none. Its error on the crater: docs/crater.md, -")

    def inertial_density(self) -> float:
        """The density the run gives the solid, f rho0, kg/m^3 (its particles' masses; rho0 without scaling)."""
        return self.density * self.mass_scaling

    def case_material(self) -> dict:
        """The solid as an sph_flow case's [[materials]] table, with the mass scaling applied: density f rho0, the
        same bulk modulus (mie_gruneisen: rho0 C0^2, so C0 / sqrt(f)) and the same heating per volume (C_p / f)."""
        solid = self.solid.model_dump(exclude_none=True)
        f = self.mass_scaling
        if f != 1.0:
            if "bulk_sound_speed" in solid:
                solid["bulk_sound_speed"] /= math.sqrt(f)
            if "heat_capacity" in solid:
                solid["heat_capacity"] /= f
        return {"name": self.name, "model": "johnson_cook", "density": self.inertial_density(), "solid": solid}

    def check_impact_speed(self, speed: float, key: str, table: str = "material") -> None:
        """ValueError naming <table>.mass_scaling (and the speed's key) when the run's wave speed sqrt((K + 4G/3) /
        (f rho0)) is below 10 x the impact speed (m/s): weakly compressible SPH needs a Mach number below 0.1."""
        wave = self.solid.wave_speed(self.density) / math.sqrt(self.mass_scaling)
        if wave < 10.0 * speed:
            most = (self.solid.wave_speed(self.density) / (10.0 * speed)) ** 2
            raise ValueError(f"{table}.mass_scaling = {self.mass_scaling:g} leaves a wave speed of {wave:.4g} m/s, "
                             f"below 10 x {key} = {speed:g} m/s (the Mach number must stay below 0.1): "
                             f"use a mass_scaling of at most {max(most, 1.0):.3g}")


class ImpactViscosity(Frozen):
    """Monaghan's artificial viscosity (eqs. 11-12 of the engine) against an impact's shock."""

    alpha: NonNegative = Field(0.5, description="linear coefficient alpha, -")
    beta: NonNegative = Field(1.0, description="quadratic coefficient beta, -")


def check_solid(case, i: int, m) -> None:
    """A johnson_cook material against its own keys, the engine's configurations and the run's density window;
    ValueError naming the key."""
    where, s = f"materials[{i}]", m.solid
    if s is None:
        raise ValueError(f"{where}.solid ({m.name}) is missing; a johnson_cook material needs a [materials.solid] "
                         "table (shear_modulus Pa, eos and its constants, ...)")
    for key in ("viscosity", "sound_speed", "modes", "epsilon", "solvent_viscosity"):
        if getattr(m, key) not in (None, ()):
            raise ValueError(f"{where}.{key} ({m.name}) is not a key of a johnson_cook material (its pressure and "
                             "wave speed come from [materials.solid]); remove it")
    fluid_keys = m.given(("gamma", "background_pressure", "eos"))
    if fluid_keys:
        raise ValueError(f"{where}.{fluid_keys[0]} ({m.name}) is a key of the fluids' equation of state; a "
                         "johnson_cook material's is [materials.solid].eos: remove it")
    check_solid_table(where, s)
    if s.yield_stress is not None:
        limit = s.yield_stress / (2.0 * s.shear_modulus)
        deviation = case.numerics.max_density_deviation
        if limit >= deviation:
            raise ValueError(f"{where}.solid.yield_stress = {s.yield_stress:g} Pa is above what the equation of "
                             f"state's range carries: yielding in uniaxial strain needs a density change A / (2 G) = "
                             f"{limit:.3g}, beyond numerics.max_density_deviation = {deviation:g}")
    others = [o for o in case.materials if o.model != "johnson_cook"]
    models = {o.model for o in others}
    if len(models) > 1:
        raise ValueError(f"{where} ({m.name}) is a johnson_cook material beside fluids of two models "
                         f"({', '.join(sorted(models))}); the sph executable runs solids alone or beside newtonian "
                         "fluids or one ptt medium")
    terms = set(case.physics.terms)
    if others:
        fluid = others[0].name
        if "morris_viscosity" not in terms:
            raise ValueError(f"physics.terms = {sorted(terms)} has no 'morris_viscosity', which the fluid {fluid!r} "
                             f"beside the johnson_cook material {where} ({m.name}) needs (its no-slip against the "
                             "solid): add it")
        apart = [key for key, on in (("lees_edwards", case.lees_edwards),
                                     ("inlets", case.inlets), ("outlets", case.outlets),
                                     ("physics.viscosity_correction", case.physics.viscosity_correction),
                                     ("physics.eddy_viscosity", case.physics.eddy_viscosity)) if on]
        if apart:
            raise ValueError(f"{apart[0]} is set with the fluid {fluid!r} beside the johnson_cook material {where} "
                             f"({m.name}); a fluid beside solids runs with walls, grains, a body force and the Morris "
                             "and artificial viscosities only: remove it")
        if s.smoothing is None or s.smoothing < SMOOTHING_BESIDE_FLUID:
            raise ValueError(f"{where}.solid.smoothing = {s.smoothing}: the johnson_cook material {m.name!r} beside "
                             f"the fluid {fluid!r} needs eq. SS1's smoothing of at least {SMOOTHING_BESIDE_FLUID} "
                             "(0.02 in cases/verification/sph_solid_under_water.toml): without it the solid's row "
                             "mode grows under the fluid's pressure (docs/solids.md)")
        _check_grains_clear_of(case, i, m)
    elif "morris_viscosity" in terms:
        raise ValueError(f"physics.terms has 'morris_viscosity' with the johnson_cook material {where} ({m.name}); "
                         "a solid takes artificial_viscosity only: remove it")


def _check_grains_clear_of(case, i: int, m) -> None:
    """ValueError naming grains[k].centre when a grain reaches into a block of the solid material m (materials[i])."""
    for j, block in enumerate(case.blocks):
        if block.material != m.name:
            continue
        lo, hi = np.asarray(block.lo, dtype=float), np.asarray(block.hi, dtype=float)
        for k, g in enumerate(case.grains):
            centre = np.asarray(g.centre, dtype=float)
            gap = float(np.linalg.norm(centre - np.clip(centre, lo, hi))) - g.radius
            if gap < 0.0:
                raise ValueError(f"grains[{k}].centre = {list(g.centre)}: grain {g.name!r} (radius {g.radius:g} m) "
                                 f"reaches {-gap:.4g} m into blocks[{j}] ({block.name!r}) of the johnson_cook material "
                                 f"materials[{i}] ({m.name}); a grain starts in the fluid")


def check_solid_table(where: str, s: SolidMaterial) -> None:
    """A [<where>.solid] table against itself: its equation of state's keys, the strength keys only with a yield
    stress, Tm above T0, C_p with heating; ValueError naming the key as <where>.solid.<key>."""
    _check_eos(where, s)
    _check_strength(where, s)
    if s.momentum not in MOMENTUM_SUMS:
        raise ValueError(f"{where}.solid.momentum = {s.momentum!r}: allowed: {', '.join(MOMENTUM_SUMS)}")
    if s.heat_fraction > 0.0 and s.heat_capacity is None:
        raise ValueError(f"{where}.solid.heat_capacity is missing; heat_fraction = {s.heat_fraction} heats the "
                         "solid by eq. 12, which needs C_p (J/(kg K))")
    if s.heat_fraction == 0.0 and s.heat_capacity is not None:
        raise ValueError(f"{where}.solid.heat_capacity = {s.heat_capacity:g} J/(kg K) is given but heat_fraction is "
                         "0 (isothermal): give heat_fraction > 0 to heat the solid, or remove heat_capacity")


def _check_eos(where: str, s: SolidMaterial) -> None:
    if s.eos not in SOLID_EOS:
        raise ValueError(f"{where}.solid.eos = {s.eos!r}: unknown equation of state; allowed: {', '.join(SOLID_EOS)}")
    own = ("bulk_modulus",) if s.eos == "linear" else ("bulk_sound_speed", "hugoniot_slope", "gruneisen")
    for key in ("bulk_modulus", "bulk_sound_speed", "hugoniot_slope", "gruneisen"):
        given = getattr(s, key) is not None
        if key in own and not given:
            raise ValueError(f"{where}.solid.{key} is missing; eos = {s.eos!r} needs {', '.join(own)}")
        if key not in own and given:
            raise ValueError(f"{where}.solid.{key} is not a key of eos = {s.eos!r}; remove it")


def _check_strength(where: str, s: SolidMaterial) -> None:
    if s.yield_stress is None:
        given = [key for key in STRENGTH_KEYS if getattr(s, key) is not None]
        if given:
            what = "a failure model" if given[0] == "failure" else "a strength parameter"
            raise ValueError(f"{where}.solid.{given[0]} is {what} without plasticity: the solid has no yield_stress "
                             "(elastic); give yield_stress (Pa) or remove it")
        return
    if s.melting_temperature is None:
        raise ValueError(f"{where}.solid.melting_temperature is missing; the Johnson-Cook strength (eq. 11) needs "
                         "Tm (K)")
    room = 293.0 if s.room_temperature is None else s.room_temperature
    if not s.melting_temperature > room:
        raise ValueError(f"{where}.solid.melting_temperature = {s.melting_temperature:g} K is not above "
                         f"room_temperature = {room:g} K")
    if s.rate_form is not None and s.rate_form not in RATE_FORMS:
        raise ValueError(f"{where}.solid.rate_form = {s.rate_form!r}: allowed: {', '.join(RATE_FORMS)}")
