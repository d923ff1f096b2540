"""Materials of an SPH flow case (kind "sph_flow"): the [[materials]] tables of a scene made of several
weakly compressible fluids, each block naming its own, and the table of materials a run uses (one material
from [fluid] when the case has no [[materials]]). SI units (kg/m^3, m^2/s, m/s, Pa).

    [fluid]
    max_speed = 2.5e-4            # the only [fluid] key with [[materials]]

    [[materials]]
    name = "water"
    model = "newtonian"
    density = 1000.0              # kg/m^3
    viscosity = 1.0e-6            # m^2/s (kinematic, with morris_viscosity)

    [[blocks]]
    name = "lower"
    kind = "fluid"
    material = "water"
    ...

Across two materials the Morris term (eq. 10) takes the harmonic mean of their dynamic viscosities rho0 nu
(engines/sph/src/material.h).

A viscoelastic material is a multi-mode linear Phan-Thien-Tanner fluid (Nutto et al., eqs. 1-9;
engines/sph/src/materials/ptt.h), its modes in the key names `orchestrator calibrate maxwell` writes, so a fitted
fragment's [[material.modes]] tables paste in as [[materials.modes]]:

    [[materials]]
    name = "mf20"
    model = "ptt"
    density = 1000.0              # kg/m^3
    epsilon = 0.1                 # -, extensibility (0: Oldroyd-B / UCM)
    solvent_viscosity = 0.0       # Pa s
    eos = "quadratic"             # "tait" (Canini et al. eq. 6, default) or Nutto et al.'s p = c0^2 rho^2 / (2 rho0)

    storage_plateau = 0.0         # G_p, Pa: an upper-convected elastic stress beside the modes (0: none)

    [[materials.modes]]
    relaxation_time = 0.5         # lambda_i, s
    viscosity = 738.0             # eta_i, Pa s (a dynamic viscosity)

    [materials.cross_loss]        # optional: a Cross-law solvent, 2 eta_C(gamma_dot) D beside 2 eta_s D
    zero_shear_viscosity = 2.0e4  # eta_0, Pa s
    infinite_shear_viscosity = 10.0   # eta_inf, Pa s (<= eta_0)
    time_constant = 0.3           # K, s
    exponent = 0.8                # m, in (0, 1]

Conventions: per mode f_i tau_i + lambda_i tau_i^nabla = 2 eta_i D with D = (grad v + grad v^T)/2 (the paper's
eq. 5 has no 1/2; with it eta_i stays a viscosity: lambda_i -> 0 gives tau_i = 2 eta_i D), and each mode has its
own f_i = 1 + (lambda_i epsilon / eta_i) tr tau_i. The sph executable compiles PTT alone, with artificial
viscosity, in a Lees-Edwards cell, or with 'morris_viscosity' (one material; the Morris term then carries the
solvent viscosity, which damps the row zig-zag mode of walled channels): no Newtonian material beside it, and a
fixed numerics.dt (its adaptive step does not know the relaxation and viscous limits of the modes).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from pydantic import Field, field_validator, model_validator

from orchestrator.case.common import Frozen, Name, NonNegative, Positive
from orchestrator.kinds.sph_flow.case_parts import Finite
from orchestrator.kinds.sph_flow.case_solids import SolidMaterial, check_solid

#: Material models of the sph executable (engines/sph/src/material_models.h).
MATERIAL_MODELS = ("newtonian", "ptt", "johnson_cook")

#: Equations of state of the sph executable: Tait (Canini et al. eq. 6) and Nutto et al.'s quadratic p = c0^2 rho^2/(2 rho0).
EQUATIONS_OF_STATE = ("tait", "quadratic")

#: Most PTT modes a material may have (engines/sph max_stress_modes).
MAX_MODES = 8

#: Keys only a ptt material takes.
PTT_KEYS = ("modes", "epsilon", "solvent_viscosity", "storage_plateau", "cross_loss", "stress_diffusion")

#: Keys of [fluid] that each [[materials]] table takes instead when the case has materials.
MATERIAL_KEYS = ("density", "viscosity", "sound_speed", "gamma", "background_pressure")


class PttMode(Frozen):
    """One [[materials.modes]] table of a ptt material: a Maxwell mode (the keys `calibrate maxwell` writes)."""

    relaxation_time: Positive = Field(description="relaxation time lambda_i, s")
    viscosity: Positive = Field(description="mode viscosity eta_i, Pa s (G_i = eta_i / lambda_i)")


class CrossLoss(Frozen):
    """A Cross-law solvent, the [material.cross_loss] table `calibrate maxwell --cross` writes:
    eta_C(gamma_dot) = eta_inf + (eta_0 - eta_inf) / (1 + (K gamma_dot)^m), gamma_dot = sqrt(2 D:D) of the flow."""

    zero_shear_viscosity: Positive = Field(description="zero-shear viscosity eta_0, Pa s")
    infinite_shear_viscosity: NonNegative = Field(description="infinite-shear viscosity eta_inf, Pa s (at most eta_0)")
    time_constant: Positive = Field(description="time constant K, s")
    exponent: float = Field(description="exponent m, - (0 < m <= 1: the shear stress rises with the shear rate)")

    @model_validator(mode="after")
    def _thinning(self):
        if self.infinite_shear_viscosity > self.zero_shear_viscosity:
            raise ValueError(f"cross_loss.infinite_shear_viscosity = {self.infinite_shear_viscosity:g} Pa s is above "
                             f"zero_shear_viscosity = {self.zero_shear_viscosity:g} Pa s; a Cross law thins")
        if not 0.0 < self.exponent <= 1.0:
            raise ValueError(f"cross_loss.exponent = {self.exponent:g}; allowed: 0 < m <= 1 (above 1 the shear "
                             "stress falls with the shear rate: an ill-posed solvent)")
        return self

    @property
    def law(self) -> tuple[float, float, float, float]:
        """(eta_0 Pa s, eta_inf Pa s, K s, m -)."""
        return (self.zero_shear_viscosity, self.infinite_shear_viscosity, self.time_constant, self.exponent)

    def viscosity(self, shear_rate):
        """eta_C at shear rates gamma_dot (1/s, scalar or array), Pa s."""
        eta_0, eta_inf, time, exponent = self.law
        return eta_inf + (eta_0 - eta_inf) / (1.0 + (time * np.abs(np.asarray(shear_rate, dtype=float))) ** exponent)

    def deck(self) -> dict:
        """The engine's `cross_viscosity` object (Pa s, s, -)."""
        eta_0, eta_inf, time, exponent = (float(v) for v in self.law)
        return {"eta_0": eta_0, "eta_inf": eta_inf, "time_constant": time, "exponent": exponent}


