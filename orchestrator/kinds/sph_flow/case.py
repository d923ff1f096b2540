"""The SPH flow case (kind "sph_flow"): a weakly compressible fluid in a 2D or
3D box, filled from blocks of particles on a lattice of spacing dx, held by
fixed boundary particles and/or triangle-mesh penalty walls, driven by a body
force, inlets or moving boundary particles, observed by pressure probes and
flow-rate planes. It is what the sph executable can run (engines/sph, seed
000: Canini et al., eqs. 6-14). All quantities SI (m, kg, s, Pa, N); in 2D a
mass is per metre of depth (kg/m) and a force per metre (N/m).

Physics is explicit: ``physics.terms`` lists the optional terms the scene
uses (continuity, the Tait equation of state and the pressure gradient are
always on), and a term's parameters are given exactly when the term is on,
as the executable's deck requires. A scene of several fluids lists them as
[[materials]] and each block names its own (case_materials.py).
"""

from __future__ import annotations

import math

from pydantic import Field, model_validator

from orchestrator.case.common import CaseMeta, Frozen
from orchestrator.kinds.sph_flow.case_grains import Grain, GrainContact, check_grains
from orchestrator.kinds.sph_flow.case_impactors import Impactor, check_impactors
from orchestrator.kinds.sph_flow.case_limits import check_sph
from orchestrator.kinds.sph_flow.case_materials import (Material, check_materials, largest_c0_and_viscosity,
                                                       run_materials)
from orchestrator.kinds.sph_flow.case_open import Inlet, Outlet, check_outlet_pressures
from orchestrator.kinds.sph_flow.case_shear import LeesEdwards, check_lees_edwards
from orchestrator.kinds.sph_flow.case_parts import (  # noqa: F401  (the parts are part of this module's API)
    BOX_SIDES,
    LATTICE_TOLERANCE,
    PHYSICS_TERMS,
    ArtificialViscosity,
    Block,
    Domain,
    Fluid,
    Patch,
    Physics,
    Probe,
    Wall,
    WallPenalty,
    _norm,
)
from orchestrator.kinds.sph_flow.case_run import SphExpected, SphNumerics, SphOutput, SphSimulation  # noqa: F401


