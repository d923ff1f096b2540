"""The parts of an SPH flow case (kind "sph_flow"): domain, fluid, physics terms, particle blocks, walls, inlets and
outlets and probes (numerics, output and expected checks: case_run.py). SI units (m, kg, s, Pa, N); in 2D a mass is per metre of depth (kg/m) and a
force per metre (N/m). case.py assembles them into SphFlowCase and checks them against each other."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Literal

from pydantic import Field, ValidationInfo, field_validator, model_validator

from orchestrator.case.common import Frozen, Name, NonNegative, Positive, mesh_file
from orchestrator.kinds.sph_flow.case_cylinder import BlockCylinder
from orchestrator.reference.sph_flows import tait_density

#: Optional physics terms of the sph executable (engines/sph/src/physics_terms.h).
PHYSICS_TERMS = ("morris_viscosity", "artificial_viscosity", "body_force", "wall_penalty")


#: Sides of a box wall, for BoxWall.open_sides.
BOX_SIDES = ("-x", "+x", "-y", "+y", "-z", "+z")


#: Relative tolerance of "is a multiple of dx" and "lies inside the domain".
LATTICE_TOLERANCE = 1e-6


Finite = Annotated[float, Field(allow_inf_nan=False)]


Vector = Annotated[tuple[Finite, ...], Field(min_length=2, max_length=3)]


def _norm(vector) -> float:
    return math.sqrt(sum(c * c for c in vector))


class Domain(Frozen):
    """The box that holds the scene, and its periodic axes."""

    dimension: Literal[2, 3] = Field(description="2 (x, y) or 3 (x, y, z)")
    lo: Vector = Field(description="lower corner of the box, m (one value per axis)")
    hi: Vector = Field(description="upper corner of the box, m; along a periodic axis the period is hi - lo")
    periodic: tuple[int, ...] = Field((), description="indices of the periodic axes (0 = x, 1 = y, 2 = z), -")

    @field_validator("periodic")
    @classmethod
    def _distinct_axes(cls, value: tuple[int, ...]) -> tuple[int, ...]:
        if len(set(value)) != len(value):
            raise ValueError("an axis is listed twice")
        return value

    @model_validator(mode="after")
    def _box(self):
        for key in ("lo", "hi"):
            if len(getattr(self, key)) != self.dimension:
                raise ValueError(f"domain.{key} has {len(getattr(self, key))} values; allowed: one per axis "
                                 f"(domain.dimension = {self.dimension})")
        for axis, (a, b) in enumerate(zip(self.lo, self.hi)):
            if not b > a:
                raise ValueError(f"domain.hi[{axis}] = {b} is not above domain.lo[{axis}] = {a}; allowed: hi > lo")
        for axis in self.periodic:
            if not 0 <= axis < self.dimension:
                raise ValueError(f"domain.periodic lists axis {axis}; allowed: 0 to {self.dimension - 1}")
        return self

    def contains(self, point, margin: float = 0.0) -> bool:
        """True if point (m) lies inside the box grown by margin (m) on every side."""
        return all(lo - margin <= p <= hi + margin for p, lo, hi in zip(point, self.lo, self.hi))


class Fluid(Frozen):
    """The fluid: reference density, viscosity and the weakly compressible equation of state (eq. 6).

    With [[materials]] it holds only max_speed; each material then has its own density, viscosity and EOS.
    """

    density: Positive | None = Field(None, description="reference density rho0, kg/m^3 (required without "
                                                       "[[materials]])")
    viscosity: Positive | None = Field(
        None, description="kinematic viscosity nu, m^2/s; given exactly when physics.terms has morris_viscosity"
    )
    max_speed: Positive = Field(description="largest speed expected in the flow, m/s (sets c0 = 10 max_speed)")
    sound_speed: Positive | None = Field(
        None, description="reference sound speed c0, m/s; default 10 max_speed; at least 10 max_speed"
    )
    gamma: float = Field(7.0, ge=1, description="exponent of the Tait equation of state, -")
    background_pressure: Finite = Field(0.0, description="background pressure p_B of eq. 6, Pa")
    min_pressure: Finite | None = Field(
        None, description="cavitation floor: the fluid's pressure is at least this, Pa (gauge, as p_B; water: its "
                          "vapour pressure less the ambient, about -0.99e5); below p_B; default none (any tension); "
                          "one-fluid cases only (not with [[materials]])")

    @property
    def c0(self) -> float:
        """Reference sound speed, m/s: sound_speed, or 10 max_speed."""
        return self.sound_speed if self.sound_speed is not None else 10.0 * self.max_speed

    @property
    def floor_density(self) -> float:
        """The density of min_pressure (eq. 6 inverted), kg/m^3; 0 without a floor. A cavitating particle below
        it holds this much liquid, the rest of its volume vapour (the engine counts it so in flow planes)."""
        if self.min_pressure is None:
            return 0.0
        return float(tait_density(self.min_pressure, self.density, self.c0, self.gamma, self.background_pressure))

    @model_validator(mode="after")
    def _floor_below_rest(self):
        if self.min_pressure is not None and not self.min_pressure < self.background_pressure:
            raise ValueError(f"fluid.min_pressure = {self.min_pressure:g} Pa must lie below the rest pressure "
                             f"fluid.background_pressure = {self.background_pressure:g} Pa")
        return self

    @model_validator(mode="after")
    def _fast_enough(self):
        if self.sound_speed is not None and self.sound_speed < 10.0 * self.max_speed * (1 - 1e-12):
            raise ValueError(f"fluid.sound_speed = {self.sound_speed} m/s is below 10 x fluid.max_speed = "
                             f"{10 * self.max_speed:g} m/s; weakly compressible SPH needs c0 >= 10 v_max "
                             "(density error < 1 %); raise sound_speed or leave it out")
        return self


class ArtificialViscosity(Frozen):
    """Monaghan's artificial viscosity (eqs. 11-12)."""

    alpha: NonNegative = Field(description="linear coefficient alpha, -")
    beta: NonNegative = Field(0.0, description="quadratic coefficient beta, -")
    walls: bool = Field(True, description=(
        "whether eqs. 11-12 also act between a fluid particle and a fixed one (boundary, inlet or outlet "
        "buffer particle). false keeps them to fluid-fluid pairs, and the wall friction comes from the Morris "
        "viscosity with the no-slip wall velocity only: with true, a uniform 11 m/s flow through the drill's "
        "clearance past fixed boundary particles lost 0.75 bar/mm at alpha = 0.1, an effective viscosity "
        "about 120 x alpha h c0 / 10, against a laminar loss near zero (docs/ejector_drill.md)"))