class Material(Frozen):
    """One [[materials]] table: a weakly compressible fluid with its own reference density, viscosity and
    equation of state; blocks name it. Keys and units are those of [fluid]; a ptt material has modes instead of
    a (Morris) viscosity."""

    name: Name = Field(description="identifier, named by blocks[].material")
    model: str = Field(description="constitutive model: newtonian, ptt or johnson_cook (a solid, case_solids.py)")
    density: Positive = Field(description="reference density rho0, kg/m^3")
    viscosity: Positive | None = Field(
        None, description="kinematic viscosity nu, m^2/s; given exactly when physics.terms has morris_viscosity"
    )
    sound_speed: Positive | None = Field(
        None, description="reference sound speed c0, m/s; default 10 fluid.max_speed; at least 10 fluid.max_speed"
    )
    gamma: float = Field(7.0, ge=1, description="exponent of the Tait equation of state, -")
    background_pressure: Finite = Field(0.0, description="background pressure p_B of eq. 6, Pa")
    eos: str = Field("tait", description="equation of state: tait (Canini et al. eq. 6) or quadratic (Nutto et al. eq. 9, "
                                         "p = c0^2 rho^2 / (2 rho0) + p_B; gamma is then not used)")
    modes: tuple[PttMode, ...] = Field((), description="ptt: the Maxwell modes, 1 to 8 [[materials.modes]] tables")
    epsilon: NonNegative | None = Field(None, description="ptt: extensibility parameter epsilon of f_i, - (0: "
                                                          "Oldroyd-B / UCM; default 0)")
    solvent_viscosity: NonNegative | None = Field(None, description="ptt: solvent viscosity eta_s, Pa s (default 0)")
    storage_plateau: NonNegative | None = Field(None, description="ptt: plateau modulus G_p, Pa (an upper-convected "
                                                "elastic stress; default 0: none; with it at most 7 modes)")
    cross_loss: CrossLoss | None = Field(None, description="ptt: a Cross-law solvent viscosity beside eta_s "
                                         "([materials.cross_loss]: zero_shear_viscosity, infinite_shear_viscosity "
                                         "Pa s, time_constant s, exponent -)")
    stress_diffusion: NonNegative | None = Field(None, description="ptt: diffusivity kappa of the mode stresses, m^2/s "
                                                 "(eq. SD1 of the engine; default 0: none; compiled for a Lees-Edwards cell with morris_viscosity)")
    solid: SolidMaterial | None = Field(None, description="johnson_cook: the [materials.solid] table (elasticity, "
                                                          "equation of state, strength, heat, failure)")

    @field_validator("eos")
    @classmethod
    def _known_eos(cls, value: str) -> str:
        if value not in EQUATIONS_OF_STATE:
            raise ValueError(f"unknown equation of state {value!r}; allowed: {', '.join(EQUATIONS_OF_STATE)}")
        return value

    @field_validator("model")
    @classmethod
    def _known_model(cls, value: str) -> str:
        if value not in MATERIAL_MODELS:
            raise ValueError(f"unknown material model {value!r}; allowed: {', '.join(MATERIAL_MODELS)}")
        return value