class SphFlowCase(Frozen):
    """A validated SPH flow case in SI units."""

    case: CaseMeta
    domain: Domain
    fluid: Fluid
    materials: tuple[Material, ...] = Field((), max_length=255, description="several fluids, each block naming "
                                            "one (case_materials.py); without them [fluid] is the one material")
    physics: Physics
    blocks: tuple[Block, ...] = Field(min_length=1)
    walls: tuple[Wall, ...] = ()
    inlets: tuple[Inlet, ...] = ()
    outlets: tuple[Outlet, ...] = ()
    impactors: tuple[Impactor, ...] = Field((), description="rigid impactors (3D): hard bodies made of spheres that "
                                            "push on the particles (case_impactors.py)")
    grains: tuple[Grain, ...] = Field((), max_length=1000, description="rigid grains (3D) made of the lattice's "
                                      "particles that the fluid drags (case_grains.py)")
    grain_contact: GrainContact | None = Field(None, description="contact between the grains, with wall planes and "
                                               "with solids (engine eqs. G6-G8): stiffness N/m, restitution, walls, "
                                               "solid_stiffness_factor (case_grains.py)")
    lees_edwards: LeesEdwards | None = Field(None, description="a sheared periodic cell (case_shear.py): steady "
                                             "shear_rate 1/s, or oscillatory amplitude and omega rad/s")
    numerics: SphNumerics
    simulation: SphSimulation
    output: SphOutput
    expected: tuple[SphExpected, ...] = Field((), description="the verification checks of the scene (orchestrator "
                                              "verify sph), with their tolerances")

    @property
    def dimension(self) -> int:
        """2 or 3."""
        return self.domain.dimension

    @model_validator(mode="after")
    def _consistent(self):
        self._check_lengths()
        check_materials(self)
        self._check_terms()
        self._check_blocks()
        self._check_walls()
        self._check_patches()
        check_outlet_pressures(self)
        self._check_times()
        check_lees_edwards(self)
        check_impactors(self.impactors, self.dimension)
        check_grains(self)

        check_sph(self, *largest_c0_and_viscosity(run_materials(self)))
        return self

    def _vectors(self):
        """(key, vector) of every vector whose length must equal the dimension."""
        yield "physics.body_force", self.physics.body_force
        for i, b in enumerate(self.blocks):
            yield from ((f"blocks[{i}].lo", b.lo), (f"blocks[{i}].hi", b.hi), (f"blocks[{i}].velocity", b.velocity))
        for i, w in enumerate(self.walls):
            for key in ("lo", "hi", "center", "normal", "translate"):
                yield f"walls[{i}].{key}", getattr(w, key, None)
        for group, items in (("inlets", self.inlets), ("outlets", self.outlets),
                             ("output.flow_planes", self.output.flow_planes)):
            for i, p in enumerate(items):
                yield f"{group}[{i}].center", p.center
                yield f"{group}[{i}].normal", p.normal
        for i, p in enumerate(self.output.probes):
            yield f"output.probes[{i}].point", p.point

    def _check_lengths(self) -> None:
        d = self.dimension
        for key, vector in self._vectors():
            if vector is not None and len(vector) != d:
                raise ValueError(f"{key} = {list(vector)} has {len(vector)} values; allowed: {d} "
                                 f"(domain.dimension = {d})")
        for key, vector in self._vectors():
            if key.endswith(".normal") and vector is not None and _norm(vector) == 0.0:
                raise ValueError(f"{key} is the zero vector; give a direction, e.g. {[1.0] + [0.0] * (d - 1)}")

    def _check_terms(self) -> None:
        terms = self.physics.terms
        if "morris_viscosity" in terms and self.fluid.viscosity is None and not self.materials:
            raise ValueError("physics.terms has 'morris_viscosity' but fluid.viscosity is missing")
        if self.fluid.viscosity is not None and "morris_viscosity" not in terms:
            raise ValueError("fluid.viscosity is given but 'morris_viscosity' is not in physics.terms; "
                             "add it or remove the key")
        if self.numerics.viscous_factor is not None and "morris_viscosity" not in terms:
            raise ValueError("numerics.viscous_factor limits the step by the viscosity, which needs "
                             "'morris_viscosity' in physics.terms")
        if self.physics.density_diffusion is not None and (
                len(self.materials) > 1 or any(getattr(m, "model", "newtonian") != "newtonian" for m in self.materials)):
            raise ValueError("physics.density_diffusion acts in a scene of one Newtonian fluid; this case has "
                             f"[[materials]] {[m.name for m in self.materials]}: remove the key")
        if "wall_penalty" in terms and not self.walls:
            raise ValueError("physics.terms has 'wall_penalty' but the case has no [[walls]]")
        if self.walls and "wall_penalty" not in terms:
            raise ValueError("the case has [[walls]] but 'wall_penalty' is not in physics.terms; add it (with "
                             "[physics.wall_penalty]) or remove the walls")

    def _check_blocks(self) -> None:
        dx = self.numerics.dx
        names = set()
        fluid = 0
        for i, b in enumerate(self.blocks):
            if b.name in names:
                raise ValueError(f"blocks[{i}].name = {b.name!r} is used twice; names must be unique")
            names.add(b.name)
            fluid += b.kind == "fluid"
            for axis, (lo, hi) in enumerate(zip(b.lo, b.hi)):
                cells = (hi - lo) / dx
                if not hi > lo:
                    raise ValueError(f"blocks[{i}].hi[{axis}] = {hi} is not above lo[{axis}] = {lo}; allowed: hi > lo")
                if round(cells) < 1:
                    raise ValueError(f"blocks[{i}] ({b.name}): hi[{axis}] - lo[{axis}] = {hi - lo:.9g} m is less than "
                                     f"one spacing numerics.dx = {dx:g} m; allowed: dx <= the block's size")
                if abs(cells - round(cells)) > LATTICE_TOLERANCE * max(1.0, cells):
                    raise ValueError(f"blocks[{i}] ({b.name}): hi[{axis}] - lo[{axis}] = {hi - lo:.9g} m is not a "
                                     f"multiple of numerics.dx = {dx} m ({cells:.6g} spacings); allowed: a whole "
                                     "number of spacings")
            tol = LATTICE_TOLERANCE * dx
            if not (self.domain.contains(b.lo, tol) and self.domain.contains(b.hi, tol)):
                raise ValueError(f"blocks[{i}] ({b.name}) reaches outside the domain box "
                                 f"[{list(self.domain.lo)}, {list(self.domain.hi)}]")
            speed = _norm(b.velocity) if b.velocity is not None else 0.0
            if speed > self.fluid.max_speed:
                raise ValueError(f"blocks[{i}].velocity has speed {speed:g} m/s, above fluid.max_speed = "
                                 f"{self.fluid.max_speed} m/s")
            if b.cylinder is not None and b.cylinder.wall is not None and b.kind != "boundary":
                raise ValueError(f"blocks[{i}].cylinder.wall is given for a {b.kind} block ({b.name}); only a "
                                 "boundary block has a wall face (remove the key)")
            if b.hydrostatic_surface is not None and self.physics.body_force is None:
                raise ValueError(f"blocks[{i}].hydrostatic_surface needs a body force (physics.body_force)")
            if b.hydrostatic_surface is not None and _norm(self.physics.body_force) == 0.0:
                raise ValueError(f"blocks[{i}].hydrostatic_surface needs a non-zero physics.body_force")
        if not fluid:
            raise ValueError("blocks has no block of kind 'fluid'; the scene needs fluid particles")
        h = self.numerics.h
        for axis in self.domain.periodic:
            length = self.domain.hi[axis] - self.domain.lo[axis]
            if length < 2.0 * h:
                raise ValueError(f"domain: the periodic length along axis {axis} ({length} m) is shorter than the "
                                 f"kernel support 2h = {2 * h:g} m")

    def _check_walls(self) -> None:
        names = set()
        d = self.dimension
        for i, w in enumerate(self.walls):
            if w.name in names:
                raise ValueError(f"walls[{i}].name = {w.name!r} is used twice; names must be unique")
            names.add(w.name)
            if w.shape == "box":
                for axis, (lo, hi) in enumerate(zip(w.lo, w.hi)):
                    if not hi > lo:
                        raise ValueError(f"walls[{i}].hi[{axis}] = {hi} is not above lo[{axis}] = {lo}")
                bad = [s for s in w.open_sides if "xyz".index(s[1]) >= d]
                if bad:
                    raise ValueError(f"walls[{i}].open_sides has {bad[0]!r}; allowed in {d}D: "
                                     f"{', '.join(BOX_SIDES[:2 * d])}")
            elif w.shape == "plane":
                if len(w.half_extents) != d - 1:
                    raise ValueError(f"walls[{i}].half_extents has {len(w.half_extents)} values; allowed: {d - 1} "
                                     f"in {d}D")
                if d == 3:
                    if w.u is None:
                        raise ValueError(f"walls[{i}].u is missing: a 3D plane wall needs the direction of "
                                         "half_extents[0]")
                    _check_not_parallel(f"walls[{i}]", w.u, w.normal)
                elif w.u is not None:
                    raise ValueError(f"walls[{i}].u is not used in 2D (the segment is normal to 'normal'); remove it")
            elif d != 3:
                raise ValueError(f"walls[{i}]: a mesh file (shape = 'stl') is 3D only; in 2D use 'box' or 'plane'")

    def _check_patches(self) -> None:
        d, dx, h = self.dimension, self.numerics.dx, self.numerics.h
        names: set[str] = set()
        for group, items in (("inlets", self.inlets), ("outlets", self.outlets)):
            for i, p in enumerate(items):
                if p.name in names:
                    raise ValueError(f"{group}[{i}].name = {p.name!r} is used twice among inlets and outlets")
                names.add(p.name)
                if p.layers * dx < 2.0 * h * (1 - 1e-12):
                    raise ValueError(f"{group}[{i}].layers = {p.layers}: layers x dx = {p.layers * dx:g} m must cover "
                                     f"the kernel support 2h = {2 * h:g} m; allowed: layers >= {math.ceil(2 * h / dx)}")
        for i, p in enumerate(self.inlets):
            if p.velocity > self.fluid.max_speed:
                raise ValueError(f"inlets[{i}].velocity = {p.velocity} m/s is above fluid.max_speed = "
                                 f"{self.fluid.max_speed} m/s")
            if p.peak_speed > self.fluid.max_speed:
                raise ValueError(f"inlets[{i}]: the {p.profile} profile peaks at {p.peak_speed:g} m/s, above "
                                 f"fluid.max_speed = {self.fluid.max_speed} m/s")
        for group, items in (("inlets", self.inlets), ("outlets", self.outlets),
                             ("output.flow_planes", self.output.flow_planes)):
            for i, p in enumerate(items):
                if p.half_extents is not None and len(p.half_extents) != d - 1:
                    raise ValueError(f"{group}[{i}].half_extents has {len(p.half_extents)} values; allowed: "
                                     f"{d - 1} in {d}D")
                if d == 3 and p.half_extents is not None:
                    if p.u is None:
                        raise ValueError(f"{group}[{i}].u is missing: a 3D rectangle needs the direction of "
                                         "half_extents[0]")
                    _check_not_parallel(f"{group}[{i}]", p.u, p.normal)
                if d == 2 and p.u is not None:
                    raise ValueError(f"{group}[{i}].u is not used in 2D (the segment is normal to 'normal'); remove it")
        names = set()
        for i, p in enumerate(self.output.flow_planes):
            if p.name in names:
                raise ValueError(f"output.flow_planes[{i}].name = {p.name!r} is used twice")
            names.add(p.name)
        names = set()
        for i, p in enumerate(self.output.probes):
            if p.name in names:
                raise ValueError(f"output.probes[{i}].name = {p.name!r} is used twice")
            names.add(p.name)

    def _check_times(self) -> None:
        t_end = self.simulation.duration
        for key in ("frame_interval", "series_interval"):
            value = getattr(self.output, key)
            if value is not None and value > t_end:
                raise ValueError(f"output.{key} = {value} s is longer than the run (simulation.duration = {t_end} s)")
        if self.numerics.dt is not None and self.numerics.dt > t_end:
            raise ValueError(f"numerics.dt = {self.numerics.dt} s is longer than the run "
                             f"(simulation.duration = {t_end} s)")


def _check_not_parallel(where: str, u, normal) -> None:
    dot = sum(a * b for a, b in zip(u, normal))
    nu, nn = _norm(u), _norm(normal)
    if nu == 0.0 or abs(dot) >= nu * nn * (1 - 1e-9):
        raise ValueError(f"{where}.u = {list(u)} is zero or parallel to normal = {list(normal)}; give an in-plane "
                         "direction")
