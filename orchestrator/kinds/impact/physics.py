"""The physics of an impact case: material constants, the damping constant alpha of each contact pair, energies,
closing speeds and the time step. SI units.

The critical time step of an impact scene is the smaller of
- the Rayleigh step of the smallest sphere (waves through a sphere; what
  Yade and LIGGGHTS users scale), and
- the stability limit 2/omega_max of the stiffest Hertz contact at the
  fastest closing speed the scene can reach (omega_max from the tangent
  stiffness 3/2 k_n delta_max^(1/2) at the deepest overlap): 1.461
  delta_max / v, about half the Hertz contact duration.
The contact limit binds only in fast impacts: in every verification scene
the Rayleigh step is the smaller (by 1.4x for the glass spheres of Chung &
Ooi's test 1 up to 3.4x for the sphere drop); those glass spheres would need
about 60 m/s each. The default factor 0.05 gives 60 to 140 steps per contact
in the verification scenes, and at least 40 wherever the contact limit binds
(see the README's time-step study).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from orchestrator.case.common import rayleigh_timestep
from orchestrator.reference import closed_form, contact
from orchestrator.reference.closed_form import hertz_max_overlap
from orchestrator.reference.contact import effective_modulus

if TYPE_CHECKING:
    from orchestrator.kinds.impact.case import ImpactCase

#: The material name of the rigid wall (a plane of infinite E).
RIGID = "rigid"
#: g used when simulation.gravity is true, m/s^2 (along -z).
STANDARD_GRAVITY = 9.81
#: 2/omega_max of an undamped Hertz impact over delta_max / v: 2 / sqrt(15/8).
CONTACT_STABILITY_FACTOR = 2.0 / math.sqrt(15.0 / 8.0)


@dataclass(frozen=True)
class PairPhysics:
    """Elastic and damping constants of one material pair (for a sphere of radius 1 m; scale k by sqrt(R_eq)).

    effective_young: E_eq, Pa (eq. 3, E scaled by numerics.stiffness_scale; a rigid wall adds nothing);
    restitution: e_n of the case, -; friction: mu, -; alpha: Tsuji damping
    constant of eq. 9 under the case's model.damping (None for "engine").
    """

    materials: tuple[str, str]
    effective_young: float
    restitution: float
    tangential_restitution: float
    friction: float
    alpha: float | None


def young_modulus(case: ImpactCase, name: str) -> float:
    """E of a material, Pa, times numerics.stiffness_scale (inf for the rigid wall)."""
    if name == RIGID:
        return math.inf
    return case.materials[name].young_modulus * case.numerics.stiffness_scale


def poisson_ratio(case: ImpactCase, name: str) -> float:
    """nu of a material, - (0 for the rigid wall, where it has no effect)."""
    return 0.0 if name == RIGID else case.materials[name].poisson_ratio


def effective_young(case: ImpactCase, a: str, b: str) -> float:
    """E_eq of the pair (a, b), Pa (eq. 3)."""
    return float(effective_modulus(young_modulus(case, a), poisson_ratio(case, a),
                                   young_modulus(case, b), poisson_ratio(case, b)))


def damping_alpha_for(case: ImpactCase, restitution: float) -> float | None:
    """alpha of eq. 9, -, for a pair's e_n under model.damping (None for 'engine')."""
    if case.model.damping == "engine":
        return None
    if restitution >= 1.0:
        return 0.0
    if case.model.damping == "eq10":
        return float(contact.damping_alpha(restitution))
    return float(closed_form.alpha_from_restitution(restitution, True))


def pair_physics(case: ImpactCase) -> dict[tuple[str, str], PairPhysics]:
    """PairPhysics of every material pair that can touch, keyed by the sorted names."""
    out = {}
    for a, b in case.touching_pairs():
        pair = case.contact(a, b)
        out[(a, b)] = PairPhysics((a, b), effective_young(case, a, b), pair.restitution, pair.e_t, pair.friction,
                                  damping_alpha_for(case, pair.restitution))
    return out


def sphere_mass(case: ImpactCase, index: int) -> float:
    """Mass of spheres[index], kg."""
    sphere = case.spheres[index]
    return case.materials[sphere.material].density * 4.0 / 3.0 * math.pi * sphere.radius**3


