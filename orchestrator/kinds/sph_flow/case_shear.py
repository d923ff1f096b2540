"""Lees-Edwards boundaries of an SPH flow case (kind "sph_flow"): a periodic cell sheared along x (axis 0) with
the gradient along y (axis 1), whose images across y are shifted by gamma(t) L_y and move at gamma_dot(t) L_y
(engines/sph/README.md, "Lees-Edwards boundaries", eqs. LE1-LE2). Steady shear or oscillatory strain:

    [lees_edwards]
    shear_rate = 1.0              # 1/s: gamma(t) = shear_rate t

    [lees_edwards]
    amplitude = 5.0e-4            # gamma_A, -
    omega = 6.283                 # rad/s: gamma(t) = gamma_A sin(omega t)
"""

from __future__ import annotations

import math

from pydantic import Field, model_validator

from orchestrator.case.common import Frozen, Positive
from orchestrator.kinds.sph_flow.case_parts import Finite


class LeesEdwards(Frozen):
    """Lees-Edwards shear of the periodic box: steady (shear_rate) or oscillatory (amplitude and omega)."""

    shear_rate: Finite | None = Field(None, description="steady shear rate gamma_dot, 1/s")
    amplitude: Finite | None = Field(None, description="strain amplitude gamma_A of gamma_A sin(omega t), -")
    omega: Positive | None = Field(None, description="angular frequency omega of the oscillation, rad/s")
    subtract_mean_stress: bool = Field(False, description="the momentum equation takes the extra stress minus the "
                                       "cell's volume mean (a uniform stress moves nothing in the periodic cell; "
                                       "engines/sph/README.md)")

    @model_validator(mode="after")
    def _steady_or_oscillatory(self):
        steady, oscillatory = self.shear_rate is not None, self.amplitude is not None or self.omega is not None
        if steady == oscillatory:
            raise ValueError("lees_edwards takes either shear_rate (steady, 1/s) or amplitude and omega "
                             "(oscillatory gamma_A sin(omega t), -, rad/s), not both and not neither")
        if oscillatory and (self.amplitude is None or self.omega is None):
            missing = "amplitude" if self.amplitude is None else "omega"
            raise ValueError(f"lees_edwards.{missing} is missing; an oscillatory shear needs amplitude and omega")
        return self

    @property
    def peak_rate(self) -> float:
        """Largest |gamma_dot(t)|, 1/s."""
        return abs(self.shear_rate) if self.shear_rate is not None else abs(self.amplitude) * self.omega

    def deck(self) -> dict:
        """The deck's lees_edwards object."""
        deck = {"shear_rate": float(self.shear_rate)} if self.shear_rate is not None else \
            {"amplitude": float(self.amplitude), "omega": float(self.omega)}
        return {**deck, "subtract_mean_stress": True} if self.subtract_mean_stress else deck


def check_lees_edwards(case) -> None:
    """The Lees-Edwards cell against the domain, blocks and fluid speed; ValueError naming the key."""
    le = case.lees_edwards
    if le is None:
        return
    for axis in (0, 1):
        if axis not in case.domain.periodic:
            raise ValueError(f"lees_edwards shears along x with the gradient along y: domain.periodic must list "
                             f"axes 0 and 1 (it lists {list(case.domain.periodic)})")
    boundary = [b.name for b in case.blocks if b.kind == "boundary"]
    if boundary or case.walls or case.inlets or case.outlets:
        what = f"boundary block {boundary[0]!r}" if boundary else "walls, inlets or outlets"
        raise ValueError(f"lees_edwards: the sheared cell takes fluid particles only; the case has {what}")
    length = case.domain.hi[0] - case.domain.lo[0]
    if length < 2.2 * case.numerics.h * (1 - 1e-12):
        raise ValueError(f"lees_edwards: the box along x ({length:g} m) must be at least 2.2 h = "
                         f"{2.2 * case.numerics.h:g} m long")
    edge = 0.5 * le.peak_rate * (case.domain.hi[1] - case.domain.lo[1])
    if edge > case.fluid.max_speed * (1 + 1e-12) or not math.isfinite(edge):
        raise ValueError(f"lees_edwards: the cell's edges move at up to gamma_dot L_y / 2 = {edge:g} m/s, above "
                         f"fluid.max_speed = {case.fluid.max_speed:g} m/s; raise max_speed (c0 >= 10 max_speed)")
