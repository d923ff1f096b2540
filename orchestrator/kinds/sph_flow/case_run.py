"""The run settings of an SPH flow case (kind "sph_flow"): resolution and time stepping, duration, output, and the
expected checks a verification scene compares with. SI units (m, s). case.py assembles them into SphFlowCase."""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from orchestrator.case.common import Frozen, Positive
from orchestrator.kinds.sph_flow.case_parts import Patch, Probe


class SphNumerics(Frozen):
    """Resolution and time stepping (eq. 13)."""

    dx: Positive = Field(description="particle spacing, m")
    h_over_dx: float = Field(1.3, ge=0.5, le=5.0, description="smoothing length over spacing h/dx, - (kernel support "
                             "2h; below 0.5 a particle has no neighbours, above 5 thousands in 3D)")
    dt: Positive | None = Field(None, description="fixed time step, s; leave out for the adaptive step")
    cfl: Positive | None = Field(None, description="adaptive step: dt <= cfl h / (c0 + |v|max), - (default 0.25)")
    viscous_factor: Positive | None = Field(
        None, description="adaptive step: dt <= factor h^2 / nu, - (default 0.125; with morris_viscosity)"
    )
    force_factor: Positive | None = Field(None, description="adaptive step: dt <= factor sqrt(h / |a|max), - "
                                                            "(default 0.25)")
    max_density_deviation: Positive = Field(
        0.1, description="the run stops as unstable when a fluid particle has |rho/rho0 - 1| above this, -"
    )
    max_steps: int | None = Field(None, ge=1, le=1_000_000_000, description="optional cap on the number of steps, -")
    threads: int = Field(1, ge=1, le=256, description="OpenMP threads of the engine")
    thread_wait: Literal["passive", "spin"] = Field(
        "passive", description="how idle OpenMP threads wait (threads > 1): passive sleeps at once, safe when "
        "cores are shared (parallel runs, other jobs); spin polls about 10^4 times first (GOMP_SPINCOUNT), "
        "faster on small scenes when every thread has a core of its own (2D dam break, 3918 particles: "
        "2 threads 1.8 x one instead of 1.3 x) and many times slower when threads outnumber free cores")

    @model_validator(mode="after")
    def _fixed_or_adaptive(self):
        factors = [k for k in ("cfl", "viscous_factor", "force_factor") if getattr(self, k) is not None]
        if self.dt is not None and factors:
            raise ValueError(f"numerics.dt (fixed step) and numerics.{factors[0]} (adaptive step) are both given; "
                             "give one of them")
        return self

    @property
    def h(self) -> float:
        """Smoothing length h = h_over_dx dx, m."""
        return self.h_over_dx * self.dx

    @property
    def adaptive(self) -> dict[str, float]:
        """Factors of the adaptive step (the engine's defaults where not given), -."""
        return {"cfl": self.cfl or 0.25, "viscous": self.viscous_factor or 0.125, "force": self.force_factor or 0.25}


class SphSimulation(Frozen):
    """How long to run."""

    duration: Positive = Field(description="end time t_end (the run starts at t = 0), s")


class SphOutput(Frozen):
    """What is recorded: frames, series, probes and flow planes."""

    frame_interval: Positive = Field(description="time between particle frames, s")
    series_interval: Positive | None = Field(None, description="time between series records, s "
                                                               "(default frame_interval)")
    probes: tuple[Probe, ...] = ()
    flow_planes: tuple[Patch, ...] = ()


#: The comparisons an SPH scene can ask for in its [[expected]] rows, and the quantities each measures
#: (kinds/sph_flow/checks.py computes them; the scene's rows give the tolerances).
CHECK_QUANTITIES = {
    "poiseuille_series": ("u_profile",),
    "hagen_poiseuille": ("u_profile", "pressure_gradient", "mass_balance", "density_drift"),
    "annulus_laminar": ("u_profile", "pressure_gradient", "mass_balance", "density_drift"),
    "couette_series": ("u_profile",),
    "two_layer_poiseuille": ("u_profile",),
    "two_layer_couette": ("u_profile",),
    "hydrostatic": ("pressure_profile", "particle_pressure", "spurious_speed", "simulated_time"),
    "surge_front": ("surge_front_Z",),
    "penalty_column": ("eq14_wall_force", "min_distance_to_wall", "floor_force"),
    "oldroyd_b_startup": ("centreline_velocity",),
    "settling": ("terminal_speed",),
    "grain_in_shear": ("rotation_rate", "centre_velocity"),
    "grain_collision": ("restitution", "momentum_change"),
    "grain_wall_bounce": ("restitution", "tangential_change"),
    "solid_under_water": ("layer_stress", "layer_rows", "water_pressure", "spurious_speed"),
    "slot_orifice": ("discharge_coefficient",),
    "penalty_incline": ("eq14_wall_force", "min_distance_to_wall", "slide_distance", "distance_to_plane",
                        "plane_force"),
}


class SphExpected(Frozen):
    """One [[expected]] row of an SPH scene: a quantity of one comparison (CHECK_QUANTITIES) and its tolerance, the
    largest rel_error that passes (its scale is in the row's note: e.g. profiles over the steady peak speed, -).
    A quantity without a tolerance passes on its own condition (min_distance_to_wall: > 0)."""

    check: Literal[tuple(CHECK_QUANTITIES)] = Field(description="the comparison, e.g. 'poiseuille_series'")
    quantity: str = Field(description="a quantity the comparison measures, e.g. 'u_profile'")
    tolerance: float | None = Field(None, gt=0, lt=1, description="largest rel_error that passes, -")

    @model_validator(mode="after")
    def _known_quantity(self):
        allowed = CHECK_QUANTITIES[self.check]
        if self.quantity not in allowed:
            raise ValueError(f"quantity = {self.quantity!r} is not measured by check {self.check!r}; allowed: "
                             f"{', '.join(allowed)}")
        if self.tolerance is None and self.quantity != "min_distance_to_wall":
            raise ValueError(f"quantity {self.quantity!r} needs a tolerance (the largest rel_error that passes)")
        return self