def _sphere_energies(case: ImpactCase):
    """Per sphere: mass (kg), radius (m), kinetic energy incl. spin (J) and the potential energy of its
    fall onto the plane (J; zero without gravity or plane)."""
    masses = np.array([sphere_mass(case, i) for i in range(len(case.spheres))])
    velocities = np.array([s.velocity for s in case.spheres], float)
    spins = np.array([s.angular_velocity for s in case.spheres], float)
    radii = np.array([s.radius for s in case.spheres], float)
    kinetic = 0.5 * masses * (np.sum(velocities**2, axis=1) + 0.4 * radii**2 * np.sum(spins**2, axis=1))
    fall = np.zeros(len(masses))
    if case.plane is not None and case.simulation.gravity:
        normal = np.array(case.plane.unit_normal)
        heights = (np.array([s.position for s in case.spheres]) - np.array(case.plane.point)) @ normal - radii
        fall = masses * STANDARD_GRAVITY * np.maximum(heights, 0.0) * max(normal[2], 0.0)
    return masses, radii, kinetic, fall


def fastest_closing_speeds(case: ImpactCase) -> tuple[np.ndarray, float]:
    """Upper bounds of each sphere's speed against the wall (m/s, (n,)) and of any
    sphere-sphere closing speed (m/s) over the run.

    Against the wall: all kinetic energy of the scene plus the potential energy
    of a fall onto the plane, put into that one sphere. Between spheres gravity
    cancels (both fall alike), so only the kinetic energy counts.
    """
    masses, radii, kinetic, fall = _sphere_energies(case)
    wall_speed = np.sqrt(2.0 * (kinetic.sum() + fall.sum()) / masses)
    free_speed = np.sqrt(2.0 * kinetic.sum() / masses)
    if fall.sum() > 0.0:  # a sphere bouncing off the plane can meet one still falling
        free_speed = wall_speed
    pair_speed = 2.0 * float(free_speed.max()) if len(masses) > 1 else 0.0
    return wall_speed, pair_speed


def energy_scale(case: ImpactCase) -> float:
    """The energy the scene can release, J: kinetic energy plus the fall of every sphere onto the plane
    (plus a floor of 1e-6 m g R per sphere, so a pile at rest has a scale). Energy growth beyond a
    fraction of this marks an unstable run."""
    masses, radii, kinetic, fall = _sphere_energies(case)
    floor = 1e-6 * masses * STANDARD_GRAVITY * radii
    return float(kinetic.sum() + fall.sum() + floor.sum())


def contact_stability_step(effective_m, effective_rad, effective_young_modulus, speed) -> float:
    """2/omega_max of an undamped Hertz impact at `speed` (m/s), s: 1.461 delta_max / v (inf if speed is 0)."""
    if speed <= 0.0:
        return math.inf
    return CONTACT_STABILITY_FACTOR * float(hertz_max_overlap(effective_m, effective_rad, effective_young_modulus,
                                                              speed)) / speed


def critical_timestep(case: ImpactCase) -> float:
    """min(Rayleigh step of each sphere, contact stability step of every possible contact), s."""
    steps = []
    for sphere in case.spheres:
        steps.append(rayleigh_timestep(sphere.radius, case.materials[sphere.material], case.numerics.stiffness_scale))
    wall_speed, pair_speed = fastest_closing_speeds(case)
    masses = [sphere_mass(case, i) for i in range(len(case.spheres))]
    if case.plane is not None:
        for i, sphere in enumerate(case.spheres):
            e_eq = effective_young(case, sphere.material, case.plane.material)
            steps.append(contact_stability_step(masses[i], sphere.radius, e_eq, float(wall_speed[i])))
    if len(case.spheres) > 1:
        # the stiffest sphere-sphere contact: smallest m_eq and R_eq with the stiffest pair of materials
        radius = min(s.radius for s in case.spheres) / 2.0
        mass = min(masses) / 2.0
        kinds = {s.material for s in case.spheres}
        e_eq = max(effective_young(case, a, b) for a in kinds for b in kinds)
        steps.append(contact_stability_step(mass, radius, e_eq, pair_speed))
    return float(min(steps))


