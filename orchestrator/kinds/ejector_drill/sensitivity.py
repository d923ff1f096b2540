"""How the 1D network's feed pressure depends on its reconstructed dimensions and loss coefficients
(reference/drill_network.py): a one-at-a-time scan (each parameter times a few factors, the others at the case's
values), the factor that brings the feed to each edge of the paper's 10-20 bar, and a map over the ejector nozzles'
total area and the annular gap d_Diff. The paper (Canini et al.) states the bore, d_Diff, the flows and the expected
pressure; every other number the network has is a reconstruction, and this says which of them the 30 bar hang on.

Units: SI inside (m, m^2, Pa s, m^3/s); the results carry the feed's gauge pressure in bar and flows in l/min, the
parameters' values in the unit of their Parameter (mm, mm^2, mPa s, um or -)."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from orchestrator.errors import OrchestratorError
from orchestrator.kinds.ejector_drill.comparison import PAPER_BAR
from orchestrator.reference.drill_network import LITRE_PER_MIN, DrillNetwork, solve


@dataclass(frozen=True)
class Parameter:
    """A scanned quantity: name, a DrillNetwork field or one of DERIVED; label, what it is; unit and scale, the
    display unit and the factor from SI to it; integer, a count (rounded to a whole number in the scan)."""

    name: str
    label: str
    unit: str
    scale: float = 1.0
    integer: bool = False


#: Quantities that set several fields at once: the nozzle's discharge coefficient Cd = 1 / sqrt(1 + K_p), the tube
#: set's bore (the outer tube's ID with both walls and the gap kept), the radial clearances of the head and of the
#: outer tube to the bore (the bore, the paper's 30 mm, stays).
DERIVED = ("nozzle_cd", "tube_bore", "head_clearance", "tube_clearance")

PARAMETERS = (
    Parameter("n_ejector_nozzles", "ejector nozzle count", "-", integer=True),
    Parameter("d_ejector_nozzle", "ejector nozzle diameter", "mm", 1e3),
    Parameter("nozzle_cd", "ejector nozzle Cd = 1/sqrt(1+K_p)", "-"),
    Parameter("k_secondary", "ejector suction entry K_s", "-"),
    Parameter("mixing_length", "ejector mixing length", "mm", 1e3),
    Parameter("d_diff", "annular gap d_Diff (diametral)", "mm", 1e3),
    Parameter("tube_bore", "tube set bore (outer tube ID)", "mm", 1e3),
    Parameter("tube_length", "tube length", "mm", 1e3),
    Parameter("d_inner_tube_id", "inner tube ID", "mm", 1e3),
    Parameter("roughness", "tube wall roughness", "um", 1e6),
    Parameter("n_holes", "adduction hole count", "-", integer=True),
    Parameter("d_hole", "adduction hole diameter", "mm", 1e3),
    Parameter("cd_hole", "adduction hole Cd", "-"),
    Parameter("front_area", "cutting-zone passage area", "mm^2", 1e6),
    Parameter("k_cutting_zone", "cutting-zone turns K", "-"),
    Parameter("d_chip_mouth", "chip mouth diameter", "mm", 1e3),
    Parameter("head_clearance", "head/bore clearance (radial)", "mm", 1e3),
    Parameter("tube_clearance", "outer tube/bore clearance (radial)", "mm", 1e3),
    Parameter("pad_blockage", "guide pads' blockage of the head clearance", "-"),
    Parameter("bore_depth", "drilled depth", "mm", 1e3),
    Parameter("mu", "coolant viscosity", "mPa s", 1e3),
)
BY_NAME = {p.name: p for p in PARAMETERS}
DEFAULT_FACTORS = (0.5, 0.75, 1.5, 2.0)


def parameter(name: str) -> Parameter:
    """The Parameter called name (OrchestratorError naming the known ones otherwise)."""
    if name not in BY_NAME:
        raise OrchestratorError(f"unknown network parameter {name!r}; allowed: {', '.join(BY_NAME)}")
    return BY_NAME[name]


def parameter_value(net: DrillNetwork, name: str) -> float:
    """The value of a parameter (SI: m, m^2, Pa s, or -) in the network net."""
    if name == "nozzle_cd":
        return 1.0 / math.sqrt(1.0 + net.k_primary)
    if name == "tube_bore":
        return net.d_outer_tube_id
    if name == "head_clearance":
        return 0.5 * (net.d_bore - net.d_head_body)
    if name == "tube_clearance":
        return 0.5 * (net.d_bore - net.d_outer_tube_od)
    return float(getattr(net, parameter(name).name))


def with_value(net: DrillNetwork, name: str, value: float, whole_counts: bool = True) -> DrillNetwork:
    """The network net with the parameter name set to value (SI); a count is rounded to a whole number unless
    whole_counts is False (then it stands for the equivalent total area, e.g. of the nozzles)."""
    p = parameter(name)
    if name == "nozzle_cd":
        return dataclasses.replace(net, k_primary=1.0 / value**2 - 1.0)
    if name == "tube_bore":
        outer_wall = net.d_outer_tube_od - net.d_outer_tube_id
        inner_wall = net.d_inner_tube_od - net.d_inner_tube_id
        return dataclasses.replace(net, d_outer_tube_id=value, d_outer_tube_od=value + outer_wall,
                                   d_inner_tube_id=value - net.d_diff - inner_wall)
    if name == "head_clearance":
        return dataclasses.replace(net, d_head_body=net.d_bore - 2.0 * value)
    if name == "tube_clearance":
        return dataclasses.replace(net, d_outer_tube_od=net.d_bore - 2.0 * value)
    if p.integer and whole_counts:
        value = max(1, math.floor(value + 0.5))
    return dataclasses.replace(net, **{name: value})


def impossibility(net: DrillNetwork) -> str:
    """Why the network's geometry cannot be built ('' when it can): the tubes nest inside each other and the bore,
    the head fits the bore, the nozzles' area is below the inner tube's, Cd at most 1, the pads leave a passage."""
    checks = (
        (net.d_outer_tube_od < net.d_bore, "the outer tube is wider than the bore"),
        (net.d_outer_tube_id < net.d_outer_tube_od, "the outer tube has no wall"),
        (net.d_inner_tube_id < net.d_inner_tube_od, "the inner tube has no wall"),
        (net.d_head_body < net.d_bore, "the head is wider than the bore"),
        (net.nozzle_area < 0.25 * math.pi * net.d_inner_tube_id**2, "the nozzles' area exceeds the inner tube's"),
        (net.cd_hole <= 1.0 and net.k_primary >= 0.0, "a discharge coefficient above 1"),
        (net.pad_blockage < 1.0, "the guide pads close the head clearance"),
    )
    return "; ".join(reason for ok, reason in checks if not ok)


@dataclass(frozen=True)
class Point:
    """The network solved with one parameter changed: parameter name, factor on its base value (-), value (SI),
    the feed's gauge pressure p_feed_bar (bar), the nozzles' V_EN and the leak's V_loss (l/min; V_loss < 0: the
    ejector draws from the bore mouth), the gauge pressures at C1 and at the jet pump's mixing entry (its lowest)
    p_C1_bar and p_mixing_bar (bar), cavitating (the mixing entry below the vapour pressure), and note: '' or why the geometry cannot be built or the network did not solve (its
    numbers are then still shown when the network solved, NaN when it did not)."""

    parameter: str
    factor: float
    value: float
    p_feed_bar: float
    V_EN: float
    V_loss: float
    p_C1_bar: float
    p_mixing_bar: float
    cavitating: bool
    note: str = ""

    @property
    def buildable(self) -> bool:
        """True when the point's geometry can exist and the network solved."""
        return not self.note and math.isfinite(self.p_feed_bar)


