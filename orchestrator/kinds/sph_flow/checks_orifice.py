"""The SPH verification check of a jet: a sharp-edged slot (2D) across a channel, fed by a velocity inlet, its
discharge coefficient from the pressure difference over the plate against inviscid free-streamline theory (see
checks.py for the row format).

The scene names its parts: the fluid block `slot` spans the opening (its width b along x), the one inlet feeds the
channel across its width B (2 half_extents[0]) at the speed V, and the probes `upstream` (in the approach flow) and
`corner*` (in the still water beside the jet, just behind the plate) give the pressure difference dp over the
second half of the run. C_d = V B / (b sqrt(2 dp / rho)) is compared with Cc / sqrt(1 - (Cc b/B)^2), Cc of
von Mises (1917) (reference/hydraulics.py).
"""

from __future__ import annotations

import math

import numpy as np

from orchestrator.errors import OrchestratorError
from orchestrator.kinds.sph_flow.checks_base import check_row, one_material, tolerance_of
from orchestrator.reference.hydraulics import slot_contraction_coefficient, slot_discharge_coefficient


def _slot_parts(case):
    """(b m, B m, V m/s, upstream probe, corner probes) of a slot scene; OrchestratorError naming what is missing."""
    name = case.case.name
    slots = [block for block in case.blocks if block.name == "slot" and block.kind == "fluid"]
    if case.dimension != 2 or len(slots) != 1 or len(case.inlets) != 1 or case.inlets[0].half_extents is None:
        raise OrchestratorError(f"{name}: check 'slot_orifice' needs a 2D scene with one fluid block named 'slot' "
                                "(the opening) and one inlet across the channel (half_extents)")
    probes = [p.name for p in case.output.probes]
    corners = [p for p in probes if p.startswith("corner")]
    if "upstream" not in probes or not corners:
        raise OrchestratorError(f"{name}: check 'slot_orifice' needs the output.probes 'upstream' and 'corner...' "
                                f"(behind the plate); the case has {probes}")
    inlet = case.inlets[0]
    return slots[0].hi[0] - slots[0].lo[0], 2.0 * inlet.half_extents[0], inlet.velocity, "upstream", corners


def check_slot_orifice(case, run) -> tuple[list[dict], dict]:
    """The slot's discharge coefficient over the second half of the run against von Mises' free streamlines."""
    name = case.case.name
    b, width, speed, upstream, corners = _slot_parts(case)
    rho = one_material(case, "slot_orifice").rho0
    series = run.get("series", {})
    t = np.asarray(series.get("time", []), dtype=float)
    beta = b / width
    expected = slot_discharge_coefficient(beta)
    source = "von Mises 1917 (free streamlines, Cc of a slot in a channel)"
    tolerance = tolerance_of(case, "discharge_coefficient")
    if not len(t):
        return [check_row(name, "discharge_coefficient", None, expected, None, tolerance, passed=False, source=source,
                          note="discharge_coefficient: the run recorded no series")], {}
    late = t >= 0.5 * t[-1]
    dp_t = np.asarray(series[f"pressure_probe_{upstream}"], dtype=float) - np.mean(
        [np.asarray(series[f"pressure_probe_{c}"], dtype=float) for c in corners], axis=0)
    dp = float(np.mean(dp_t[late]))
    flow = speed * width
    value = flow / (b * math.sqrt(2.0 * dp / rho)) if dp > 0 else math.nan
    rel = abs(value - expected) / expected if math.isfinite(value) else math.inf
    ok = run["attrs"].get("status") == "ok"
    cc = slot_contraction_coefficient(beta)
    row = check_row(name, "discharge_coefficient", value, expected, rel, tolerance,
                    passed=ok and tolerance is not None and rel <= tolerance, source=source,
                    note=f"discharge_coefficient: Q / (b sqrt(2 dp / rho)), Q = {flow:.4g} m^2/s, b/B = {beta:.4g}, dp "
                         f"= {dp:.4g} Pa (upstream - corners, mean over t >= {0.5 * t[-1]:.3g} s); expected "
                         f"Cc / sqrt(1 - (Cc b/B)^2), Cc = {cc:.4f}")
    dp_expected = 0.5 * rho * (flow / (expected * b)) ** 2
    plot = {"title": f"{name}: pressure over the plate", "xlabel": "t, s", "ylabel": "dp, Pa",
            "lines": [(t, dp_t, "-", "k", "SPH: upstream - corners"),
                      (t[[0, -1]], [dp_expected] * 2, "--", "C3", "free streamlines (von Mises)")]}
    return [row], plot