@dataclass(frozen=True)
class RunMaterial:
    """A material as the run uses it: name, model, rho0 kg/m^3, c0 m/s, gamma -, p_B Pa, nu m^2/s (or None),
    eos ('tait' or 'quadratic'); ptt: modes ((lambda_i s, eta_i Pa s), ...), epsilon -, eta_s Pa s."""

    name: str
    model: str
    rho0: float
    c0: float
    gamma: float
    background_pressure: float
    viscosity: float | None
    eos: str = "tait"
    modes: tuple[tuple[float, float], ...] = ()
    epsilon: float = 0.0
    solvent_viscosity: float = 0.0
    storage_plateau: float = 0.0
    cross_loss: dict | None = None  # the engine's cross_viscosity object (CrossLoss.deck)
    solid: dict | None = None  # johnson_cook: its deck keys (case_solids.SolidMaterial.deck); c0 is its wave speed
    stress_diffusion: float = 0.0  # ptt: kappa m^2/s of eq. SD1 (0: none)

    def deck(self) -> dict:
        """The material as the deck's JSON object (engines/sph/README.md, `materials`), SI units."""
        if self.solid is not None:
            return {"name": self.name, "model": self.model, "rho0": float(self.rho0), **self.solid}
        item = {"name": self.name, "model": self.model, "rho0": float(self.rho0), "c0": float(self.c0)}
        if self.eos != "tait":
            item["eos"] = self.eos
        else:
            item["gamma"] = float(self.gamma)
        item["background_pressure"] = float(self.background_pressure)
        if self.viscosity is not None:
            item["viscosity"] = float(self.viscosity)
        if self.model == "ptt":
            item.update(epsilon=float(self.epsilon), solvent_viscosity=float(self.solvent_viscosity),
                        modes=[{"lambda": float(lam), "eta": float(eta)} for lam, eta in self.modes])
            if self.storage_plateau > 0.0:
                item["storage_plateau"] = float(self.storage_plateau)
            if self.cross_loss is not None:
                item["cross_viscosity"] = dict(self.cross_loss)
            if self.stress_diffusion > 0.0:
                item["stress_diffusion"] = float(self.stress_diffusion)
        return item

    @property
    def mu(self) -> float:
        """Dynamic viscosity rho0 nu, Pa s (0 without viscosity)."""
        return 0.0 if self.viscosity is None else self.rho0 * self.viscosity


