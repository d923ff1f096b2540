"""A Johnson-Cook solid of an sph_flow scene mapped onto LAMMPS MACHDYN (Smooth Mach Dynamics, Ganzenmueller 2015:
total-Lagrangian SPH, `pair_style smd/tlsph`), in one place for every solid kind that runs on LAMMPS (the Taylor bar,
the crater). SI units.

- particles: the sph scene's lattice (atom_style smd: volume dx^3, mass rho0 dx^3); the kernel radius is our h, so a
  pair's support r_i + r_j is our 2h (MACHDYN's spiky kernel in place of ours);
- elasticity: E = 9KG / (3K + G), nu = (3K - 2G) / (2 (3K + G)) from the case's G and K (K = rho0 C0^2 for
  Mie-Grueneisen);
- equation of state: `*EOS_LINEAR` (the pressure rate K tr D) for eos = "linear"; `*EOS_SHOCK C0 S Gamma0` for
  "mie_gruneisen": MACHDYN's p = rho0 C0^2 mu (1 + mu) / (1 - (S - 1) mu)^2 + rho Gamma0 e in compression and
  tension alike, where ours has (1 + (1 - Gamma0/2) mu) in the numerator, rho0 in the energy term and K mu in tension
  (the two differ at second order in mu: under 0.1 % of p at the 2 % compression of an impact);
- `*JOHNSON_COOK A B n C epsdot_0 T0 Tm m`: MACHDYN's yield stress is (A + B eps_p^n)(1 + C ln(epsdot* >= 1)) with the
  rate form 'log' only, and epsdot_p a running mean over 1000 r / c_L; its thermal factor (1 - T*^m) is switched off in
  LAMMPS's source (T0, Tm, m and C_p are passed and unused), so the solid stays at room temperature and
  heat_fraction has no effect; an elastic solid (no yield_stress) is `*STRENGTH_LINEAR`;
- Monaghan's artificial viscosity: MACHDYN writes mu_ab with the pair's support 2h where ours has h, so Q1 = alpha / 2
  and Q2 = beta / 4 give the same Pi_ab (MACHDYN also caps v_ab . r_ab / r_ab at 0.01 c_L);
- MACHDYN's hourglass control (HOURGLASS, which our SPH does not have) and no artificial stress (a total-Lagrangian
  kernel has no tensile instability);
- a fixed step: the sph engine's step at rest (SphScene.timestep, 1/8 of MACHDYN's own bound 2 r / c_L), shortened so
  that a whole number of steps per frame ends at simulation.duration.
"""

from __future__ import annotations

import math

from orchestrator.errors import OrchestratorError

#: MACHDYN's hourglass control coefficient (the amplitude of its pair hourglass force; LAMMPS's examples use 10).
HOURGLASS = 10.0


def finite(name: str, value) -> float:
    """value as a finite float; OrchestratorError naming it otherwise (no text of the case reaches the deck)."""
    number = float(value)
    if not math.isfinite(number):
        raise OrchestratorError(f"{name} = {value!r} is not a finite number")
    return number


def solid_material(scene):
    """The scene's first material (the solid of a Taylor bar or a crater's target: density, solid)."""
    return scene.case.materials[0]


def refusal(solid, eos: tuple[str, ...] = ("linear",), elastic: bool = False) -> str:
    """Why MACHDYN cannot run this solid ('' when it can): the material models it does not have. eos: the equations
    of state the caller's deck writes; elastic: True when the deck takes a solid without yield_stress."""
    reasons = {
        f"the equation of state {solid.eos!r} (the deck writes {' or '.join(eos)})": solid.eos not in eos,
        "an elastic solid (no yield_stress)": solid.yield_stress is None and not elastic,
        f"the rate form {solid.rate_form or 'power'!r} (MACHDYN's Johnson-Cook has 1 + C ln(epsdot*) only: "
        "rate_form = 'log')": (solid.rate_form or "power") != "log" and bool(solid.rate_sensitivity),
        "Johnson-Cook failure (material.solid.failure)": solid.failure is not None,
    }
    return "; ".join(text for text, applies in reasons.items() if applies)


