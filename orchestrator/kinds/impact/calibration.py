"""`orchestrator calibrate restitution`: fit e_n from a sphere drop, as
Uhlmann et al. (2015, section 4) did: from "the change in the magnitude of
the maximum impact forces and the time since the first impact" of the first
three impacts.

Observed: the peak forces F_1..F_3 (N) and the peak times t_1..t_3 (s), from
a force-sensor trace (CSV: time in s, force in N) or from a simulated run
(its contact events). Model: the drop case's closed forms (damped Hertz
peaks at v_k = e_n^(k-1) sqrt(2 g h), flights 2 e_n v_k / g plus the contact
durations) for a trial e_n, the case's damping mapping included. The fit
minimises the squared log-residuals of F_2/F_1, F_3/F_1, t_2 - t_1 and
t_3 - t_1: ratios and differences, so that neither the sensor's compliance
(absolute force) nor its clock offset enters.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from orchestrator.case.loader import shipped_cases
from orchestrator.errors import CaseError, OrchestratorError, ReadError
from orchestrator.kinds.impact.theory import CLOSED_FORMS, NotApplicable, first_impact
from orchestrator.reference import closed_form
from orchestrator.runh5 import read_run, stored_case

#: A force sample counts as part of an impact above this fraction of the largest force.
CONTACT_THRESHOLD = 0.05
#: A fit fails when a feature's relative residual exceeds this: the data contradict the model.
MAX_RESIDUAL = 0.10
#: Range of e_n the fit searches, -.
RESTITUTION_BOUNDS = (0.01, 0.999)


@dataclass(frozen=True)
class DropObservation:
    """The first three impacts: peak forces (N) and the times of the peaks (s)."""

    peak_forces: tuple[float, float, float]
    peak_times: tuple[float, float, float]

    def features(self) -> np.ndarray:
        """[F_2/F_1, F_3/F_1, t_2 - t_1, t_3 - t_1] (-, -, s, s)."""
        f, t = self.peak_forces, self.peak_times
        return np.array([f[1] / f[0], f[2] / f[0], t[1] - t[0], t[2] - t[0]])


@dataclass(frozen=True)
class RestitutionFit:
    """The fitted e_n (-), the observation, the model at the fit and the relative residual of each feature;
    failure says why the fit is not to be trusted (empty when it is)."""

    restitution: float
    observed: DropObservation
    model: DropObservation
    residuals: dict[str, float]
    source: str
    failure: str = ""


FEATURES = ("F2/F1", "F3/F1", "t2-t1", "t3-t1")


def observations_from_csv(path) -> DropObservation:
    """Peaks of the first three impacts in a CSV trace with a header and columns time (s), force (N).

    An impact is a run of samples above CONTACT_THRESHOLD of the largest force; its
    peak is the largest sample (refined by a parabola through it and its neighbours).
    """
    path = Path(path)
    if path.is_dir():
        raise ReadError(f"{path} is a directory; give a CSV file with columns time_s,force_N")
    if path.exists() and not path.is_file():
        raise ReadError(f"{path} is not a regular file (a device, pipe or socket); give a CSV file with columns "
                        "time_s,force_N")
    if not path.is_file():
        raise ReadError(f"no CSV file at {path}; give a file with columns time_s,force_N")
    try:
        with open(path, newline="") as fh:
            rows = list(csv.reader(fh))
        data = np.array([[float(v) for v in row[:2]] for row in rows[1:] if row], dtype=float)
    except (ValueError, IndexError):
        raise ReadError(f"{path}: expected a header line, then rows 'time_s,force_N' of numbers") from None
    except (UnicodeDecodeError, csv.Error):
        raise ReadError(f"{path}: not a text CSV; expected a header line, then rows 'time_s,force_N'") from None
    if data.ndim != 2 or len(data) < 10:
        raise ReadError(f"{path}: fewer than 10 samples; expected rows 'time_s,force_N'")
    if not np.all(np.isfinite(data)):
        row = int(np.flatnonzero(~np.all(np.isfinite(data), axis=1))[0]) + 2
        raise ReadError(f"{path}: line {row} holds a value that is not a finite number (inf or nan); allowed: "
                        "finite times (s) and forces (N)")
    time, force = data[:, 0], data[:, 1]
    if np.any(np.diff(time) <= 0):
        raise ReadError(f"{path}: the times (first column, s) must increase")
    above = force > CONTACT_THRESHOLD * force.max()
    edges = np.flatnonzero(np.diff(above.astype(int)))
    starts = list(np.flatnonzero(above[:1])) + [e + 1 for e in edges if not above[e]]
    peaks_t, peaks_f = [], []
    for start in starts[:3]:
        stop = start
        while stop < len(force) and above[stop]:
            stop += 1
        k = start + int(np.argmax(force[start:stop]))
        t_k, f_k = _parabola_peak(time, force, k)
        peaks_t.append(t_k)
        peaks_f.append(f_k)
    if len(peaks_f) < 3:
        raise ReadError(f"{path}: found {len(peaks_f)} impact(s) above {CONTACT_THRESHOLD:.0%} of the largest "
                        "force; the fit needs the first three")
    return DropObservation(tuple(peaks_f), tuple(peaks_t))


def _parabola_peak(time, force, k):
    if 0 < k < len(force) - 1:
        t, f = time[k - 1:k + 2], force[k - 1:k + 2]
        a, b, c = np.polyfit(t - t[1], f, 2)
        if a < 0:
            shift = -b / (2 * a)
            if abs(shift) <= t[2] - t[1]:
                return float(t[1] + shift), float(c - b * b / (4 * a))
    return float(time[k]), float(force[k])


def observations_from_run(run_dir) -> tuple[DropObservation, object]:
    """The first three contacts' peaks of a simulated drop (run.h5 events) and the run's case model."""

    run = read_run(run_dir)
    events = run.get("events", {})
    if "peak_normal_force" not in events or len(events["peak_normal_force"]) < 3:
        raise ReadError(f"{run_dir}: the run has fewer than three contact events; the fit needs a sphere drop with "
                        "three impacts (e.g. cases/verification/uhlmann2015_sphere_drop.toml)")
    order = np.argsort(events["start_time"])[:3]
    observed = DropObservation(tuple(float(v) for v in events["peak_normal_force"][order]),
                               tuple(float(v) for v in events["peak_time"][order]))
    return observed, stored_case(run, run_dir)


def drop_model(case, restitution: float) -> DropObservation:
    """Peaks (N) and peak times (s, from release) of the case's first three impacts for a trial e_n.

    The case must be one sphere dropped under gravity onto the plane. Peak time
    = start of the contact + the time to the peak of the damped Hertz impact
    (taken as half the contact, which moves t_k - t_1 by under 1e-5 of itself).
    """

    trial = with_restitution(case, restitution)
    try:
        impact = first_impact(trial)
        peaks = [CLOSED_FORMS[f"damped_hertz_peak_force_{k}"].function(trial) for k in (1, 2, 3)]
        gaps = [CLOSED_FORMS[f"ballistic_time_between_impacts_{k}"].function(trial) for k in (1, 2)]
    except NotApplicable as exc:
        raise CaseError(f"{case.case.name} is not a sphere drop the fit can model: {exc}") from None
    speeds = impact.normal_speed * restitution ** np.arange(3)
    ratio = closed_form.damped_hertz_impact(impact.alpha, True).duration_ratio
    halves = [0.5 * ratio * closed_form.hertz_contact_duration(impact.effective_m, impact.effective_radius,
                                                               impact.effective_young, v) for v in speeds]
    first = impact.normal_speed / impact.gravity
    starts = [first, first + gaps[0], first + gaps[0] + gaps[1]]
    return DropObservation(tuple(peaks), tuple(s + h for s, h in zip(starts, halves)))


def with_restitution(case, restitution: float):
    """A copy of the case whose sphere-plane pair has e_n = restitution (damping 'engine' modelled as 'exact')."""
    if case.case.kind != "impact":
        raise CaseError(f"{case.case.name} is a {case.case.kind} case, not a sphere drop; give an impact case with "
                        "one sphere, a plane and gravity with --case (e.g. cases/verification/"
                        "uhlmann2015_sphere_drop.toml)")
    if case.plane is None or len(case.spheres) != 1 or not case.simulation.gravity:
        raise CaseError(f"{case.case.name} is not a sphere drop (one sphere, a plane, gravity); give the drop's case "
                        "with --case")
    names = sorted((case.spheres[0].material, case.plane.material))
    contacts = tuple(c.model_copy(update={"restitution": float(restitution)}) if sorted(c.pair) == names else c
                     for c in case.contacts)
    model = case.model if case.model.damping != "engine" else case.model.model_copy(update={"damping": "exact"})
    return case.model_copy(update={"contacts": contacts, "model": model})


def fit_restitution(case, observed: DropObservation, source: str = "") -> RestitutionFit:
    """The e_n (-) whose modelled drop best matches the observed ratios and time differences."""
    from scipy.optimize import minimize_scalar

    target = observed.features()
    if np.any(target <= 0) or not np.all(np.isfinite(target)):
        raise OrchestratorError("the observed impacts do not fall and bounce: peaks must be positive and in order")

    def cost(e):
        return float(np.sum(np.log(drop_model(case, e).features() / target) ** 2))

    # first guess from the leading-order relations F_k+1 / F_k = e^(6/5) and (t3 - t2) / (t2 - t1) = e
    from_forces = (target[0] ** (1 / 1.2) * target[1] ** (1 / 2.4)) ** 0.5
    from_times = target[3] / target[2] - 1.0
    guess = float(np.clip(0.5 * (from_forces + from_times), 0.05, 0.99))
    low, high = RESTITUTION_BOUNDS
    window = (max(low, guess - 0.05), min(high, guess + 0.05))
    result = minimize_scalar(cost, bounds=window, method="bounded", options={"xatol": 1e-6})
    if min(abs(result.x - window[0]), abs(result.x - window[1])) < 1e-4:  # the optimum lies outside the window
        result = minimize_scalar(cost, bounds=(low, high), method="bounded", options={"xatol": 1e-6})
    restitution = float(result.x)
    model = drop_model(case, restitution)
    residuals = dict(zip(FEATURES, (model.features() / target - 1.0).tolist()))
    return RestitutionFit(restitution, observed, model, residuals, source, fit_failure(observed, restitution,
                                                                                        residuals))


def fit_failure(observed: DropObservation, restitution: float, residuals: dict[str, float]) -> str:
    """Why a fit is not to be trusted, or '' when it is: peaks that grow (a drop loses energy at every impact),
    an e_n at the edge of RESTITUTION_BOUNDS, or a relative residual above MAX_RESIDUAL."""
    f = observed.peak_forces
    reasons = []
    if f[1] > f[0] or f[2] > f[1]:
        reasons.append(f"the peaks grow ({' N, '.join(f'{v:.4g}' for v in f)} N) while a bouncing sphere loses "
                       "energy at every impact: the data contradict the model")
    low, high = RESTITUTION_BOUNDS
    if min(restitution - low, high - restitution) < 1e-3:
        reasons.append(f"e_n = {restitution:.4f} is at the edge of the range searched ({low} to {high})")
    worst = max(residuals, key=lambda k: abs(residuals[k]))
    if not abs(residuals[worst]) <= MAX_RESIDUAL:
        reasons.append(f"the model misses {worst} by {residuals[worst]:+.0%}; allowed: at most "
                       f"{MAX_RESIDUAL:.0%} on every feature")
    return "; ".join(reasons)


def format_fit(fit: RestitutionFit) -> str:
    """Plain text: the fitted e_n, then observed and modelled features with their relative residuals."""
    lines = [f"fitted e_n    {fit.restitution:.4f}   (from {fit.source})"
             + ("   FAILED FIT: see the error below" if fit.failure else ""),
             f"{'feature':<9} {'observed':>12} {'model':>12} {'residual':>9}"]
    units = {"F2/F1": "-", "F3/F1": "-", "t2-t1": "s", "t3-t1": "s"}
    for name, obs, mod in zip(FEATURES, fit.observed.features(), fit.model.features()):
        lines.append(f"{name + ' [' + units[name] + ']':<9} {obs:12.6g} {mod:12.6g} {fit.residuals[name]:+9.2e}")
    lines.append("peaks [N]     " + "  ".join(f"{f:.4g}" for f in fit.observed.peak_forces)
                 + "   at t [s] " + "  ".join(f"{t:.6g}" for t in fit.observed.peak_times))
    return "\n".join(lines)


def drop_case_path() -> Path:
    """The shipped sphere-drop case (the paper's setup)."""

    return shipped_cases("verification") / "uhlmann2015_sphere_drop.toml"


__all__ = ["DropObservation", "RestitutionFit", "drop_model", "fit_restitution", "format_fit",
           "observations_from_csv", "observations_from_run"]
