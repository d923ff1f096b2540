"""Pieces shared by every kind of case: metadata, materials, contact pairs,
numerics. All quantities are SI (m, kg, s, Pa, N)."""

from __future__ import annotations

import math
import stat
import typing
import warnings
from pathlib import Path
from typing import Annotated, Any

from pydantic import AfterValidator, BaseModel, ConfigDict, Field, ValidationInfo, field_validator, model_validator

from orchestrator.engines import engine_names
from orchestrator.kinds import engines_for_kind

#: Largest magnitude of any number in a case (SI units): far beyond physics, far below where products overflow;
#: its inverse is the smallest non-zero magnitude.
MAX_MAGNITUDE = 1e30

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
    """Immutable model that rejects unknown keys and non-finite numbers (inf, nan) in every float field."""

    model_config = ConfigDict(frozen=True, extra="forbid", allow_inf_nan=False)

    def given(self, keys) -> list[str]:
        """The keys among `keys` that the case sets to something other than their default, in that order.

        A validator that refuses a key in some context asks this, not model_fields_set: run.h5 stores the case
        resolved (every default written out), and that text must validate again.
        """
        return [key for key in keys
                if key in self.model_fields_set and getattr(self, key) != type(self).model_fields[key].default]

    @field_validator("*", mode="before")
    @classmethod
    def _no_bool_for_number(cls, value: Any, info: ValidationInfo) -> Any:
        # pydantic would read true as 1 and false as 0 (e.g. media.count = true -> 1 ball).
        field = cls.model_fields.get(info.field_name or "")
        items = value if isinstance(value, (list, tuple)) else (value,)
        if field is not None and _numeric(field.annotation) and any(isinstance(v, bool) for v in items):
            raise ValueError("expected a number, not true/false")
        if field is not None and _numeric(field.annotation):
            for v in items:
                if not isinstance(v, (int, float)) or not math.isfinite(v) or v == 0:
                    continue
                which = f"{v:g} is" if len(items) > 1 else "is"
                if abs(v) > MAX_MAGNITUDE:
                    raise ValueError(f"{which} beyond any physical value in SI units; allowed: magnitudes up to "
                                     f"{MAX_MAGNITUDE:g} (products of larger numbers overflow)")
                if abs(v) < 1.0 / MAX_MAGNITUDE:
                    raise ValueError(f"{which} below any physical value in SI units; allowed: 0 or magnitudes from "
                                     f"{1.0 / MAX_MAGNITUDE:g} to {MAX_MAGNITUDE:g} (products of smaller numbers "
                                     "underflow to 0)")
        return value


#: What a name that reaches an engine's input may hold (materials and their contact pairs; SPH blocks, walls,
#: patches and probes): nothing in it can end a comment, a string or a line of a LIGGGHTS deck, a Yade script
#: or the SPH deck.
NAME_RULE = "a letter, then up to 63 letters, digits, '_', '.' or '-'"
_NAME_CHARACTERS = frozenset("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.-")


def check_name(value: str) -> str:
    """value if it is a name (NAME_RULE); ValueError saying what is allowed otherwise."""
    if not (0 < len(value) <= 64 and value[0].isascii() and value[0].isalpha() and set(value) <= _NAME_CHARACTERS):
        raise ValueError(f"not allowed as a name; allowed: {NAME_RULE}")
    return value


def check_label(value: str) -> str:
    """value if it is one line of printable text (at most 200 characters); ValueError otherwise."""
    if len(value) > 200 or not value.isprintable():
        raise ValueError("not allowed as a label; allowed: one line of printable text, at most 200 characters")
    return value


#: A name (check_name): material names, SPH object names.
Name = Annotated[str, AfterValidator(check_name)]
#: A free-text label shown in plots and reports (check_label).
Label = Annotated[str, AfterValidator(check_label)]


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
        if value not in engine_names():
            raise ValueError(f"unknown engine; allowed: {', '.join(engine_names())}")
        return value

    @model_validator(mode="after")
    def _engine_runs_kind(self):
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

    pair: tuple[Name, Name] = Field(description="two material names")
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