def run_materials(case) -> tuple[RunMaterial, ...]:
    """The case's materials in [[materials]] order, or the one material "fluid" of [fluid] without them."""
    if not case.materials:
        f = case.fluid
        return (RunMaterial("fluid", "newtonian", f.density, f.c0, f.gamma, f.background_pressure, f.viscosity),)
    speed = 10.0 * case.fluid.max_speed
    return tuple(RunMaterial(m.name, m.model, m.density, _sound_speed(m, speed), m.gamma, m.background_pressure,
                             m.viscosity, m.eos, tuple((mode.relaxation_time, mode.viscosity) for mode in m.modes),
                             m.epsilon or 0.0, m.solvent_viscosity or 0.0, m.storage_plateau or 0.0,
                             None if m.cross_loss is None else m.cross_loss.deck(),
                             None if m.solid is None else m.solid.deck(), m.stress_diffusion or 0.0)
                 for m in case.materials)


def _sound_speed(m: Material, default: float) -> float:
    """c0 of a material, m/s: a solid's wave speed, a fluid's sound_speed or the default 10 max_speed."""
    if m.solid is not None:
        return m.solid.wave_speed(m.density)
    return m.sound_speed if m.sound_speed is not None else default


def largest_c0_and_viscosity(materials) -> tuple[float, float | None]:
    """The largest sound speed (m/s) and kinematic viscosity (m^2/s, None if no material has one) of run
    materials: what the engine's adaptive step takes (engines/sph/README.md, "Materials")."""
    return (max(m.c0 for m in materials),
            max((m.viscosity for m in materials if m.viscosity is not None), default=None))


def block_materials(case) -> tuple[int, ...]:
    """Index into run_materials(case) of every block's material (0 for all without [[materials]])."""
    if not case.materials:
        return (0,) * len(case.blocks)
    index = {m.name: k for k, m in enumerate(case.materials)}
    return tuple(index[b.material] for b in case.blocks)


def check_materials(case) -> None:
    """The materials against [fluid], the physics terms and the blocks; ValueError naming the key."""
    fluid, morris = case.fluid, "morris_viscosity" in case.physics.terms
    if not case.materials:
        if fluid.density is None:
            raise ValueError("fluid.density is missing; give it (kg/m^3), or describe the fluids as [[materials]]")
        named = [(f"blocks[{i}]", b.material) for i, b in enumerate(case.blocks)]
        named += [(f"inlets[{i}]", p.material) for i, p in enumerate(case.inlets)]
        for key, material in named:
            if material is not None:
                raise ValueError(f"{key}.material = {material!r} names a material but the case has no "
                                 "[[materials]]; add them or remove the key")
        return
    if fluid.min_pressure is not None:
        raise ValueError("fluid.min_pressure (a cavitation floor) applies to one-fluid cases; this case has "
                         "[[materials]], which do not take one yet: remove the key")
    given = fluid.given(MATERIAL_KEYS)
    if given:
        raise ValueError(f"fluid.{given[0]} is given with [[materials]]; give it in each [[materials]] table "
                         "([fluid] then holds only max_speed)")
    names: set[str] = set()
    for i, m in enumerate(case.materials):
        if m.name in names:
            raise ValueError(f"materials[{i}].name = {m.name!r} is used twice; names must be unique")
        names.add(m.name)
        model = getattr(m, "model", "newtonian")
        if model == "johnson_cook":
            check_solid(case, i, m)
            continue
        if getattr(m, "solid", None) is not None:
            raise ValueError(f"materials[{i}].solid ({m.name}) is the table of a johnson_cook material; this one "
                             f"is {model}: remove it or set model = \"johnson_cook\"")
        given = [key for key in PTT_KEYS if getattr(m, key, None) not in (None, ())]
        if model == "ptt":
            _check_ptt(case, i, m)
        elif given:
            raise ValueError(f"materials[{i}].{given[0]} ({m.name}) is a key of a ptt material; this one is "
                             f"{model}: remove it or set model = \"ptt\"")
        elif morris and m.viscosity is None:
            raise ValueError(f"materials[{i}].viscosity ({m.name}) is missing; physics.terms has 'morris_viscosity'")
        if m.viscosity is not None and not morris:
            raise ValueError(f"materials[{i}].viscosity ({m.name}) is given but 'morris_viscosity' is not in "
                             "physics.terms; add it or remove the key")
        if m.sound_speed is not None and m.sound_speed < 10.0 * fluid.max_speed * (1 - 1e-12):
            raise ValueError(f"materials[{i}].sound_speed = {m.sound_speed} m/s is below 10 x fluid.max_speed = "
                             f"{10 * fluid.max_speed:g} m/s; weakly compressible SPH needs c0 >= 10 v_max")
    for i, block in enumerate(case.blocks):
        if block.material is None:
            raise ValueError(f"blocks[{i}].material ({block.name}) is missing; with [[materials]] every block, "
                             f"fluid or boundary, names its material; allowed: {', '.join(sorted(names))}")
        if block.material not in names:
            raise ValueError(f"blocks[{i}].material = {block.material!r} ({block.name}) is not a [[materials]] "
                             f"name; allowed: {', '.join(sorted(names))}")
    for i, inlet in enumerate(case.inlets):
        if inlet.material is not None and inlet.material not in names:
            raise ValueError(f"inlets[{i}].material = {inlet.material!r} is not a [[materials]] name; allowed: "
                             f"{', '.join(sorted(names))}")


