"""The cantilever plate's verification rows (`verify solids`): the period (run.h5 /measured) against thin-plate
theory (rel_error the relative difference) and the clumping: the smallest distance between two plate particles over
the run, over dx, against the lattice's 1 (rel_error = 1 - it)."""

from __future__ import annotations

import math

from orchestrator.kinds.cantilever_plate.analysis import QUANTITIES
from orchestrator.kinds.cantilever_plate.theory import plate_theory
from orchestrator.kinds.sph_flow.checks_base import check_row, relative

#: Units of the checked quantities in the table.
UNITS = {**{name: unit for name, (unit, _) in QUANTITIES.items()}, "clumping": "-"}


def check_run(case, engine: str, run: dict) -> tuple[list[dict], dict]:
    """The plate's rows (one per [[expected]] row; a quantity the run did not measure fails); no picture data (the
    solids suite's picture is the Taylor bar's)."""
    measured = run.get("measured", {}).get("attrs", {}) if run else {}
    name = case.case.name
    theory = plate_theory(case)
    rows = []
    for row in case.expected:
        if row.quantity == "period":
            value = measured.get("period")
            source = (f"thin-plate theory, omega^2 = E H^2 k^4 / (12 rho (1 - nu^2)), kL = 1.8751, L from the "
                      f"clamp's face: {theory['period']:.6g} s")
            note = (f"period from {measured.get('crossings', 0):.0f} zero crossings of the tip's displacement; "
                    "rel_error = |T - T_theory| / T_theory")
            expected = theory["period"]
            error = relative(value, expected) if _known(value) else None
        else:
            value = measured.get("min_distance")
            source = "the initial lattice: nearest neighbours at dx"
            note = ("clumping: the smallest distance between two plate particles over the run, over dx; rel_error = "
                    "1 - it (tensile clumping pulls pairs together)")
            expected = 1.0
            error = max(0.0, 1.0 - value) if _known(value) else None
        if error is None:
            rows.append(check_row(name, row.quantity, None, expected, None, row.tolerance, passed=False,
                                  source=source, note=f"{row.quantity}: not measured (the run ended early?)"))
            continue
        rows.append(check_row(name, row.quantity, value, expected, error, row.tolerance, source=source, note=note))
    return rows, {}


def _known(value) -> bool:
    return value is not None and math.isfinite(value)
