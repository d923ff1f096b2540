"""The drag-finishing case (Uhlmann, Eulitz, Dethlefs 2015): a cylindrical
bowl filled with spherical media through which a rod is dragged on a
circular path. All quantities SI."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Literal

from pydantic import Field, ValidationInfo, field_validator, model_validator

from orchestrator.case.common import (
    Frozen,
    Label,
    MaterialCase,
    Name,
    NonNegative,
    Numerics,
    Positive,
    mesh_file,
    rayleigh_timestep,
)
from orchestrator.case.limits import MAX_CHECKPOINTS, check_interval, check_memory, check_steps

#: Random loose packing of monodisperse spheres poured into a container; used
#: only to tell a user early that a bed cannot fit in the bowl.
DENSEST_RANDOM_PACKING = 0.64
#: Memory one DEM ball takes in an engine (Yade's body, state and shape objects with about six interactions,
#: LIGGGHTS's per-atom arrays and contact history), rounded up, bytes.
BYTES_PER_DEM_PARTICLE = 4096


class Media(Frozen):
    """The bed of spherical media (paper: n_b, R_b, delta_b, h_f)."""

    material: Name
    count: int = Field(ge=1, le=5_000_000, description="number of balls n_b")
    radius: Positive = Field(description="mean ball radius R_b, m")
    radius_spread: NonNegative = Field(0.0, description="delta_b, m: std (normal) or half-width (uniform)")
    distribution: Literal["normal", "uniform"] = Field(
        "normal", description="radius distribution; a normal one is truncated at +-2 spread"
    )
    fill_height: Positive = Field(description="height of filling h_f above the bowl floor, m")

    @model_validator(mode="after")
    def _spread_below_radius(self):
        widest = 2.0 * self.radius_spread if self.distribution == "normal" else self.radius_spread
        if widest >= self.radius:
            raise ValueError(
                f"media.radius_spread = {self.radius_spread} m gives radii <= 0 "
                f"(media.radius = {self.radius} m); allowed: "
                + ("2 * radius_spread < radius" if self.distribution == "normal" else "radius_spread < radius")
            )
        return self

    @property
    def radius_max(self) -> float:
        """Largest radius the distribution can draw, m."""
        return self.radius + (2.0 if self.distribution == "normal" else 1.0) * self.radius_spread

    @property
    def solid_volume(self) -> float:
        """Expected total volume of the balls, m^3."""
        mean_r3 = self.radius**3 + 3 * self.radius * self.radius_spread**2 * (
            1.0 if self.distribution == "normal" else 1.0 / 3.0
        )
        return self.count * 4.0 / 3.0 * math.pi * mean_r3


class Bowl(Frozen):
    """Cylindrical bowl with a flat floor (geometry reconstructed from the paper's Fig. 3)."""

    material: Name
    inner_radius: Positive = Field(description="m")
    height: Positive = Field(description="wall height above the floor, m")
    segments: int = Field(64, ge=8, le=1024, description="facets around the circumference")


class Workpiece(Frozen):
    """The rod dragged through the media on a circular path about the bowl axis."""

    material: Name
    radius: Positive = Field(description="rod radius, m")
    length: Positive = Field(description="rod length, m")
    path_radius: Positive = Field(description="radius of the rod's circular path about the bowl axis, m")
    speed: Positive = Field(description="workpiece velocity v_w along the path, m/s")
    submersion_depth: Positive = Field(description="depth d_s of the rod tip below the bed surface, m")
    insertion_speed: Positive = Field(0.1, description="vertical speed while the rod is pushed in, m/s")
    segments: int = Field(24, ge=6, le=512, description="facets around the rod")
    mesh: Path | None = Field(None, description="optional STL replacing the cylinder (tip at z=0, axis +z), m")

    @field_validator("mesh")
    @classmethod
    def _mesh_exists(cls, value: Path | None, info: ValidationInfo) -> Path | None:
        if value is None:
            return None
        return mesh_file(value, (info.context or {}).get("base_dir", "."))


class Settling(Frozen):
    """Gravity deposition of the bed before the rod goes in.

    The criterion: the bed counts as at rest when the unbalanced-force ratio
    (mean resultant force on a ball / mean contact force) is below
    ``unbalanced_force`` and no ball moves faster than ``max_speed``.
    Numerical (Cundall) damping speeds settling up; it is switched off for
    the rest of the run, so the process phase runs the paper's contact law only.
    """

    damping: float = Field(0.4, ge=0, lt=1, description="numerical damping during settling only, -")
    max_time: Positive = Field(2.0, description="simulated time allowed for settling, s")
    unbalanced_force: float = Field(0.02, gt=0, lt=1, description="rest criterion, -")
    max_speed: Positive = Field(0.01, description="rest criterion on the fastest ball, m/s")
    relax_time: NonNegative = Field(0.05, description="undamped rest after the rod is inserted, s")
    stiffness_scale: float | None = Field(
        None, gt=0, le=1,
        description="Young's modulus factor while the bed settles and the rod goes in (None: "
                    "numerics.stiffness_scale). A softer value makes settling cheap; the contacts are then "
                    "stiffened to numerics.stiffness_scale over stiffen_time, with damping, before the process, -",
    )
    timestep_factor: float | None = Field(
        None, gt=0, le=1,
        description="time step while settling, as a fraction of the Rayleigh step at settling.stiffness_scale "
                    "(None: numerics.timestep_factor). Runs that share the settling values share the settled bed, -",
    )
    stiffen_time: Positive = Field(0.02, description="damped ramp from the settling stiffness to the process one, s")


class Process(Frozen):
    """The dragging phase."""

    duration: Positive = Field(description="process time t_p after insertion, s")


class Output(Frozen):
    """What is recorded, and when (times are process time, s after the rod starts moving)."""

    record_interval: Positive = Field(0.005, description="interval of the force series, s")
    network_times: tuple[NonNegative, ...] = Field((), description="times of interaction-network snapshots, s")
    checkpoint_interval: Positive | None = Field(
        None, description="process time between checkpoints from which 'orchestrator run --resume' continues a "
        "stopped run, s (LIGGGHTS restart files; None: no checkpoints)")
    impact_window: tuple[NonNegative, NonNegative] | None = Field(
        None, description="[start, end] process time, s (the end cut to the process), in which every ball's first touch of the rod is recorded "
        "with its normal impact speed (checked every step; costs engine time; the rod must be a regular prism, as the "
        "generated one; [] or absent: off)")

    @field_validator("impact_window", mode="before")
    @classmethod
    def _empty_window_is_off(cls, value):
        """[] turns the window off (TOML, and so --set, has no null)."""
        return None if isinstance(value, (list, tuple)) and len(value) == 0 else value


class Analysis(Frozen):
    """How a run is reduced to the numbers compared with the paper."""

    transient_time: NonNegative = Field(
        0.5, description="start-up transient discarded before mean/std of the forces, s of process time"
    )


class ForceBand(Frozen):
    """A published mean and standard deviation of a force, N."""

    label: Label
    fn_mean: float
    fn_std: NonNegative


class DragFinishingCase(MaterialCase):
    """A validated drag-finishing case in SI units."""

    media: Media
    bowl: Bowl
    workpiece: Workpiece
    settling: Settling = Settling()
    process: Process
    numerics: Numerics = Numerics()
    output: Output = Output()
    analysis: Analysis = Analysis()
    reference: tuple[ForceBand, ...] = ()

    @model_validator(mode="after")
    def _consistent(self):
        self._check_names()
        self._check_geometry()
        self._check_times()
        check_drag_finishing(self)
        return self

    def _check_names(self) -> None:
        """Every material named is defined, and every pair that can touch has a contact row."""
        names = sorted(self.materials)
        for key, material in (
            ("media.material", self.media.material),
            ("bowl.material", self.bowl.material),
            ("workpiece.material", self.workpiece.material),
        ):
            if material not in self.materials:
                raise ValueError(f"{key} = {material!r} is not defined; allowed: {', '.join(names)}")
        for i, contact in enumerate(self.contacts):
            for name in contact.pair:
                if name not in self.materials:
                    raise ValueError(
                        f"contacts[{i}].pair names {name!r}, which is not defined; allowed: {', '.join(names)}"
                    )
        for a, b in self.touching_pairs():
            self.contact(a, b)

    def _check_geometry(self) -> None:
        """The bed fits the bowl, the rod reaches into the bed but not the floor, and stays off the wall."""
        if self.media.fill_height >= self.bowl.height:
            raise ValueError(
                f"media.fill_height = {self.media.fill_height} m is above the bowl "
                f"(bowl.height = {self.bowl.height} m); allowed: fill_height < bowl.height"
            )
        floor_area = math.pi * self.bowl.inner_radius**2
        min_height = self.media.solid_volume / (DENSEST_RANDOM_PACKING * floor_area)
        if min_height >= self.bowl.height:
            raise ValueError(
                f"media.count = {self.media.count} balls fill at least {min_height:.4g} m even at the densest "
                f"random packing, above the bowl (bowl.height = {self.bowl.height} m); "
                "allowed: fewer balls or a bigger bowl"
            )
        if self.workpiece.submersion_depth >= self.media.fill_height:
            raise ValueError(
                f"workpiece.submersion_depth = {self.workpiece.submersion_depth} m would put the rod tip "
                f"below the floor (media.fill_height = {self.media.fill_height} m); "
                "allowed: submersion_depth < fill_height"
            )
        if self.workpiece.submersion_depth >= self.workpiece.length:
            raise ValueError(
                f"workpiece.submersion_depth = {self.workpiece.submersion_depth} m is longer than the rod "
                f"(workpiece.length = {self.workpiece.length} m); allowed: submersion_depth < length"
            )
        reach = self.workpiece.path_radius + self.workpiece.radius
        if reach >= self.bowl.inner_radius - 2 * self.media.radius_max:
            raise ValueError(
                f"workpiece.path_radius = {self.workpiece.path_radius} m puts the rod (radius "
                f"{self.workpiece.radius} m) within one ball diameter of the wall (bowl.inner_radius = "
                f"{self.bowl.inner_radius} m); allowed: path_radius + radius < inner_radius - 2 * largest ball radius"
            )

    def _check_times(self) -> None:
        """Snapshots, the impact window, the record interval and the transient fall inside the process; settling
        is not stiffer than the process."""
        for t in self.output.network_times:
            if t > self.process.duration:
                raise ValueError(
                    f"output.network_times contains {t} s, after the end of the process "
                    f"(process.duration = {self.process.duration} s); allowed: 0 <= t <= duration"
                )
        window = self.output.impact_window
        if window is not None and not (window[0] < window[1] and window[0] < self.process.duration):
            raise ValueError(
                f"output.impact_window = {list(window)} s does not start inside the process (process.duration = "
                f"{self.process.duration} s); allowed: [start, end] with 0 <= start < end and start < duration (an "
                "end after the process is cut to it), or [] for none"
            )
        if self.output.record_interval > self.process.duration:
            raise ValueError(
                f"output.record_interval = {self.output.record_interval} s is longer than the process "
                f"(process.duration = {self.process.duration} s); allowed: record_interval < duration"
            )
        soft = self.settling.stiffness_scale
        if soft is not None and soft > self.numerics.stiffness_scale:
            raise ValueError(
                f"settling.stiffness_scale = {soft} is stiffer than numerics.stiffness_scale = "
                f"{self.numerics.stiffness_scale}; allowed: settling.stiffness_scale <= numerics.stiffness_scale "
                "(settle soft, then stiffen)"
            )
        if self.analysis.transient_time >= self.process.duration:
            raise ValueError(
                f"analysis.transient_time = {self.analysis.transient_time} s leaves no data after the transient "
                f"(process.duration = {self.process.duration} s); allowed: transient_time < duration"
            )

    def touching_pairs(self) -> list[tuple[str, str]]:
        """Material pairs that can come into contact: media-media, media-bowl, media-workpiece."""
        m = self.media.material
        pairs = {tuple(sorted((m, m))), tuple(sorted((m, self.bowl.material))), tuple(sorted((m, self.workpiece.material)))}
        return sorted(pairs)

    @property
    def settling_stiffness_scale(self) -> float:
        """Young's modulus factor while settling and inserting the rod, -."""
        return self.settling.stiffness_scale or self.numerics.stiffness_scale

    @property
    def settling_timestep_factor(self) -> float:
        """Time-step factor (of the settling Rayleigh step) while settling and inserting, -."""
        return self.settling.timestep_factor or self.numerics.timestep_factor

    @property
    def impact_window(self) -> tuple[float, float] | None:
        """output.impact_window cut to the process, s of process time, or None."""
        window = self.output.impact_window
        return None if window is None else (float(window[0]), min(float(window[1]), self.process.duration))

    @property
    def angular_velocity(self) -> float:
        """Angular velocity of the rod about the bowl axis, rad/s."""
        return self.workpiece.speed / self.workpiece.path_radius


def check_drag_finishing(case) -> None:
    """Memory of the bed, step counts and the record interval of a drag-finishing case."""

    check_memory(f"media.count = {case.media.count}", case.media.count, BYTES_PER_DEM_PARTICLE, "fewer balls")

    media = case.media
    r_min = media.radius - (2.0 if media.distribution == "normal" else 1.0) * media.radius_spread
    material = case.materials[media.material]
    step = case.numerics.timestep_factor * rayleigh_timestep(r_min, material, case.numerics.stiffness_scale)
    settle = case.settling_timestep_factor * rayleigh_timestep(r_min, material, case.settling_stiffness_scale)
    step_key = "the time step (numerics.timestep_factor x the Rayleigh step of the smallest ball)"
    check_steps("process.duration", case.process.duration, step_key, step)
    check_interval("output.record_interval", case.output.record_interval, "process.duration", case.process.duration,
                   "numerics.timestep_factor x the Rayleigh step", step)
    checkpoints = getattr(case.output, "checkpoint_interval", None)
    if checkpoints is not None:  # each writes the whole scene: a few thousand at most
        check_interval("output.checkpoint_interval", checkpoints, "process.duration", case.process.duration,
                       most=MAX_CHECKPOINTS, what="checkpoints")
    settle_time = case.settling.max_time + case.settling.relax_time + case.settling.stiffen_time
    check_steps("settling.max_time + relax_time + stiffen_time", settle_time,
                "the settling time step (settling.timestep_factor x the Rayleigh step at settling.stiffness_scale)",
                settle)