def _check_ptt(case, i: int, m: Material) -> None:
    """A ptt material against what the sph executable compiles (engines/sph/src/configurations.h)."""
    where = f"materials[{i}]"
    if not m.modes:
        raise ValueError(f"{where}.modes ({m.name}) is missing; a ptt material needs 1 to {MAX_MODES} "
                         "[[materials.modes]] tables (relaxation_time s, viscosity Pa s)")
    most = MAX_MODES - (1 if (m.storage_plateau or 0.0) > 0.0 else 0)  # the plateau takes a stress column
    if len(m.modes) > most:
        raise ValueError(f"{where}.modes ({m.name}) has {len(m.modes)} modes; allowed: 1 to {most}"
                         + (" beside a storage_plateau" if most < MAX_MODES else ""))
    if m.viscosity is not None:
        raise ValueError(f"{where}.viscosity ({m.name}) is not a key of a ptt material (its viscosities are the "
                         "modes' and solvent_viscosity, Pa s); remove it")
    if "morris_viscosity" in case.physics.terms:
        if not (m.solvent_viscosity or 0.0) > 0.0:
            raise ValueError(f"{where}.solvent_viscosity ({m.name}) must be > 0 with 'morris_viscosity' in "
                             "physics.terms: the Morris term carries a ptt material's solvent viscosity")
        fluids = [o.name for o in case.materials if o.model != "johnson_cook"]
        if len(fluids) > 1:
            raise ValueError(f"{where} ({m.name}): 'morris_viscosity' with a ptt material needs it to be the only "
                             f"fluid [[materials]] table (here also {[f for f in fluids if f != m.name][0]!r}); the "
                             "sph executable compiles PTT with the Morris term for one fluid, alone or beside "
                             "johnson_cook solids")
    others = [o.name for o in case.materials if o.model not in ("ptt", "johnson_cook")]
    if others:
        raise ValueError(f"{where} ({m.name}) is a ptt material beside the {others[0]!r} material of another "
                         "model; the sph executable runs PTT materials with each other or beside johnson_cook solids")
    solids = [o.name for o in case.materials if o.model == "johnson_cook"]
    if solids and "morris_viscosity" not in case.physics.terms:
        raise ValueError(f"{where} ({m.name}) is a ptt medium beside the johnson_cook material {solids[0]!r}: "
                         "physics.terms needs 'morris_viscosity' (its solvent, the no-slip on the solid; the "
                         "compiled configurations of a PTT medium on a solid carry it)")
    if m.eos == "quadratic" and m.given(("gamma",)):
        raise ValueError(f"{where}.gamma ({m.name}) is the Tait exponent; the quadratic eos does not use it: "
                         "remove it")
    if case.numerics.dt is None:
        raise ValueError(f"numerics.dt is missing: a ptt material ({where}, {m.name}) needs a fixed time step "
                         "(the adaptive step does not know the modes' relaxation and viscous limits)")