class WallPenalty(Frozen):
    """The penalty force of eq. 14 between a particle and a mesh face at distance d."""

    range: Positive = Field(description="R, distance beyond which the wall does not act, m")
    s: Positive = Field(description="distance of zero force (repulsive below s, attractive between s and R), m")
    psi: NonNegative = Field(description="force at zero distance psi, N (2D: N/m)")

    @model_validator(mode="after")
    def _s_below_range(self):
        if not self.s < self.range:
            raise ValueError(f"physics.wall_penalty.s = {self.s} m is not below range = {self.range} m; allowed: s < R")
        return self


class Physics(Frozen):
    """The optional terms the scene uses, and their parameters (given exactly when the term is on)."""

    terms: tuple[str, ...] = Field(
        description="optional terms switched on: morris_viscosity, artificial_viscosity, body_force, wall_penalty "
                    "(continuity, Tait EOS and pressure gradient are always on)"
    )
    body_force: Vector | None = Field(None, description="body force per unit mass (e.g. gravity), m/s^2")
    body_force_on: Literal["all", "fluids"] = Field("all", description=(
        "what the body force acts on: all (every moving particle and grain: gravity), fluids (the fluids' particles "
        "only, the grains and solids none: a flow driven by a pressure gradient past a held workpiece, as Nutto et "
        "al.'s channel)"))
    artificial_viscosity: ArtificialViscosity | None = None
    wall_penalty: WallPenalty | None = None
    viscosity_correction: bool = Field(False, description=(
        "renormalise the Morris viscous sum of each particle by k_a = D / sum_b V_b (-F_ab) r_ab^4 / (r_ab^2 + "
        "0.01 h^2), so a quadratic velocity field gets the exact Laplacian on a regular lattice (the plain sum "
        "gives 0.97 of it at h = 1.3 dx in 3D; engine eq. VC1, engines/sph/src/viscosity_correction.h); needs "
        "morris_viscosity"))
    eddy_viscosity: float | None = Field(None, gt=0.0, le=1.0, description=(
        "Smagorinsky's constant cs (0.1-0.2): adds the eddy viscosity nu_t = (cs dx)^2 |S| m^2/s to the Morris "
        "term's nu (the Reynolds stresses of a flow the lattice does not resolve; engine eqs. SM1-SM2, "
        "engines/sph/src/eddy_viscosity.h); needs morris_viscosity, not with viscosity_correction"))
    balance_mean_weight: bool = Field(False, description=(
        "a box periodic along the body force g: the mean weight of fluid and grains is carried by a mean pressure "
        "gradient, so the fluid takes g (1 - rho_m / rho_f) and each grain g (1 - rho_m / rho_g), rho_m their mean "
        "density (case_grains.py); needs [[grains]] and body_force"))
    density_diffusion: float | None = Field(None, gt=0.0, le=1.0, description=(
        "delta of the density diffusion between fluid particles (Molteni & Colagrossi 2009, its hydrostatic part "
        "taken out as Fourtakas et al. 2019; engine eq. DD1): it damps the particle-scale density noise that a "
        "flow with little artificial viscosity accumulates, so alpha can be small; 0.1 is the usual value, -; "
        "one Newtonian fluid only"))
    eddy_viscosity_walls: bool = Field(True, description=(
        "nu_t also on the pairs with a wall particle (the fluid's own); false: between fluid particles only, the "
        "wall friction the laminar Morris term's (walls the lattice does not resolve)"))

    @field_validator("terms")
    @classmethod
    def _known_terms(cls, value: tuple[str, ...]) -> tuple[str, ...]:
        for term in value:
            if term not in PHYSICS_TERMS:
                raise ValueError(f"unknown term {term!r}; allowed: {', '.join(PHYSICS_TERMS)} (continuity, "
                                 "Tait EOS and pressure gradient are always on)")
        if len(set(value)) != len(value):
            raise ValueError("a term is listed twice")
        return value

    @model_validator(mode="after")
    def _parameters_with_terms(self):
        for term, key in (("body_force", "body_force"), ("artificial_viscosity", "artificial_viscosity"),
                          ("wall_penalty", "wall_penalty")):
            given = getattr(self, key) is not None
            if term in self.terms and not given:
                raise ValueError(f"physics.terms has {term!r} but physics.{key} is missing")
            if given and term not in self.terms:
                raise ValueError(f"physics.{key} is given but {term!r} is not in physics.terms; add it or remove the key")
        if self.body_force_on != "all" and self.body_force is None:
            raise ValueError(f"physics.body_force_on = {self.body_force_on!r} needs physics.body_force")
        if self.viscosity_correction and "morris_viscosity" not in self.terms:
            raise ValueError("physics.viscosity_correction = true needs 'morris_viscosity' in physics.terms")
        if self.eddy_viscosity is not None and ("morris_viscosity" not in self.terms or self.viscosity_correction):
            raise ValueError("physics.eddy_viscosity needs 'morris_viscosity' in physics.terms and "
                             "viscosity_correction = false")
        return self