def solve_point(net: DrillNetwork, flow_lpm: float, name: str = "", factor: float = 1.0,
                whole_counts: bool = True) -> Point:
    """The network net at the feed flow flow_lpm (l/min) with the parameter name times factor ('' : net as is)."""
    value = parameter_value(net, name) * factor if name else math.nan
    changed = with_value(net, name, value, whole_counts) if name else net
    if name:
        value = parameter_value(changed, name)
    note = impossibility(changed)
    try:
        s = solve(changed, flow_lpm * LITRE_PER_MIN)
    except (OrchestratorError, ValueError, ZeroDivisionError) as exc:
        reason = str(exc).split("\n")[0]
        return Point(name, factor, value, *[math.nan] * 5, False, note or reason)
    return Point(name, factor, value, s.gauge_bar("p_feed"), s.litres_per_min("V_EN"), s.litres_per_min("V_loss"),
                 s.gauge_bar("p_C1"), s.gauge_bar("p_mixing_entry"), s.cavitating, note)


def one_at_a_time(net: DrillNetwork, flow_lpm: float, factors=DEFAULT_FACTORS, names=None) -> list[Point]:
    """Every parameter (or those named) times each factor (-), the others at net's values, at flow_lpm (l/min)."""
    return [solve_point(net, flow_lpm, name, f) for name in (names or BY_NAME) for f in factors]


