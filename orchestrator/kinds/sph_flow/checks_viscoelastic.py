"""The SPH verification check of a viscoelastic channel flow: start-up of plane Poiseuille flow of an Oldroyd-B
fluid (a PTT material with epsilon = 0 and a solvent) against the Waters & King (1970) series
(reference/viscoelastic_flows.py). The scene: one fluid block between boundary blocks, periodic along x, driven
by a body force along x from rest. rel_error: the largest |u_c - u_WK| over the frames from lambda/5 on, divided
by the steady centre-line speed; u_c is the mean speed of the particle rows nearest the centre line."""

from __future__ import annotations

import numpy as np

from orchestrator.errors import OrchestratorError
from orchestrator.kinds.sph_flow.checks_base import block_of, body_force_of, check_row, fluid_mask, frames_of, \
    one_material, tolerance_of
from orchestrator.reference.viscoelastic_flows import (
    oldroyd_b_poiseuille_steady_velocity,
    waters_king_centreline_velocity,
    waters_king_startup_velocity,
)


def check_oldroyd_b_startup(case, run) -> tuple[list[dict], dict]:
    """Centre-line speed u(L/2, t) against Waters & King for t >= lambda/5."""
    material = one_material(case, "oldroyd_b_startup")
    if material.model != "ptt" or len(material.modes) != 1 or material.epsilon != 0.0:
        raise OrchestratorError(f"{case.case.name}: check 'oldroyd_b_startup' needs one ptt material of one mode "
                                "with epsilon = 0 (Oldroyd-B)")
    (lam, eta_p), eta_s = material.modes[0], material.solvent_viscosity
    fluid = block_of(case, "fluid")
    gap, g = fluid.hi[1] - fluid.lo[1], float(body_force_of(case)[0])
    params = dict(gap=gap, body_force=g, rho=material.rho0, eta_polymer=eta_p, eta_solvent=eta_s,
                  relaxation_time=lam)
    steady = float(oldroyd_b_poiseuille_steady_velocity(0.5 * gap, gap=gap, body_force=g, rho=material.rho0,
                                                        eta_polymer=eta_p, eta_solvent=eta_s))
    times, centre = [], []
    for t, frame in frames_of(run):
        mask = fluid_mask(frame)
        y = np.asarray(frame["positions"])[mask, 1] - fluid.lo[1]
        u = np.asarray(frame["velocities"])[mask, 0]
        near = np.abs(y - 0.5 * gap) <= np.min(np.abs(y - 0.5 * gap)) + 1e-9 * gap
        times.append(t)
        centre.append(float(np.mean(u[near])))
    times, centre = np.array(times), np.array(centre)
    # the two rows nearest the centre line sit at L/2 +- dx/2: the series at the same heights
    exact = np.mean([waters_king_startup_velocity(0.5 * gap + side * 0.5 * case.numerics.dx, times, **params)
                     for side in (-1.0, 1.0)], axis=0)
    late = times >= 0.2 * lam * (1 - 1e-9)
    name, tolerance = case.case.name, tolerance_of(case, "centreline_velocity")
    source = "Waters & King 1970 (reference/viscoelastic_flows.waters_king_startup_velocity)"
    if not late.any():
        rows = [check_row(name, "centreline_velocity", None, None, None, tolerance, passed=False,
                          note="centreline_velocity: no frames after lambda/5")]
    else:
        errors = np.abs(centre[late] - exact[late]) / steady
        worst = int(np.argmax(errors))
        rows = [check_row(name, f"centreline_velocity(t={times[late][worst]:.3g} s)", centre[late][worst],
                          exact[late][worst], float(errors[worst]), tolerance, source=source,
                          note=f"centreline_velocity: the worst of {int(late.sum())} frames from lambda/5 = "
                               f"{0.2 * lam:g} s; rel_error = |u_c - u_WK| / {steady:.3g} m/s (steady centre-line "
                               "speed); u_c: the two particle rows at L/2 +- dx/2, the series at the same heights")]
    line = np.linspace(0.0, times[-1] if len(times) else 1.0, 300)
    plot = {"title": f"{name}: centre-line speed", "xlabel": "t [s]", "ylabel": "u_c / u_steady",
            "lines": [(times, centre / steady, "o", "C0", "SPH"),
                      (line, waters_king_centreline_velocity(line, **params) / steady, "-", "k", "Waters & King")]}
    return rows, plot

