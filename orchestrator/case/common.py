"""Pieces shared by every kind of case: metadata, materials, contact pairs,
numerics. All quantities are SI (m, kg, s, Pa, N)."""

from __future__ import annotations

import typing
from typing import Annotated, Any

from pydantic import BaseModel, ConfigDict, Field, ValidationInfo, field_validator, model_validator

Positive = Annotated[float, Field(gt=0)]
NonNegative = Annotated[float, Field(ge=0)]
Fraction = Annotated[float, Field(gt=0, le=1)]


def _numeric(annotation: Any) -> bool:
    """True if the annotation is (or contains) a number type and no bool."""
    if annotation is bool:
        return False
    if annotation in (int, float):
        return True
    args = typing.get_args(annotation)
    return bool(args) and bool not in args and any(_numeric(a) for a in args)


class Frozen(BaseModel):
    """Immutable model that rejects unknown keys."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    @field_validator("*", mode="before")
    @classmethod
    def _no_bool_for_number(cls, value: Any, info: ValidationInfo) -> Any:
        # pydantic would read true as 1 and false as 0 (e.g. media.count = true -> 1 ball).
        field = cls.model_fields.get(info.field_name or "")
        items = value if isinstance(value, (list, tuple)) else (value,)
        if field is not None and _numeric(field.annotation) and any(isinstance(v, bool) for v in items):
            raise ValueError("expected a number, not true/false")
        return value


class CaseMeta(Frozen):
    """The [case] table: what the case is and which engine runs it by default."""

    kind: str = Field(description="scene type, e.g. 'drag_finishing'")
    name: str = Field(min_length=1, pattern=r"^[A-Za-z0-9_.-]+$", description="identifier used in run names")
    description: str = ""
    engine: str = Field("yade", description="default engine; --engine overrides it")
    seed: int = Field(0, ge=0, description="seed of every random draw (particle cloud)")

    @field_validator("engine")
    @classmethod
    def _known_engine(cls, value: str) -> str:
        from ..backends import engine_names

        if value not in engine_names():
            raise ValueError(f"unknown engine; allowed: {', '.join(engine_names())}")
        return value

    @model_validator(mode="after")
    def _engine_runs_kind(self):
        from ..backends import engines_for_kind

        engines = engines_for_kind(self.kind)
        if engines and self.engine not in engines:
            raise ValueError(f"case.engine = {self.engine!r} does not run {self.kind} cases; allowed: {', '.join(engines)}")
        return self


class Material(Frozen):
    """An elastic material (one row of the paper's section 5 table)."""

    density: Positive = Field(description="kg/m^3")
    young_modulus: Positive = Field(description="Young's modulus E, Pa")
    poisson_ratio: float = Field(ge=0, lt=0.5, description="Poisson's ratio nu, -")

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + nu)), Pa (paper eq. 6)."""
        return self.young_modulus / (2.0 * (1.0 + self.poisson_ratio))


class ContactPair(Frozen):
    """Restitution and friction of one material pair (order does not matter)."""

    pair: tuple[str, str] = Field(description="two material names")
    restitution: float = Field(gt=0, le=1, description="normal coefficient of restitution e_n, -")
    tangential_restitution: float | None = Field(
        None, gt=0, le=1, description="e_t, -; the paper sets e_t = e_n, which is the default"
    )
    friction: NonNegative = Field(description="Coulomb friction coefficient mu, -")

    @property
    def e_t(self) -> float:
        """Tangential restitution, -: e_t if given, else e_n (the paper's choice)."""
        return self.restitution if self.tangential_restitution is None else self.tangential_restitution


class Numerics(Frozen):
    """Time stepping and the stiffness reduction commonly used to speed DEM up."""

    timestep_factor: float = Field(
        0.3, gt=0, le=1, description="time step as a fraction of the Rayleigh critical step, -"
    )
    stiffness_scale: float = Field(
        1.0, gt=0, le=1, description="factor applied to every Young's modulus (1 = physical), -"
    )
    threads: int = Field(1, ge=1, le=256, description="engine threads (Yade -j)")


def rayleigh_timestep(radius_m: float, material: Material, stiffness_scale: float = 1.0) -> float:
    """Rayleigh critical time step of a sphere, s: pi R sqrt(rho/G) / (0.1631 nu + 0.8766)."""
    import math

    shear = material.shear_modulus * stiffness_scale
    return math.pi * radius_m * math.sqrt(material.density / shear) / (0.1631 * material.poisson_ratio + 0.8766)


class MaterialCase(Frozen):
    """Base of every DEM case: metadata, materials and contact pairs, with the pair lookup."""

    case: CaseMeta
    materials: dict[str, Material] = Field(min_length=1)
    contacts: tuple[ContactPair, ...] = Field(min_length=1)

    def contact(self, a: str, b: str) -> ContactPair:
        """The contact parameters of materials a and b (raises ValueError naming the gap)."""
        for contact in self.contacts:
            if sorted(contact.pair) == sorted((a, b)):
                return contact
        raise ValueError(f"contacts has no entry for the pair ({a}, {b}); add [[contacts]] pair = [{a!r}, {b!r}]")
