"""The impact case: a few spheres with initial positions, velocities and
spins, optionally one flat wall (a rigid plane, or a plate of a given
material), with or without gravity. It is the scene of the DEM verification
suite (Chung & Ooi 2011 tests 1-4, the sphere drop of Uhlmann et al. 2015)
and of any single- or few-contact test of your own. All quantities SI (m,
kg, s, N, Pa).

The [[expected]] table lists checks: a measured quantity (see
orchestrator.kinds.impact.theory.QUANTITIES), the expected value or the name of a
closed form that computes it from this case (orchestrator.kinds.impact.theory),
and a relative tolerance.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import Field, field_validator, model_validator

from orchestrator.case.common import Frozen, MaterialCase, Name, Numerics, Positive
from orchestrator.case.limits import check_interval, check_steps
from orchestrator.kinds.impact.physics import RIGID, critical_timestep
from orchestrator.kinds.impact.theory import CLOSED_FORMS, QUANTITIES

#: Reserved material name of an immovable, infinitely stiff wall (E = inf).
#: Largest number of spheres an impact case may hold (engines; the reference DEM takes fewer).
MAX_IMPACT_SPHERES = 100_000

Finite = Annotated[float, Field(allow_inf_nan=False)]
Vector3 = tuple[Finite, Finite, Finite]


class Sphere(Frozen):
    """One sphere: material, radius and its state at t = 0."""

    material: Name
    radius: Annotated[float, Field(gt=0, allow_inf_nan=False)] = Field(description="m")
    position: Vector3 = Field(description="centre at t = 0, m")
    velocity: Vector3 = Field((0.0, 0.0, 0.0), description="m/s")
    angular_velocity: Vector3 = Field((0.0, 0.0, 0.0), description="rad/s")


class Plane(Frozen):
    """An infinite flat wall through `point` with `normal` pointing to the spheres' side.

    material = "rigid" (the default) is immovable and infinitely stiff
    (E = inf: a sphere on it has E_eq = E / (1 - nu^2)); any other name is a
    plate of that material (e.g. the paper's steel plate), still immovable.
    """

    point: Vector3 = Field((0.0, 0.0, 0.0), description="m")
    normal: Vector3 = Field((0.0, 0.0, 1.0), description="unit vector (normalised on load), -")
    material: Name = RIGID

    @field_validator("normal")
    @classmethod
    def _not_zero(cls, value):
        if math.hypot(*value) == 0.0:
            raise ValueError("the normal is the zero vector; give the direction the spheres' side faces, e.g. [0, 0, 1]")
        return value

    @property
    def unit_normal(self) -> tuple[float, float, float]:
        """The normal scaled to length 1, -."""
        size = math.hypot(*self.normal)
        return tuple(c / size for c in self.normal)


class Simulation(Frozen):
    """How long to run and whether gravity acts."""

    duration: Positive = Field(description="simulated time, s")
    gravity: bool = Field(False, description="true: g = 9.81 m/s^2 along -z")


class ImpactModel(Frozen):
    """How the case's restitution e_n becomes the damping constant alpha of
    c_n = alpha sqrt(m_eq k_n) delta^(1/4) (paper eq. 9, c_t = c_n).

    - "exact": the alpha with which one impact rebounds at exactly e_n while the
      normal force may not pull (closed_form.alpha_from_restitution). Every
      engine is given this alpha in its own parameters: same physics everywhere.
    - "eq10": alpha from the paper's eq. 10 (Antypov & Elliott). Exact only if
      the dash-pot may pull at the end of a contact; with the no-tension rule
      of Yade and the reference it rebounds higher (0.7007 for e_n = 0.68).
    - "engine": each engine's own mapping of e_n (Yade 2023: Thornton et al.
      2013's fit of its betan/betas; the reference: eq. 10, the paper's).
      Closed forms that depend on alpha are not defined for it.

    coulomb_limit: which tangential force the Coulomb law mu F_n bounds; the
    paper does not say. "total" (elastic spring plus dash-pot; the reference
    DEM's default) or "elastic" (the spring only, the dash-pot added on top
    while the contact sticks: Yade, the paper's engine, and LIGGGHTS 3.8's
    tangential history model). Yade and LIGGGHTS run "elastic" whatever the
    case says and note the deviation in run.h5.
    """

    damping: Literal["exact", "eq10", "engine"] = "exact"
    coulomb_limit: Literal["total", "elastic"] = "total"


class ImpactNumerics(Numerics):
    """Time stepping of an impact scene.

    The critical step is the smaller of the Rayleigh step of the smallest
    sphere and the stability limit 2/omega of the stiffest Hertz contact at the
    fastest closing speed the scene can reach (about half its contact
    duration); see orchestrator.kinds.impact.scene.critical_timestep.
    """

    timestep_factor: float = Field(
        0.05, gt=0, le=1, description="time step as a fraction of the critical step, - (0.05: >= 40 steps per contact)"
    )
    timestep: Positive | None = Field(
        None, description="explicit time step, s; overrides timestep_factor and is not checked (stability tests)"
    )


class ImpactOutput(Frozen):
    """What is recorded."""

    record_interval: Positive | None = Field(
        None, description="interval of the recorded series, s (default: duration / 1000)"
    )


class Check(Frozen):
    """One expected result: quantity, the expected value or a named closed form, relative tolerance."""

    quantity: str = Field(description="a measured quantity, e.g. max_normal_force")
    value: Finite | None = Field(None, description="expected value in the quantity's SI unit")
    closed_form: str | None = Field(None, description="name of a closed form computing it, e.g. hertz_max_force")
    tolerance: float = Field(gt=0, lt=1, description="relative tolerance |value - expected| / |expected|, -")

    @model_validator(mode="after")
    def _one_source(self):

        if self.quantity not in QUANTITIES:
            raise ValueError(f"quantity = {self.quantity!r} is not measured; allowed: {', '.join(QUANTITIES)}")
        if (self.value is None) == (self.closed_form is None):
            raise ValueError("give exactly one of value (a number) and closed_form (a name)")
        if self.closed_form is not None:
            if self.closed_form not in CLOSED_FORMS:
                raise ValueError(f"closed_form = {self.closed_form!r} is not known; allowed: {', '.join(CLOSED_FORMS)}")
            predicts = CLOSED_FORMS[self.closed_form].quantity
            if predicts != self.quantity:
                raise ValueError(f"closed_form {self.closed_form!r} gives {predicts}, not {self.quantity}")
        return self


class ImpactCase(MaterialCase):
    """A validated impact case in SI units."""

    spheres: tuple[Sphere, ...] = Field(min_length=1, max_length=MAX_IMPACT_SPHERES)
    plane: Plane | None = None
    simulation: Simulation
    model: ImpactModel = ImpactModel()
    numerics: ImpactNumerics = ImpactNumerics()
    output: ImpactOutput = ImpactOutput()
    expected: tuple[Check, ...] = ()

    @model_validator(mode="after")
    def _consistent(self):
        if RIGID in self.materials:
            raise ValueError(f"materials.{RIGID} is reserved for the immovable, infinitely stiff wall; "
                             "give your material another name")
        for name, material in self.materials.items():
            if not all(math.isfinite(v) for v in (material.density, material.young_modulus)):
                raise ValueError(f"materials.{name}: density and young_modulus must be finite numbers; "
                                 f"for an infinitely stiff wall use plane.material = {RIGID!r}")
        names = sorted(self.materials)
        for i, sphere in enumerate(self.spheres):
            if sphere.material not in self.materials:
                raise ValueError(f"spheres[{i}].material = {sphere.material!r} is not defined; allowed: {', '.join(names)}")
        if self.plane is not None and self.plane.material not in self.materials and self.plane.material != RIGID:
            raise ValueError(f"plane.material = {self.plane.material!r} is not defined; allowed: "
                             f"{', '.join(names + [RIGID])}")
        for i, contact in enumerate(self.contacts):
            for name in contact.pair:
                if name not in self.materials and name != RIGID:
                    raise ValueError(f"contacts[{i}].pair names {name!r}, which is not defined; allowed: "
                                     f"{', '.join(names + [RIGID])}")
        for a, b in self.touching_pairs():
            self.contact(a, b)
        self._check_start_positions()
        if self.output.record_interval is not None and self.output.record_interval > self.simulation.duration:
            raise ValueError(f"output.record_interval = {self.output.record_interval} s is longer than the run "
                             f"(simulation.duration = {self.simulation.duration} s); allowed: record_interval < duration")
        if self.model.damping != "engine":
            for i, contact in enumerate(self.contacts):
                if contact.tangential_restitution not in (None, contact.restitution):
                    raise ValueError(
                        f"contacts[{i}].tangential_restitution = {contact.tangential_restitution}: the paper's law "
                        "damps the tangential direction like the normal one (c_t = c_n); a separate e_t exists only "
                        "with model.damping = 'engine'; remove the key or set it equal to restitution")
        if self.model.coulomb_limit != "total":

            for check in self.expected:
                if check.closed_form and CLOSED_FORMS[check.closed_form].needs_total_limit:
                    raise ValueError(f"closed_form {check.closed_form!r} integrates the law with the Coulomb limit on "
                                     "the total tangential force; it needs model.coulomb_limit = 'total'")
        if self.model.damping == "engine":

            for check in self.expected:
                if check.closed_form and CLOSED_FORMS[check.closed_form].needs_alpha:
                    raise ValueError(f"closed_form {check.closed_form!r} depends on the damping constant, which "
                                     "model.damping = 'engine' leaves to each engine; use 'exact' or 'eq10', or give "
                                     "a value")

        check_impact(self)
        return self

    def _check_start_positions(self) -> None:
        tolerance = 1e-9
        if self.plane is not None:
            n = self.plane.unit_normal
            for i, sphere in enumerate(self.spheres):
                height = sum((p - q) * c for p, q, c in zip(sphere.position, self.plane.point, n))
                if height < sphere.radius * (1 - tolerance):
                    raise ValueError(
                        f"spheres[{i}] starts {'behind' if height < 0 else 'overlapping'} the plane (centre "
                        f"{height:.6g} m from it, radius {sphere.radius} m); allowed: centre at least one radius "
                        "above the plane on its normal's side")
        if len(self.spheres) <= 200:  # pairwise check; larger scenes are checked by the engines
            for i, a in enumerate(self.spheres):
                for j in range(i + 1, len(self.spheres)):
                    b = self.spheres[j]
                    gap = math.dist(a.position, b.position) - a.radius - b.radius
                    if gap < -tolerance * min(a.radius, b.radius):
                        raise ValueError(f"spheres[{i}] and spheres[{j}] overlap by {-gap:.6g} m at t = 0; "
                                         "allowed: centres at least the sum of the radii apart")

    def touching_pairs(self) -> list[tuple[str, str]]:
        """Material pairs that can touch: sphere-sphere (two spheres of them exist) and sphere-plane."""
        counts: dict[str, int] = {}
        for sphere in self.spheres:
            counts[sphere.material] = counts.get(sphere.material, 0) + 1
        pairs = set()
        kinds = sorted(counts)
        for i, a in enumerate(kinds):
            if counts[a] > 1:
                pairs.add((a, a))
            for b in kinds[i + 1:]:
                pairs.add((a, b))
            if self.plane is not None:
                pairs.add(tuple(sorted((a, self.plane.material))))
        return sorted(pairs)


def check_impact(case) -> None:
    """The explicit time step against the run, step counts and the number of records of an impact case."""

    duration = case.simulation.duration
    explicit = case.numerics.timestep
    if explicit is not None and explicit > duration:
        raise ValueError(f"numerics.timestep = {explicit:g} s is longer than the run (simulation.duration = "
                         f"{duration:g} s): the run would be a single step; allowed: timestep < duration")
    if explicit is not None:
        step, step_key = explicit, "numerics.timestep"
    else:
        step = case.numerics.timestep_factor * critical_timestep(case)
        step_key = "the time step (numerics.timestep_factor x the critical step)"
        if not step > 0:
            raise ValueError(f"numerics.timestep_factor = {case.numerics.timestep_factor:g} gives a time step of "
                             f"{step:g} s; allowed: a factor that gives a positive step")
    step = min(step, duration)
    check_steps("simulation.duration", duration, step_key, step)
    if case.output.record_interval is not None:  # below the step the DEM engines record every step
        check_interval("output.record_interval", case.output.record_interval, "simulation.duration", duration)
