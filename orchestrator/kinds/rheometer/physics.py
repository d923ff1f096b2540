"""Mass scaling, sound speed and time step of the rheometer's sample (SI units).

The slowest modes of a paste relax in seconds while an explicit step of its viscous, elastic modes is a
microsecond at the material's density. The moduli of a linear material in a quasi-static sample do not depend on
its density, so the density is chosen per frequency:

    criterion (numerics.quasi_static = N): the shear wave crosses the sample within 1/N of the period T = 2 pi/omega,
        L / c_s = T / N  with  c_s = sqrt(|G*(omega)| / rho)   =>   rho = |G*(omega)| (T / (N L))^2

(|G*| = sqrt(G'^2 + G''^2) of the modes and the solvent at omega, eqs. 18-19; steady shear takes omega = |gamma_dot|).
Inertia then enters the sample's response as (omega L / c_s)^2 = (2 pi / N)^2 (0.1 at N = 20), and the moduli must
not change when N grows (docs/rheometry.md shows N = 20, 40, 80).

The sound speed is sound_speed_ratio times the fastest shear wave, sqrt(max(G_0, |G*|) / rho) with G_0 = sum G_i
(the modes' instantaneous modulus), and at least 10 x the cell's edge speed (weakly compressible SPH). The step is
the smallest of cfl h / c0, relaxation_factor x the shortest relaxation time (the explicit stress update) and,
with a solvent, viscous_factor h^2 rho / eta_s (eta_s + eta_0 with a Cross law: its largest viscosity).

Rest pressure (numerics.rest_pressure_ratio = r): the pressure at the reference density is P0 = r max(G_0, |G*|)
(the EOS is shifted by p_B so that p(rho0) = P0). The sph executable's tensor path (eqs. T1-T2) has a zero-energy
mode: rows of particles moving alternately +u and -u along x leave the kernel-corrected velocity gradient, hence
the stress, unchanged, and nothing in a PTT Lees-Edwards cell damps it. With P0 = 0 it grows from round-off and
the UCM moduli of ucm_one_mode.toml come out 1.7 % off; a uniform pressure gives the particle lattice a shear
stiffness of order P0 that holds the mode down (P0 = G_0: 0.1 %, 10 G_0: 0.01 %).

Steady shear (docs/rheometry.md, "Steady shear"). The first normal stress difference grows as Wi^2 at small epsilon
(N1 = 2 G Wi^2 / f^2) and passes the rest pressure: the sample's stress turns tensile along the flow and the lattice
clumps (the tensile instability of SPH). A higher rest pressure does not help (a pressure of 30 G_0 or more stirs
the sliding lattice), neither do a higher sound speed or a shorter step (measured). So a steady run (1) subtracts
the sample's mean extra stress in the momentum equation (numerics.subtract_mean_stress: a uniform stress moves
nothing in the periodic cell, the stress itself is unchanged), (2) damps the rows' velocity modes with a Morris
viscosity of numerics.damping_viscosity_ratio x the modes' expected shear viscosity sum eta_i / f_i (with the
material's solvent viscosity it is the Morris term's; in homogeneous shear its stress is eta gamma_dot exactly,
so the measured viscosity adds the material's solvent viscosity and leaves the damping out) and (3) diffuses the
mode stresses with kappa = numerics.stress_diffusion_ratio x h^2 |gamma_dot| (the engine's eq. SD1; zero for the
uniform stress of homogeneous shear). Without (2) and (3) a slow mode of the sliding lattice (rows turning wavy,
the stress following them) grows by 0.13-0.15 per unit strain at Wi = 5 and 20 and ends any run after about 200
strain units; (3) alone leaves a mode of the rows' x velocities (period three rows) growing at 0.14, (2) at 10 %
alone slows the first to 0.09; both together hold it to round-off (docs/rheometry.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class SampleNumerics:
    """What the criteria give: density rho kg/m^3, sound speed c0 m/s, time step dt s, the limit that sets dt,
    the shear-wave speed c_s m/s at the shear's frequency and the largest speed of the cell's edges m/s."""

    density: float
    sound_speed: float
    dt: float
    dt_limit: str
    shear_wave_speed: float
    edge_speed: float
    rest_pressure: float
    morris_viscosity: float = 0.0
    subtract_mean_stress: bool = False
    stress_diffusion: float = 0.0


def sample_numerics(case) -> SampleNumerics:
    """Density, sound speed and step of a rheometer case (the criteria of this module)."""
    sample, material, shear, numerics = case.sample, case.material, case.shear, case.numerics
    omega = shear.omega if shear.oscillatory else abs(shear.shear_rate)
    modulus = abs(material.complex_modulus(omega))
    period = 2.0 * math.pi / omega
    rho = modulus * (period / (numerics.quasi_static * sample.size)) ** 2
    wave = math.sqrt(modulus / rho)
    fastest = math.sqrt(max(material.instantaneous_modulus, modulus) / rho)
    edge = 0.5 * shear.peak_rate * sample.size
    c0 = max(numerics.sound_speed_ratio * fastest, 10.0 * edge)
    h = sample.h_over_dx * sample.dx
    limits = {"cfl h / c0": numerics.cfl * h / c0,
              "relaxation": numerics.relaxation_factor * min(m.relaxation_time for m in material.modes)}
    morris = 0.0
    if not shear.oscillatory and numerics.damping_viscosity_ratio > 0.0:
        morris = material.solvent_viscosity + numerics.damping_viscosity_ratio * material.polymer_viscosity(omega)
    viscous = max(morris, float(material.solvent_shear_viscosity(0.0)))  # a Cross law is largest at rest (eta_0)
    if viscous > 0.0:
        limits["viscous (solvent)"] = numerics.viscous_factor * h * h * rho / viscous
    kappa = 0.0 if shear.oscillatory else numerics.stress_diffusion_ratio * h * h * abs(shear.shear_rate)
    if kappa > 0.0:
        limits["stress diffusion"] = numerics.viscous_factor * h * h / kappa
    which = min(limits, key=limits.get)
    dt = limits[which]
    # a whole number of steps per record: the series then samples the cycles evenly
    record = period / numerics.samples_per_cycle if shear.oscillatory else shear.duration / 200.0
    dt = record / math.ceil(record / dt * (1.0 - 1e-12))
    rest = numerics.rest_ratio(sample.arrangement, sample.dimension) * max(material.instantaneous_modulus, modulus)
    subtract = numerics.subtract_mean_stress and not shear.oscillatory
    return SampleNumerics(rho, c0, dt, which, wave, edge, rest, morris, subtract, kappa)