def deviations(solid) -> str:
    """What MACHDYN runs differently from what the case asks for this solid."""
    notes = []
    if solid.yield_stress is not None:
        notes.append("no thermal softening (MACHDYN's Johnson-Cook leaves out 1 - T*^m) and no temperature")
    if solid.heat_fraction:
        notes.append(f"heat_fraction = {solid.heat_fraction:g} unused")
    if solid.artificial_stress is not None:
        notes.append("no artificial stress (total-Lagrangian SPH)")
    if solid.eos == "mie_gruneisen":
        notes.append("MACHDYN's shock EOS (numerator 1 + mu, rho Gamma0 e, no tension branch)")
    notes.append(f"MACHDYN's hourglass control {HOURGLASS:g}")
    return "; ".join(notes)


def elastic_constants(solid, density: float) -> tuple[float, float]:
    """(E Pa, nu -) of the solid's G and its reference-state K (kg/m^3 density for K = rho0 C0^2)."""
    shear, bulk = finite("shear_modulus", solid.shear_modulus), finite("bulk_modulus", solid.bulk(density))
    return 9.0 * bulk * shear / (3.0 * bulk + shear), (3.0 * bulk - 2.0 * shear) / (2.0 * (3.0 * bulk + shear))


def machdyn_parameters(scene) -> dict[str, float]:
    """The solid's MACHDYN material (SI): rho0, E, nu, Q1, Q2, hg, Cp of *COMMON; with a yield stress also A, B, n,
    C, epsdot0, T0, Tm, m of *JOHNSON_COOK (the case's defaults where a key is left out: B 0, n 1, C 0, epsdot_0 1,
    T0 293, m 1)."""
    m = scene.case.materials[0]
    solid = m.solid
    young, poisson = elastic_constants(solid, m.density)
    av = scene.case.physics.artificial_viscosity
    values = {
        "rho0": m.density, "E": young, "nu": poisson, "Q1": av.alpha / 2.0, "Q2": av.beta / 4.0, "hg": HOURGLASS,
        "Cp": solid.heat_capacity if solid.heat_capacity is not None else 1.0,
    }
    if solid.yield_stress is not None:
        t0 = solid.room_temperature if solid.room_temperature is not None else 293.0
        values.update({
            "A": solid.yield_stress, "B": solid.hardening_modulus or 0.0,
            "n": solid.hardening_exponent if solid.hardening_exponent is not None else 1.0,
            "C": solid.rate_sensitivity or 0.0,
            "epsdot0": solid.reference_rate if solid.reference_rate is not None else 1.0,
            "T0": t0, "Tm": solid.melting_temperature if solid.melting_temperature is not None else 2.0 * t0,
            "m": solid.thermal_exponent if solid.thermal_exponent is not None else 1.0,
        })
    return {name: finite(name, value) for name, value in values.items()}


def material_cards(scene) -> list[str]:
    """The keyword blocks of the solid's `pair_coeff ... smd/tlsph` line after *COMMON: its equation of state and
    its strength, numbers as repr (e.g. ['*EOS_SHOCK 4578.0 1.33 1.67', '*JOHNSON_COOK 688170000.0 ...'])."""
    solid = scene.case.materials[0].solid
    p = machdyn_parameters(scene)
    if solid.eos == "mie_gruneisen":
        shock = [finite(k, getattr(solid, k)) for k in ("bulk_sound_speed", "hugoniot_slope", "gruneisen")]
        cards = ["*EOS_SHOCK " + " ".join(repr(v) for v in shock)]
    else:
        cards = ["*EOS_LINEAR"]
    if solid.yield_stress is None:
        return cards + ["*STRENGTH_LINEAR"]
    keys = ("A", "B", "n", "C", "epsdot0", "T0", "Tm", "m")
    return cards + ["*JOHNSON_COOK " + " ".join(repr(p[k]) for k in keys)]


def run_steps(scene) -> tuple[int, float, int]:
    """(steps, dt s, steps per frame): a whole number of steps per frame, dt at most the sph step at rest."""
    duration = finite("simulation.duration", scene.case.simulation.duration)
    frames = max(1, round(duration / scene.case.output.frame_interval))
    per_frame = max(1, math.ceil(duration / (frames * scene.timestep) - 1e-9))
    steps = per_frame * frames
    return steps, duration / steps, per_frame