#: Mesh file types the scenes read (with trimesh), by extension.
MESH_EXTENSIONS = (".stl", ".obj", ".ply", ".off")
#: Largest mesh file read, bytes.
MAX_MESH_BYTES = 512 * 1024 * 1024


def mesh_file(value, base_dir: str, extensions=MESH_EXTENSIONS):
    """The absolute path of a mesh file named in a case (relative to the case file's folder).

    Raises ValueError (the loader names the key) when it does not exist, is not a regular file, has an
    extension other than `extensions`, or is larger than MAX_MESH_BYTES.
    """

    path = value if value.is_absolute() else Path(base_dir) / value
    try:
        info = path.stat()
    except OSError:
        raise ValueError(f"mesh file not found at {path}; give an existing mesh file "
                         f"({', '.join(extensions)}) or remove the key") from None

    if not stat.S_ISREG(info.st_mode):
        raise ValueError(f"{path} is not a regular file; give a mesh file ({', '.join(extensions)})")
    if path.suffix.lower() not in extensions:
        raise ValueError(f"{path} is not a mesh file: its extension {path.suffix or '(none)'!r} is not one of "
                         f"{', '.join(extensions)}")
    if info.st_size > MAX_MESH_BYTES:
        raise ValueError(f"{path} holds {info.st_size} bytes; allowed: mesh files up to {MAX_MESH_BYTES} bytes")
    check_mesh_content(path)
    return path.resolve()


def check_mesh_content(path: Path) -> None:
    """Raise ValueError when the mesh file at path cannot be read, has no triangle of non-zero area, or has a
    vertex coordinate that is not finite or beyond MAX_MAGNITUDE metres (before any scene is built from it)."""
    import numpy as np
    import trimesh

    try:  # overflowing normals of a huge mesh are reported below, not as numpy warnings
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            mesh = trimesh.load(str(path), force="mesh", process=False)
            vertices = np.asarray(mesh.vertices, dtype=float)
            faces = np.asarray(mesh.faces)
            area = float(np.sum(mesh.area_faces)) if len(faces) else 0.0
    except Exception as exc:  # trimesh raises many types for unreadable files
        raise ValueError(f"{path} cannot be read as a mesh ({type(exc).__name__}: {exc})") from None
    if len(vertices) == 0 or len(faces) == 0:
        raise ValueError(f"{path} holds no triangles; give a surface mesh")
    if not np.all(np.isfinite(vertices)) or np.abs(vertices).max() > MAX_MAGNITUDE:
        raise ValueError(f"{path} has a vertex coordinate that is not finite or beyond {MAX_MAGNITUDE:g} m; "
                         "allowed: finite coordinates in metres within that magnitude")
    if not area > 0.0:
        raise ValueError(f"{path} is degenerate: all its triangles have zero area")


def rayleigh_timestep(radius_m: float, material: Material, stiffness_scale: float = 1.0) -> float:
    """Rayleigh critical time step of a sphere, s: pi R sqrt(rho/G) / (0.1631 nu + 0.8766)."""

    shear = material.shear_modulus * stiffness_scale
    return math.pi * radius_m * math.sqrt(material.density / shear) / (0.1631 * material.poisson_ratio + 0.8766)


class MaterialCase(Frozen):
    """Base of every DEM case: metadata, materials and contact pairs, with the pair lookup."""

    case: CaseMeta
    materials: dict[str, Material] = Field(min_length=1)

    @field_validator("materials")
    @classmethod
    def _material_names(cls, value: dict) -> dict:
        for name in value:
            try:
                check_name(name)
            except ValueError:
                raise ValueError(f"the material name {name!r} is not allowed; allowed: {NAME_RULE}") from None
        return value
    contacts: tuple[ContactPair, ...] = Field(min_length=1)

    def contact(self, a: str, b: str) -> ContactPair:
        """The contact parameters of materials a and b (raises ValueError naming the gap)."""
        for contact in self.contacts:
            if sorted(contact.pair) == sorted((a, b)):
                return contact
        raise ValueError(f"contacts has no entry for the pair ({a}, {b}); add [[contacts]] pair = [{a!r}, {b!r}]")
