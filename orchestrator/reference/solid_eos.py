"""Equations of state of solids: Mie-Grueneisen on the Hugoniot reference, and a linear one for checks.

Compression mu = rho / rho0 - 1 (-): positive when compressed. Pressure p (Pa) is positive in compression; the
Cauchy stress is sigma = -p I + s with s the deviatoric stress.

Mie-Grueneisen, Hugoniot reference (the linear shock-velocity fit U_s = C0 + S u_p), with Gamma rho = Gamma0 rho0:

    mu >= 0:  p = rho0 C0^2 mu [1 + (1 - Gamma0 / 2) mu] / [1 - (S - 1) mu]^2 + Gamma0 rho0 e
    mu <  0:  p = rho0 C0^2 mu + Gamma0 rho0 e

e is the specific internal energy (J/kg) above the reference state. The compressed branch is p_H + Gamma0 rho0 (e -
e_H) written out with the Hugoniot's p_H = rho0 C0^2 mu (1 + mu) / [1 - (S - 1) mu]^2 and e_H = p_H mu / (2 rho0 (1 +
mu)); the expanded branch is its first-order term (the usual form in tension, where no Hugoniot exists). Both
branches meet at mu = 0 with slope dp/dmu = rho0 C0^2, the bulk modulus of the reference state.

Linear: p = K mu, K the bulk modulus (Pa).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from orchestrator.errors import OrchestratorError


def _require_positive(**values: float) -> None:
    for name, value in values.items():
        if not (math.isfinite(value) and value > 0.0):
            raise OrchestratorError(f"{name} = {value}: must be a finite number above 0")


def compression(rho: float, rho0: float) -> float:
    """mu = rho / rho0 - 1 (-): density rho and reference density rho0 in kg/m^3."""
    return rho / rho0 - 1.0


@dataclass(frozen=True)
class LinearEos:
    """p = K mu: reference density rho0 (kg/m^3) and bulk modulus K (Pa)."""

    rho0: float
    bulk_modulus: float

    def __post_init__(self):
        _require_positive(rho0=self.rho0, bulk_modulus=self.bulk_modulus)

    def pressure(self, rho: float, specific_energy: float = 0.0) -> float:
        """Pressure (Pa) at density rho (kg/m^3); the specific energy (J/kg) does not enter."""
        return self.bulk_modulus * compression(rho, self.rho0)

    @property
    def reference_bulk_modulus(self) -> float:
        """dp/dmu at mu = 0, Pa."""
        return self.bulk_modulus


@dataclass(frozen=True)
class MieGruneisen:
    """Mie-Grueneisen EOS: reference density rho0 (kg/m^3), bulk sound speed C0 (m/s), Hugoniot slope S (-) of U_s =
    C0 + S u_p, Grueneisen parameter Gamma0 (-) of the reference state."""

    rho0: float
    c0: float
    s: float
    gamma0: float

    def __post_init__(self):
        _require_positive(rho0=self.rho0, c0=self.c0)
        if not (math.isfinite(self.s) and self.s >= 0.0 and math.isfinite(self.gamma0) and self.gamma0 >= 0.0):
            raise OrchestratorError(f"s = {self.s}, gamma0 = {self.gamma0}: must be finite numbers >= 0")

    @property
    def reference_bulk_modulus(self) -> float:
        """rho0 C0^2 = dp/dmu at mu = 0, Pa."""
        return self.rho0 * self.c0 * self.c0

    @property
    def limiting_compression(self) -> float:
        """mu at which the compressed branch's denominator 1 - (S - 1) mu vanishes (inf when S <= 1), -."""
        return math.inf if self.s <= 1.0 else 1.0 / (self.s - 1.0)

    def pressure(self, rho: float, specific_energy: float = 0.0) -> float:
        """Pressure (Pa) at density rho (kg/m^3) and specific internal energy e (J/kg)."""
        mu = compression(rho, self.rho0)
        thermal = self.gamma0 * self.rho0 * specific_energy
        if mu < 0.0:
            return self.reference_bulk_modulus * mu + thermal
        if mu >= self.limiting_compression:
            raise OrchestratorError(f"compression mu = {mu:.4g} is beyond the Hugoniot's limit "
                                    f"1 / (S - 1) = {self.limiting_compression:.4g}")
        denominator = 1.0 - (self.s - 1.0) * mu
        return (self.reference_bulk_modulus * mu * (1.0 + (1.0 - 0.5 * self.gamma0) * mu) / (denominator * denominator)
                + thermal)

    def hugoniot(self, particle_velocity: float) -> tuple[float, float, float]:
        """The shocked state behind a shock of particle velocity u_p (m/s, >= 0) into material at rest:
        (density kg/m^3, pressure Pa, specific internal energy J/kg) from the jump conditions with U_s = C0 + S u_p:
        rho = rho0 U_s / (U_s - u_p), p = rho0 U_s u_p, e = u_p^2 / 2."""
        shock_velocity = self.c0 + self.s * particle_velocity
        rho = self.rho0 * shock_velocity / (shock_velocity - particle_velocity)
        return rho, self.rho0 * shock_velocity * particle_velocity, 0.5 * particle_velocity * particle_velocity