def factor_for(net: DrillNetwork, flow_lpm: float, name: str, target_bar: float, low: float = 0.25,
               high: float = 4.0) -> float:
    """The factor (-) on parameter name that puts the feed at target_bar (bar gauge) at flow_lpm (l/min), the
    nearest to 1 in [low, high] where the geometry can be built (counts taken as continuous: the equivalent area);
    NaN when none does."""
    def miss(f):
        p = solve_point(net, flow_lpm, name, f, whole_counts=False)
        return p.p_feed_bar - target_bar if p.buildable else math.nan

    grid = sorted({*np.geomspace(low, high, 25).tolist(), 1.0})
    values = [miss(f) for f in grid]
    brackets = [(a, b) for (a, ma), (b, mb) in zip(zip(grid, values), zip(grid[1:], values[1:]))
                if math.isfinite(ma) and math.isfinite(mb) and ma * mb <= 0.0]
    if not brackets:
        return math.nan
    a, b = min(brackets, key=lambda ab: abs(math.log(math.sqrt(ab[0] * ab[1]))))
    return a if miss(a) == 0.0 else brentq(miss, a, b, xtol=1e-6)


@dataclass(frozen=True)
class BandEdge:
    """Where one parameter alone puts the feed at one edge of the paper's band: parameter name, the target (bar
    gauge), the factor (-; NaN: not within the scanned range), the value there (SI) and that point's V_EN and
    V_loss (l/min) and cavitating flag."""

    parameter: str
    target_bar: float
    factor: float
    value: float
    V_EN: float
    V_loss: float
    cavitating: bool


def band_edges(net: DrillNetwork, flow_lpm: float, names=None, band=PAPER_BAR) -> list[BandEdge]:
    """For every parameter (or those named), the factors that put the feed at each edge of band (bar gauge)."""
    out = []
    for name in names or BY_NAME:
        for target in band:
            f = factor_for(net, flow_lpm, name, target)
            p = solve_point(net, flow_lpm, name, f, whole_counts=False) if math.isfinite(f) else None
            out.append(BandEdge(name, target, f, *((p.value, p.V_EN, p.V_loss) if p else [math.nan] * 3),
                                bool(p and p.cavitating)))
    return out


@dataclass(frozen=True)
class AreaGapMap:
    """The network over the ejector nozzles' total area (m^2, the count kept, the diameter scaled) and the annular
    gap d_Diff (m): p_feed_bar and the jet pump's mixing-entry pressure p_mixing_bar (bar gauge), V_loss (l/min)
    and cavitating, each indexed [gap, area]; buildable: the geometry can exist and the network solved; base_area
    and base_gap: the case's values; p_vapour_bar: the vapour pressure (bar gauge)."""

    areas: np.ndarray
    gaps: np.ndarray
    p_feed_bar: np.ndarray
    p_mixing_bar: np.ndarray
    V_loss: np.ndarray
    cavitating: np.ndarray
    buildable: np.ndarray
    base_area: float
    base_gap: float
    flow_lpm: float
    p_vapour_bar: float


def area_gap_map(net: DrillNetwork, flow_lpm: float, area_factors, gaps) -> AreaGapMap:
    """The network at flow_lpm (l/min) over the nozzle area factors (-, on net's area) and the gaps d_Diff (m)."""
    area_factors, gaps = np.asarray(area_factors, float), np.asarray(gaps, float)
    shape = (gaps.size, area_factors.size)
    p_feed, p_mixing, v_loss = (np.full(shape, np.nan) for _ in range(3))
    cavitating, buildable = np.zeros(shape, bool), np.zeros(shape, bool)
    for i, gap in enumerate(gaps):
        row = dataclasses.replace(net, d_diff=float(gap))
        for j, f in enumerate(area_factors):
            p = solve_point(row, flow_lpm, "d_ejector_nozzle", math.sqrt(f))
            p_feed[i, j], p_mixing[i, j], v_loss[i, j] = p.p_feed_bar, p.p_mixing_bar, p.V_loss
            cavitating[i, j], buildable[i, j] = p.cavitating, p.buildable
    return AreaGapMap(net.nozzle_area * area_factors, gaps, p_feed, p_mixing, v_loss, cavitating, buildable,
                      net.nozzle_area, net.d_diff, flow_lpm, (net.p_vapour - net.p_ambient) / 1e5)


def in_band(m: AreaGapMap, band=PAPER_BAR) -> np.ndarray:
    """Mask [gap, area] of the map's points with the feed in band (bar gauge) and the ejector drawing (V_loss < 0)."""
    return m.buildable & (m.p_feed_bar >= band[0]) & (m.p_feed_bar <= band[1]) & (m.V_loss < 0.0)


def flow_for(net: DrillNetwork, target_bar: float, low: float = 5.0, high: float = 200.0) -> float:
    """The feed flow (l/min) at which net's feed is at target_bar (bar gauge), in [low, high]; NaN when not there."""
    def miss(q):
        return solve_point(net, q).p_feed_bar - target_bar

    try:
        return brentq(miss, low, high, xtol=1e-6)
    except ValueError:
        return math.nan
