"""The drag-finishing phase schedule, computed once for every engine: time steps, record and control periods,
the steps of each phase and the planned total (settling counted at its maximum time). Steps are counts of the
phase's own time step; SI units otherwise."""

from __future__ import annotations

from dataclasses import dataclass

from orchestrator.kinds.drag_finishing.scene import settling_timestep

#: Period of the engines' control checks (rest criterion, stiffening stages), s.
CONTROL_PERIOD_S = 1e-3


def every(interval: float, step: float) -> int:
    """Steps of length step in interval (at least 1)."""
    return max(1, round(interval / step))


@dataclass(frozen=True)
class Schedule:
    """The phases of a drag-finishing run: settle (at most settling.max_time, dt_settle), insert the rod (dt_settle),
    relax (dt_settle), stiffen in stages and relax again when the process runs stiffer or with another step (dt), then
    the process (dt)."""

    dt: float  # s, the process step
    dt_settle: float  # s, settling and insertion
    stiffen: bool  # the process runs at another stiffness or step than the settling
    record_every: int  # process steps between records
    record_every_settle: int  # settling steps between records
    control_every: int  # process steps between control checks (and of one stiffening stage)
    control_every_settle: int  # settling steps between control checks
    stiffen_stages: int  # stages of the stiffening ramp
    settle_steps: float  # the most settling steps (settling.max_time / dt_settle)
    insert_steps: float  # steps that bring the rod's tip from its parking height to the target depth
    relax_steps_settle: int  # rest after insertion, settling steps
    relax_steps: int  # rest after stiffening, process steps
    process_steps: int

    @property
    def steps_after_insert(self) -> int:
        """Relax, the stiffening ramp and its relax (when stiffening), and the process."""
        ramp = self.stiffen_stages * self.control_every + self.relax_steps if self.stiffen else 0
        return self.relax_steps_settle + ramp + self.process_steps

    @property
    def planned_steps(self) -> int:
        """Upper bound of the whole run's steps (settling at its maximum time)."""
        return int(self.settle_steps + self.insert_steps + self.steps_after_insert)


def schedule(scene) -> Schedule:
    """The schedule of a drag-finishing scene."""
    case = scene.case
    dt, dt_settle = scene.timestep, settling_timestep(case)
    record_every = every(case.output.record_interval, dt)
    control_every = min(record_every, every(CONTROL_PERIOD_S, dt))
    record_every_settle = every(case.output.record_interval, dt_settle)
    relax = case.settling.relax_time
    return Schedule(
        dt=dt, dt_settle=dt_settle,
        stiffen=case.numerics.stiffness_scale != case.settling_stiffness_scale or dt != dt_settle,
        record_every=record_every, record_every_settle=record_every_settle,
        control_every=control_every,
        control_every_settle=min(record_every_settle, every(CONTROL_PERIOD_S, dt_settle)),
        stiffen_stages=max(1, round(case.settling.stiffen_time / (control_every * dt))),
        settle_steps=case.settling.max_time / dt_settle,
        insert_steps=(case.workpiece.submersion_depth + 2 * case.media.radius) / case.workpiece.insertion_speed
        / dt_settle,
        relax_steps_settle=every(relax, dt_settle) if relax > 0 else 0,
        relax_steps=every(relax, dt) if relax > 0 else 0,
        process_steps=every(case.process.duration, dt),
    )
