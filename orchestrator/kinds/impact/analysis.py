"""Impact runs: the measured quantities (from the contact events and the
series every engine writes), the case's checks against them and `orchestrator analyze` of a run.

Contact events (Result.events, run.h5 /events; columns and units in
orchestrator.reference.dem_forces.EVENT_FIELDS) hold one row per contact
from first touch to separation, with the same definitions on every engine:
start_time = t_1 - delta_1 / rate_1 at the first step in contact (t_1, the
overlap delta_1 and its rate), end_time likewise at the last step,
impact_speed / rebound_speed the normal approach / separation rates there,
peak_normal_force and max_overlap the largest over the steps in contact.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from orchestrator.kinds.impact.plots import ForceCurve, plot_force_curves
from orchestrator.kinds.impact.theory import QUANTITIES, NotApplicable, expected_value

#: other_kind codes of an event: the other body is a sphere, or the plane.
OTHER_SPHERE, OTHER_PLANE = 0, 1
#: Contact events are recorded for scenes of at most this many spheres (impacts); a dense scene's
#: contacts are not impacts, and every engine leaves them out alike.
EVENT_LIMIT = 50


def _events(result) -> dict[str, np.ndarray]:
    events = {name: np.asarray(item.values) for name, item in result.events.items()}
    if not events or "start_time" not in events:
        return {}
    order = np.argsort(events["start_time"], kind="stable")
    return {name: values[order] for name, values in events.items()}


def measure_impact(case, result) -> dict[str, float]:
    """The QUANTITIES this run shows (a quantity is left out when the run lacks it, e.g. fewer than 3 impacts;
    a scene of more than EVENT_LIMIT spheres has no contact events)."""
    events = _events(result)
    if not events:
        return {}
    out: dict[str, float] = {"n_contacts": float(len(events["start_time"]))}
    if not len(events["start_time"]):
        return out
    first = {name: values[0] for name, values in events.items()}
    out["max_normal_force"] = float(first["peak_normal_force"])
    out["max_overlap"] = float(first["max_overlap"])
    if np.isfinite(first["end_time"]):
        out["contact_duration"] = float(first["end_time"] - first["start_time"])
        if first["impact_speed"] > 0:
            out["restitution"] = float(first["rebound_speed"] / first["impact_speed"])
    for k in range(min(3, len(events["start_time"]))):
        out[f"peak_force_{k + 1}"] = float(events["peak_normal_force"][k])
    for k in range(min(2, len(events["start_time"]) - 1)):
        out[f"time_between_impacts_{k + 1}"] = float(events["start_time"][k + 1] - events["start_time"][k])
    out.update(_rebound_along_wall(case, result, events))
    return out


def _rebound_along_wall(case, result, events) -> dict[str, float]:
    """Tangential velocity and spin of the sphere after its first wall contact, from the first record after it."""
    if case.plane is None or result.time is None or "velocities" not in result.series:
        return {}
    walls = np.flatnonzero(events["other_kind"] == OTHER_PLANE)
    if not len(walls) or not np.isfinite(events["end_time"][walls[0]]):
        return {}
    k = walls[0]
    sphere = int(events["sphere"][k])
    normal = np.array(case.plane.unit_normal)
    incoming = np.array(case.spheres[sphere].velocity, float)
    tangential = incoming - (incoming @ normal) * normal
    if np.linalg.norm(tangential) == 0.0:
        return {}
    direction = tangential / np.linalg.norm(tangential)
    after = np.flatnonzero(result.time >= events["end_time"][k])
    later = events["start_time"][events["start_time"] > events["start_time"][k]]
    if not len(after) or (len(later) and result.time[after[0]] >= later.min()):
        return {}
    row = after[0]
    velocity = result.series["velocities"].values[row, sphere]
    spin = result.series["angular_velocities"].values[row, sphere]
    return {"rebound_tangential_velocity": float(velocity @ direction),
            "rebound_spin": float(spin @ np.cross(normal, direction))}


@dataclass(frozen=True)
class CheckResult:
    """One check of a run: measured value, expected value (SI), relative error, tolerance, passed.

    rel_error = |value - expected| / |expected| (|value - expected| when expected is 0);
    source: 'value' or the closed form's name; note: why a check could not be made.
    """

    quantity: str
    value: float
    expected: float
    rel_error: float
    tolerance: float
    passed: bool
    source: str
    note: str = ""

    def as_dict(self) -> dict:
        """Plain dict."""
        return asdict(self)


def relative_error(value: float, expected: float) -> float:
    """|value - expected| / |expected|, or |value - expected| when expected is 0."""
    if not (math.isfinite(value) and math.isfinite(expected)):
        return math.nan
    return abs(value - expected) / abs(expected) if expected != 0 else abs(value - expected)


def evaluate_checks(case, measured: dict) -> list[CheckResult]:
    """Every [[expected]] check of the case against the measured quantities."""

    rows = []
    for check in case.expected:
        source = check.closed_form or "value"
        note = ""
        try:
            expected = expected_value(case, check)
        except NotApplicable as exc:
            expected, note = math.nan, f"closed form not applicable: {exc}"
        value = float(measured.get(check.quantity, math.nan))
        if not math.isfinite(value) and not note:
            note = "not measured (the run did not show it)"
        error = relative_error(value, expected)
        rows.append(CheckResult(check.quantity, value, expected, error, check.tolerance,
                                bool(math.isfinite(error) and error <= check.tolerance), source, note))
    return rows


def expected_values(case) -> dict[str, float]:
    """{quantity: expected value} of every [[expected]] check of the case (closed forms in SI; NaN where a
    closed form does not apply): what `compare` prints beside the engines' values."""
    return {check.quantity: check.expected for check in evaluate_checks(case, {})}


def analyze_impact_run(run_dir: Path, run: dict, case, render: bool = True) -> dict:
    """Print an impact run's checks (measured against expected, SI units) and write forces.png."""
    attrs = run["attrs"]
    measured = run.get("measured", {}).get("attrs", {})
    spheres = f"{attrs['n_particles']} sphere{'s' if attrs['n_particles'] != 1 else ''}"
    print(f"run {run_dir}: status {attrs['status']}, {attrs['engine']} {attrs['engine_version']}, {spheres}, "
          f"{attrs['n_steps']} steps, {attrs['wall_time_s']:.1f} s")
    if attrs.get("deviation"):
        print(f"note: {attrs['deviation']}")
    for name, (unit, meaning) in QUANTITIES.items():
        if name in measured:
            print(f"{name:<28} {measured[name]:<12.6g} {unit:<6} {meaning}")
    for row in evaluate_checks(case, measured):
        verdict = "pass" if row.passed else "FAIL"
        print(f"check {row.quantity:<28} expected {row.expected:<12.6g} ({row.source}) rel_error {row.rel_error:.2e} "
              f"tolerance {row.tolerance:g} {verdict}" + (f" ({row.note})" if row.note else ""))
    scene = ForceCurve(case.case.name, attrs["engine"], attrs["status"])
    series, events = run.get("series", {}), run.get("events", {})
    if "normal_force" in series:
        scene.time, scene.normal_force = series["time"], series["normal_force"]
    if "peak_time" in events:
        scene.peaks = np.column_stack([events["peak_time"], events["peak_normal_force"]])
    path = plot_force_curves([scene], run_dir / "forces.png")
    print(f"forces   {path}")
    return {"forces": path}
