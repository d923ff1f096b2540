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
"""

from __future__ import annotations

from dataclasses import dataclass

from pydantic import Field, field_validator

from orchestrator.case.common import Frozen, Name, Positive
from orchestrator.kinds.sph_flow.case_parts import Finite

#: Material models of the sph executable (engines/sph/src/material_models.h).
MATERIAL_MODELS = ("newtonian",)

#: Keys of [fluid] that each [[materials]] table takes instead when the case has materials.
MATERIAL_KEYS = ("density", "viscosity", "sound_speed", "gamma", "background_pressure")


class Material(Frozen):
    """One [[materials]] table: a weakly compressible fluid with its own reference density, viscosity and Tait
    EOS (eq. 6); blocks name it. Keys and units are those of [fluid]."""

    name: Name = Field(description="identifier, named by blocks[].material")
    model: str = Field(description="constitutive model: newtonian")
    density: Positive = Field(description="reference density rho0, kg/m^3")
    viscosity: Positive | None = Field(
        None, description="kinematic viscosity nu, m^2/s; given exactly when physics.terms has morris_viscosity"
    )
    sound_speed: Positive | None = Field(
        None, description="reference sound speed c0, m/s; default 10 fluid.max_speed; at least 10 fluid.max_speed"
    )
    gamma: float = Field(7.0, ge=1, description="exponent of the Tait equation of state, -")
    background_pressure: Finite = Field(0.0, description="background pressure p_B of eq. 6, Pa")

    @field_validator("model")
    @classmethod
    def _known_model(cls, value: str) -> str:
        if value not in MATERIAL_MODELS:
            raise ValueError(f"unknown material model {value!r}; allowed: {', '.join(MATERIAL_MODELS)}")
        return value


@dataclass(frozen=True)
class RunMaterial:
    """A material as the run uses it: name, model, rho0 kg/m^3, c0 m/s, gamma -, p_B Pa, nu m^2/s (or None)."""

    name: str
    model: str
    rho0: float
    c0: float
    gamma: float
    background_pressure: float
    viscosity: float | None

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
    return tuple(RunMaterial(m.name, m.model, m.density, m.sound_speed if m.sound_speed is not None else speed,
                             m.gamma, m.background_pressure, m.viscosity) for m in case.materials)


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
    given = [key for key in MATERIAL_KEYS if key in fluid.model_fields_set]
    if given:
        raise ValueError(f"fluid.{given[0]} is given with [[materials]]; give it in each [[materials]] table "
                         "([fluid] then holds only max_speed)")
    names: set[str] = set()
    for i, m in enumerate(case.materials):
        if m.name in names:
            raise ValueError(f"materials[{i}].name = {m.name!r} is used twice; names must be unique")
        names.add(m.name)
        if morris and m.viscosity is None:
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