class Block(Frozen):
    """A box filled with particles on the lattice lo + (i + 1/2) dx: fluid, or fixed boundary particles.

    Where blocks overlap, a lattice site holds one particle, of the first block
    that covers it. Every particle has mass rho0 dx^D.
    """

    name: Name = Field(description="identifier")
    kind: Literal["fluid", "boundary"] = Field(
        description="fluid: moves; boundary: fixed boundary particles (never move; velocity is the wall's)"
    )
    lo: Vector = Field(description="lower corner, m")
    hi: Vector = Field(description="upper corner, m; hi - lo must be a multiple of numerics.dx along every axis")
    velocity: Vector | None = Field(None, description="initial velocity (fluid) or wall velocity (boundary), m/s; "
                                                      "default zero")
    hydrostatic_surface: Finite | None = Field(
        None, description="height of the free surface along -body_force, m: particles below start at the "
                          "hydrostatic density (Tait EOS of rho0 |g| depth); default rho0 everywhere"
    )
    material: Name | None = Field(
        None, description="name of the block's [[materials]] table (required, for fluid and boundary blocks, "
                          "when the case has [[materials]]; a boundary particle's rho0 sets its mass and wall "
                          "pressure, its viscosity the wall's shear)"
    )
    cylinder: BlockCylinder | None = Field(None, description="keep only the sites in a cylindrical shell (3D)")


