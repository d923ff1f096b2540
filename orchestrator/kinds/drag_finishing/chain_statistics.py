"""Statistics over the contact snapshots of a run, for the contact-chain analysis (chains.py): means with and
without a condition, lagged correlation with a force series, the series' peaks and how often a peak meets a
chain, binned means. Pure numpy; units are those of the arrays given (times in s).
"""

from __future__ import annotations

import math

import numpy as np


def conditional_means(values: np.ndarray, condition: np.ndarray) -> dict[str, float]:
    """Mean, std and count of values where condition holds ("with") and where not ("without"), in values' units."""
    values, condition = np.asarray(values, float), np.asarray(condition, bool)
    out = {}
    for name, sel in (("with", condition), ("without", ~condition)):
        v = values[sel & np.isfinite(values)]
        out[f"{name}_n"] = int(v.size)
        out[f"{name}_mean"] = float(v.mean()) if v.size else math.nan
        out[f"{name}_std"] = float(v.std(ddof=1)) if v.size > 1 else math.nan
    return out


def lagged_correlation(t_events: np.ndarray, counts: np.ndarray, t: np.ndarray, signal: np.ndarray,
                       lags: np.ndarray) -> np.ndarray:
    """Pearson correlation of counts (at times t_events, s) with signal(t_event + lag) for each lag (s);
    the signal (sampled at t, s) is interpolated linearly. nan where fewer than 3 events fall inside
    the signal's span or either side is constant. Positive lag: the signal follows the counts."""
    t_events, counts = np.asarray(t_events, float), np.asarray(counts, float)
    t, signal = np.asarray(t, float), np.asarray(signal, float)
    r = np.full(len(lags), math.nan)
    for i, lag in enumerate(lags):
        when = t_events + lag
        inside = (when >= t[0]) & (when <= t[-1])
        if inside.sum() < 3:
            continue
        x, y = counts[inside], np.interp(when[inside], t, signal)
        if x.std() > 0 and y.std() > 0:
            r[i] = float(np.corrcoef(x, y)[0, 1])
    return r


def force_peaks(t: np.ndarray, drag: np.ndarray, k_peak: float = 1.0,
                min_gap: float = 0.05) -> tuple[np.ndarray, np.ndarray, float]:
    """(peak times s, peak values, threshold) of a series: one peak per run of samples above mean + k_peak
    std (same units as drag), at the run's largest sample; runs less than min_gap (s) apart count as one
    (noise makes a single excursion cross the threshold several times)."""
    t, drag = np.asarray(t, float), np.asarray(drag, float)
    thr = float(np.nanmean(drag) + k_peak * np.nanstd(drag))
    above = np.concatenate([[False], drag > thr, [False]])
    starts, ends = np.flatnonzero(~above[:-1] & above[1:]), np.flatnonzero(above[:-1] & ~above[1:])
    runs: list[list[int]] = []
    for s, e in zip(starts, ends):
        if runs and t[s] - t[runs[-1][1] - 1] < min_gap:
            runs[-1][1] = e
        else:
            runs.append([s, e])
    idx = np.array([s + int(np.argmax(drag[s:e])) for s, e in runs], dtype=int)
    return t[idx], drag[idx], thr


def peak_coincidence(peak_times: np.ndarray, t_snap: np.ndarray, has_chain: np.ndarray,
                     window: float | None = None) -> dict[str, float]:
    """Fraction of force peaks whose nearest snapshot (within window s; default half the median snapshot
    spacing) has a chain, next to the base rate (fraction of all snapshots with a chain). Peaks with no
    snapshot within the window are not counted."""
    t_snap, has_chain = np.asarray(t_snap, float), np.asarray(has_chain, bool)
    peak_times = np.asarray(peak_times, float)
    if window is None:
        window = 0.5 * float(np.median(np.diff(np.sort(t_snap)))) if len(t_snap) > 1 else 0.0
    base = float(has_chain.mean()) if has_chain.size else math.nan
    if not t_snap.size or not peak_times.size:
        return {"n_peaks": 0, "fraction": math.nan, "base_rate": base, "window": window}
    nearest = np.argmin(np.abs(peak_times[:, None] - t_snap[None, :]), axis=1)
    covered = np.abs(t_snap[nearest] - peak_times) <= window + 1e-12
    hits = has_chain[nearest[covered]]
    return {"n_peaks": int(covered.sum()), "fraction": float(hits.mean()) if hits.size else math.nan,
            "base_rate": base, "window": float(window)}


def binned_mean(x: np.ndarray, values: np.ndarray, edges: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(mean, std, count) of values in the bins of x given by edges (len(edges) - 1 each; nan if empty)."""
    x, values = np.asarray(x, float), np.asarray(values, float)
    idx = np.digitize(x, edges) - 1
    nb = len(edges) - 1
    ok = (idx >= 0) & (idx < nb) & np.isfinite(values)
    count = np.bincount(idx[ok], minlength=nb).astype(float)
    s1 = np.bincount(idx[ok], values[ok], minlength=nb)
    s2 = np.bincount(idx[ok], values[ok] ** 2, minlength=nb)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = s1 / count
        std = np.sqrt(np.maximum(s2 / count - mean**2, 0.0))
    return mean, std, count.astype(int)
