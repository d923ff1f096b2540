"""What the SPH verification checks share: the tolerances (from the scene's [[expected]] rows), units, the row format
and access to run.h5's frames."""

from __future__ import annotations

import math

import numpy as np

from orchestrator.errors import OrchestratorError
from orchestrator.kinds.sph_flow.case_materials import RunMaterial, run_materials

ENGINE = "sph"


#: Times of the velocity profiles compared with the series (s), besides the run's end.
PROFILE_TIMES = (0.02, 0.04, 0.1, 0.2)


PRESSURE_AVERAGE_S = 0.5  # the probe pressures are averaged over the run's last 0.5 s


#: Surge-front series compared (dam_break_data names): the two large columns. Martin & Moyce's 1.125 in
#: column (28.6 mm) is drawn but not checked: its front runs 2 % behind their 2.25 in column at the
#: same T (viscosity and surface tension, which the model leaves out, weigh more in the small column).
FRONT_DATASETS = ("koshizuka_oka_1996", "martin_moyce_1952_a2.25in")


#: Units of the quantities in the table.
UNITS = {"u_profile": "m/s", "pressure_profile": "Pa", "particle_pressure": "Pa", "spurious_speed": "m/s",
         "simulated_time": "s", "surge_front_Z": "-", "floor_force": "N", "eq14_wall_force": "N",
         "plane_force": "N", "min_distance_to_wall": "m", "slide_distance": "m", "distance_to_plane": "m",
         "pressure_gradient": "Pa/m", "mass_balance": "-", "density_drift": "-",
         "centreline_velocity": "m/s", "terminal_speed": "m/s", "rotation_rate": "rad/s", "centre_velocity": "m/s",
         "restitution": "-", "momentum_change": "-", "tangential_change": "-", "layer_stress": "Pa",
         "layer_rows": "Pa", "water_pressure": "Pa", "discharge_coefficient": "-"}


def tolerance_of(case, quantity: str) -> float | None:
    """The tolerance the scene's [[expected]] rows give the quantity (None when it has none), -."""
    return next((row.tolerance for row in case.expected if row.quantity == quantity), None)


def base_quantity(quantity: str) -> str:
    """'u_profile(t=0.1 s)' -> 'u_profile', 'surge_front_Z[koshizuka_oka_1996]' -> 'surge_front_Z'."""
    return quantity.split("(")[0].split("[")[0]


def check_row(scene, quantity, value, expected, rel_error, tolerance, passed=None, note="", source=""):
    if passed is None:
        passed = rel_error is not None and tolerance is not None and math.isfinite(rel_error) and rel_error <= tolerance
    return {"scene": scene, "engine": ENGINE, "quantity": quantity, "value": _float(value),
            "expected": _float(expected), "rel_error": _float(rel_error),
            "tolerance": _float(tolerance), "passed": bool(passed), "source": source, "note": note}


def _float(value):
    return None if value is None else float(value)


def relative(value, expected) -> float:
    return abs(value - expected) / abs(expected) if expected else math.inf


# ---------------------------------------------------------------------------------------------- run.h5 access
def frames_of(run) -> list[tuple[float, dict]]:
    """(time s, arrays) of every frame, in time order."""
    frames = run.get("frames", {})
    keys = sorted((k for k in frames if k != "attrs"), key=int)
    return [(float(frames[k]["attrs"]["time"]), frames[k]) for k in keys]


def frame_at(frames, t: float):
    """The frame recorded nearest to t (s)."""
    return min(frames, key=lambda item: abs(item[0] - t))


def fluid_mask(frame) -> np.ndarray:
    return np.asarray(frame["kind"]) == 0


def body_force_of(case) -> np.ndarray:
    return np.asarray(case.physics.body_force, dtype=float)


def block_of(case, kind: str, index: int = 0):
    return [b for b in case.blocks if b.kind == kind][index]


def one_material(case, check: str) -> RunMaterial:
    """The one fluid of a one-material scene ([fluid], or a single [[materials]] table); OrchestratorError
    naming the check when the scene has several."""
    materials = run_materials(case)
    if len(materials) != 1:
        raise OrchestratorError(f"{case.case.name}: check {check!r} compares one fluid but the case has "
                                f"{len(materials)} [[materials]]; use a two-layer check or one material")
    return materials[0]