#: Keys each wall shape takes (besides shape and name), required first then optional.
WALL_KEYS = {
    "box": (("lo", "hi"), ("open_sides",)),
    "plane": (("center", "normal", "half_extents"), ("u",)),
    "stl": (("file",), ("scale", "translate")),
}


class Wall(Frozen):
    """A triangle-mesh wall (2D: segments) acting on the fluid by the penalty force of eq. 14.

    shape = "box": the faces of an axis-aligned box lo..hi (2D: its four
    edges), minus open_sides. shape = "plane": a rectangle (3D, half_extents
    [a, b] along u and normal x u) or a segment (2D, half_extents [a]) centred
    on center. shape = "stl": a mesh file (STL, OBJ, PLY: what trimesh reads;
    3D only), scaled then translated.
    """

    shape: Literal["box", "plane", "stl"] = Field(description="box, plane or stl")
    name: Name = Field(description="identifier (series wall_force_<name>)")
    lo: Vector | None = Field(None, description="box: lower corner, m")
    hi: Vector | None = Field(None, description="box: upper corner, m")
    open_sides: tuple[Literal["-x", "+x", "-y", "+y", "-z", "+z"], ...] = Field(
        (), description="box: sides left out, e.g. ['+y'] for a 2D tank open at the top"
    )
    center: Vector | None = Field(None, description="plane: centre, m")
    normal: Vector | None = Field(None, description="plane: normal (normalised on use), -")
    half_extents: tuple[Positive, ...] | None = Field(
        None, min_length=1, max_length=2, description="plane: half-lengths, m: [a] in 2D; [a, b] along u and "
                                                      "normal x u in 3D"
    )
    u: Vector | None = Field(None, description="plane: in-plane direction of half_extents[0] (3D only), -")
    file: Path | None = Field(None, description="stl: mesh file, relative to the case file")
    scale: Positive | None = Field(None, description="stl: factor applied to the file's coordinates (1e-3 for mm), -")
    translate: Vector | None = Field(None, description="stl: shift applied after scaling, m")

    @field_validator("file")
    @classmethod
    def _exists(cls, value: Path | None, info: ValidationInfo) -> Path | None:
        if value is None:
            return None
        return mesh_file(value, (info.context or {}).get("base_dir", "."))

    @model_validator(mode="after")
    def _keys_of_shape(self):
        required, optional = WALL_KEYS[self.shape]
        for key in required:
            if getattr(self, key) is None:
                raise ValueError(f"a {self.shape} wall needs {key} (it takes {', '.join(required + optional)})")
        for other, (req, opt) in WALL_KEYS.items():
            for key in req + opt:
                if other != self.shape and key not in required + optional and \
                        getattr(self, key) not in (None, ()):
                    raise ValueError(f"{key} is not a key of a {self.shape} wall; it takes "
                                     f"{', '.join(required + optional)}")
        return self


class Patch(Frozen):
    """A patch of a plane: a disc (radius) or a rectangle (half_extents [a, b], with u, in 3D).

    In 2D it is a segment normal to `normal` of half-length radius (or half_extents [a]).
    """

    name: Name = Field(description="identifier")
    center: Vector = Field(description="centre, m")
    normal: Vector = Field(description="normal: the direction of positive flow (normalised on use), -")
    radius: Positive | None = Field(None, description="disc radius (2D: segment half-length), m")
    half_extents: tuple[Positive, ...] | None = Field(
        None, min_length=1, max_length=2, description="rectangle half-lengths, m: [a, b] in 3D, [a] in 2D"
    )
    u: Vector | None = Field(None, description="rectangle direction of half_extents[0] (3D only), -")

    @model_validator(mode="after")
    def _one_shape(self):
        if (self.radius is None) == (self.half_extents is None):
            raise ValueError("give exactly one of radius (disc) and half_extents (rectangle)")
        if self.u is not None and self.half_extents is None:
            raise ValueError("u is only for rectangles (with half_extents)")
        return self


class Probe(Frozen):
    """A pressure probe: the kernel-interpolated fluid pressure at a point."""

    name: Name = Field(description="identifier (series pressure_probe_<name>)")
    point: Vector = Field(description="position, m")
