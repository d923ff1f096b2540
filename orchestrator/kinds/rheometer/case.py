"""The rheometer case (kind "rheometer"): a square (2D) or cubic (3D) sample of a multi-mode PTT fluid, periodic
in every direction and sheared along x with the gradient along y by Lees-Edwards boundaries; steady shear or
oscillatory strain gamma(t) = gamma_A sin(omega t) (Nutto et al., section 3: 1 cm x 1 cm in 2D,
10 x 10 particles, gamma_A = 0.05 %). SI units (m, kg, s, Pa).

[material] takes the key names `orchestrator calibrate maxwell` writes in its fragment ([material],
storage_plateau, [[material.modes]] relaxation_time, viscosity, [material.cross_loss]), so a fitted fragment
pastes in whole; the PTT keys (epsilon, solvent_viscosity, eos) are added beside them. The plateau G_p is an
upper-convected elastic stress (engines/sph/src/materials/ptt.h, eq. R2: G' gains G_p, G'' nothing), the Cross
law a solvent viscosity eta_C(gamma_dot) with the shear rate sqrt(2 D:D) of the flow (beside eta_s). Conventions: D = (grad v + grad v^T)/2 (the paper's eq. 5
has no 1/2; with it eta_i is a viscosity, lambda_i -> 0 gives a Newtonian fluid of viscosity eta_i), each mode
has its own f_i = 1 + (lambda_i epsilon / eta_i) tr tau_i.

The sample's density is not the material's: it is chosen per frequency (mass scaling, physics.py) so that the
shear wave crosses the sample within 1/numerics.quasi_static of the period; the moduli of a linear material
do not depend on it once the sample deforms quasi-statically.
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field, model_validator

from orchestrator.case.common import CaseMeta, Frozen, NonNegative, Positive
from orchestrator.kinds.sph_flow.case_materials import EQUATIONS_OF_STATE, MAX_MODES, CrossLoss, PttMode
from orchestrator.reference.viscoelastic_flows import ptt_f_in_shear

#: The comparisons a rheometer scene's [[expected]] rows can name, and the quantities each measures.
#: The rest pressure over max(G_0, |G*|) by lattice (physics.py): a hexagonal lattice takes any; a 2D square one
#: rearranges above about 2 (UCM at lambda omega = 10: G'' +1.0 % at 2, +5.3 % at 3, +43 % at 5, +0.02 % at 0.5).
#: The 3D cube keeps 10 (one UCM mode at lambda omega = 1: -0.10 % / +0.22 % at 10, -1.0 % / +1.1 % at 1).
HEXAGONAL_REST_RATIO, SQUARE_REST_RATIO = 10.0, 0.5

CHECK_QUANTITIES = {
    "saos_maxwell": ("storage_modulus", "loss_modulus"),
    "steady_ptt": ("shear_viscosity", "first_normal_stress_difference", "tau_yy_over_tau_xx"),
    "steady_viscosity": ("shear_viscosity",),
    "newtonian_cell": ("velocity_profile", "storage_over_loss", "loss_modulus"),
}


class Sample(Frozen):
    """The sheared sample: a square (2D) or cube (3D) of side `size` filled with particles^D particles."""

    dimension: Literal[2, 3] = Field(2, description="2 (the paper's) or 3")
    size: Positive = Field(description="side L of the sample, m (the paper's 1 cm)")
    particles: int = Field(ge=4, le=200, description="particles across the side, - (the paper's 10)")
    h_over_dx: float = Field(1.3, ge=1.0, le=3.0, description="smoothing length over spacing h/dx, -")
    lattice: Literal["square", "hexagonal"] | None = Field(None, description="default hexagonal in 2D, square in "
                                                    "3D. square: particles^D on a square lattice (the paper's; in 2D "
                                                    "it rearranges under a rest pressure above about 2 G, hence its "
                                                    "default numerics.rest_pressure_ratio of 0.5); hexagonal (2D): "
                                                    "rows of `particles` spaced dx, an even number of rows near "
                                                    "L / (dx sqrt(3)/2), odd rows shifted dx/2")

    @model_validator(mode="after")
    def _lattice_of_dimension(self):
        if self.lattice == "hexagonal" and self.dimension == 3:
            raise ValueError("sample.lattice = 'hexagonal' is 2D only; use 'square' in 3D (or leave it out)")
        return self

    @property
    def arrangement(self) -> str:
        """The lattice used: `lattice`, or hexagonal in 2D and square in 3D."""
        return self.lattice or ("hexagonal" if self.dimension == 2 else "square")

    @property
    def dx(self) -> float:
        """Particle spacing L / particles, m."""
        return self.size / self.particles


class RheometerMaterial(Frozen):
    """A multi-mode linear PTT fluid ([material] and its [[material.modes]])."""

    modes: tuple[PttMode, ...] = Field(min_length=1, max_length=MAX_MODES,
                                       description="the Maxwell modes: relaxation_time s, viscosity Pa s")
    epsilon: NonNegative = Field(0.0, description="PTT extensibility epsilon, - (0: Oldroyd-B / UCM)")
    solvent_viscosity: NonNegative = Field(0.0, description="solvent viscosity eta_s, Pa s")
    eos: str = Field("quadratic", description="equation of state: quadratic (Nutto et al. eq. 9, the paper's) or tait")
    storage_plateau: NonNegative = Field(0.0, description="plateau modulus G_p, Pa: an upper-convected elastic "
                                         "stress beside the modes (adds G_p to G'; at most 7 modes with it)")
    cross_loss: CrossLoss | None = Field(None, description="a Cross-law solvent viscosity beside eta_s: "
                                         "zero_shear_viscosity, infinite_shear_viscosity Pa s, time_constant s, "
                                         "exponent - (the table calibrate maxwell --cross writes)")

    @model_validator(mode="after")
    def _ptt_only(self):
        if self.eos not in EQUATIONS_OF_STATE:
            raise ValueError(f"material.eos = {self.eos!r}; allowed: {', '.join(EQUATIONS_OF_STATE)}")
        if self.storage_plateau > 0.0 and len(self.modes) > MAX_MODES - 1:
            raise ValueError(f"material.modes: {len(self.modes)} modes beside storage_plateau; allowed: 1 to "
                             f"{MAX_MODES - 1} (the plateau takes one of the engine's {MAX_MODES} stress columns)")
        return self

    def solvent_shear_viscosity(self, shear_rate):
        """eta_s + eta_C(gamma_dot) in Pa s at shear rates gamma_dot (1/s, scalar or array)."""
        cross = 0.0 if self.cross_loss is None else self.cross_loss.viscosity(shear_rate)
        return self.solvent_viscosity + cross

    def complex_modulus(self, omega: float) -> complex:
        """G*(omega) = G' + i G'' of the plateau, the modes and the solvent in the linear limit (eqs. 18-19 plus G_p
        and i (eta_s + eta_0) omega, eta_0 the Cross law's zero-shear viscosity), Pa; omega rad/s."""
        g = self.storage_plateau + 1j * float(self.solvent_shear_viscosity(0.0)) * omega
        for m in self.modes:
            x = omega * m.relaxation_time
            g += m.viscosity / m.relaxation_time * (x * x + 1j * x) / (1.0 + x * x)
        return g

    def polymer_viscosity(self, shear_rate: float) -> float:
        """sum eta_i / f_i of the modes in steady shear at shear_rate (1/s), Pa s (the closed form's)."""
        return sum(m.viscosity / float(ptt_f_in_shear(m.relaxation_time * shear_rate, self.epsilon))
                   for m in self.modes)

    @property
    def instantaneous_modulus(self) -> float:
        """G_0 = sum eta_i / lambda_i, Pa: the modulus of the fastest (elastic) shear waves."""
        return sum(m.viscosity / m.relaxation_time for m in self.modes)


class Shear(Frozen):
    """Steady shear (shear_rate, duration) or oscillatory strain gamma_A sin(omega t) over cycles."""

    shear_rate: float | None = Field(None, description="steady shear rate gamma_dot, 1/s")
    duration: Positive | None = Field(None, description="steady shear: run time, s")
    amplitude: Positive | None = Field(None, description="strain amplitude gamma_A, - (the paper's 5e-4)")
    omega: Positive | None = Field(None, description="angular frequency omega, rad/s")
    cycles: int = Field(2, ge=1, le=1000, description="oscillation: cycles fitted by eq. 17 after the start-up, -")
    startup_cycles: int = Field(2, ge=0, le=1000, description="oscillation: cycles run before the fit, -")

    @model_validator(mode="after")
    def _one_kind(self):
        steady = self.shear_rate is not None or self.duration is not None
        oscillatory = self.amplitude is not None or self.omega is not None
        if steady == oscillatory:
            raise ValueError("shear takes shear_rate and duration (steady) or amplitude and omega (oscillatory), "
                             "not both and not neither")
        for key, needed in (("shear_rate", steady), ("duration", steady), ("amplitude", oscillatory),
                            ("omega", oscillatory)):
            if needed and getattr(self, key) is None:
                raise ValueError(f"shear.{key} is missing; a {'steady' if steady else 'oscillatory'} shear needs it")
        if steady and self.shear_rate == 0.0:
            raise ValueError("shear.shear_rate = 0: give a non-zero shear rate, 1/s")
        given = self.given(("cycles", "startup_cycles"))
        if steady and given:
            raise ValueError(f"shear.{given[0]} counts oscillation cycles; a steady shear runs shear.duration: "
                             "remove it")
        return self

    @property
    def oscillatory(self) -> bool:
        """True for gamma_A sin(omega t), False for steady shear."""
        return self.omega is not None

    @property
    def time_scale(self) -> float:
        """The shear's time scale, s: the period 2 pi / omega, or 2 pi / |gamma_dot| for steady shear."""
        return 2.0 * math.pi / (self.omega if self.oscillatory else abs(self.shear_rate))

    @property
    def peak_rate(self) -> float:
        """Largest |gamma_dot(t)|, 1/s."""
        return self.amplitude * self.omega if self.oscillatory else abs(self.shear_rate)

    @property
    def duration_s(self) -> float:
        """Run time, s: (startup_cycles + cycles) periods, or the steady duration."""
        return (self.startup_cycles + self.cycles) * self.time_scale if self.oscillatory else self.duration


class RheometerNumerics(Frozen):
    """Mass scaling, sound speed and time step of the sample (physics.py states the criteria)."""

    quasi_static: Positive = Field(20.0, ge=2.0, description="N: the shear wave crosses the sample within 1/N of "
                                   "the period (steady: of 2 pi / gamma_dot); sets the density, -")
    sound_speed_ratio: Positive = Field(10.0, ge=3.0, description="c0 over the fastest shear-wave speed "
                                        "sqrt(max(G_0, |G*|) / rho), -")
    cfl: Positive = Field(0.1, le=1.0, description="dt <= cfl h / c0, -")
    relaxation_factor: Positive = Field(0.2, le=1.0, description="dt <= factor x the shortest relaxation time, -")
    viscous_factor: Positive = Field(0.125, le=1.0, description="dt <= factor h^2 rho / eta_s (solvent), -")
    samples_per_cycle: int = Field(64, ge=16, le=10_000, description="shear-stress records per period, -")
    frames_per_cycle: int = Field(4, ge=1, le=100, description="particle frames per period (steady shear: 8 "
                                  "frames over the run), -")
    rest_pressure_ratio: NonNegative | None = Field(None, description="pressure of the sample at its reference "
                                                    "density over max(G_0, |G*|), - (default 0.5 on a 2D square "
                                                    "lattice, else 10; physics.py: the lattice's "
                                                    "stiffness against the tensor path's zero-energy mode)")

    def rest_ratio(self, lattice: str, dimension: int) -> float:
        """rest_pressure_ratio, or its default for the sample's lattice: 0.5 on a 2D square lattice, else 10, -."""
        if self.rest_pressure_ratio is not None:
            return self.rest_pressure_ratio
        return SQUARE_REST_RATIO if lattice == "square" and dimension == 2 else HEXAGONAL_REST_RATIO
    threads: int = Field(1, ge=1, le=256, description="OpenMP threads of the engine")
    subtract_mean_stress: bool = Field(True, description="steady shear: the momentum equation takes the extra "
                                       "stress minus the sample's mean (physics.py: without it N1 above the rest "
                                       "pressure puts the sample in tension)")
    damping_viscosity_ratio: NonNegative = Field(0.1, le=1.0, description="steady shear: a Morris viscosity of "
                                                 "this fraction of the modes' expected shear viscosity damps the "
                                                 "row zig-zag mode (physics.py); not part of the measured stress, -")
    stress_diffusion_ratio: NonNegative = Field(0.1, le=10.0, description="steady shear: the mode stresses diffuse "
                                                "with kappa = this x h^2 |gamma_dot| (physics.py: damps the sliding "
                                                "lattice's slow mode; nothing in homogeneous shear), -")


class RheometerExpected(Frozen):
    """One [[expected]] row: a quantity of one comparison (CHECK_QUANTITIES) and its tolerance (largest rel_error)."""

    check: Literal[tuple(CHECK_QUANTITIES)] = Field(description="the comparison, e.g. 'saos_maxwell'")
    quantity: str = Field(description="a quantity the comparison measures")
    tolerance: float = Field(gt=0, lt=1, description="largest rel_error that passes, -")

    @model_validator(mode="after")
    def _known_quantity(self):
        if self.quantity not in CHECK_QUANTITIES[self.check]:
            raise ValueError(f"quantity = {self.quantity!r} is not measured by check {self.check!r}; allowed: "
                             f"{', '.join(CHECK_QUANTITIES[self.check])}")
        return self


class Sweep(Frozen):
    """The frequencies `orchestrator rheometry` runs when --frequencies is not given."""

    frequencies: tuple[Positive, ...] = Field(min_length=1, max_length=200, description="angular frequencies "
                                              "omega, rad/s")


class RheometerCase(Frozen):
    """A validated rheometer case in SI units."""

    case: CaseMeta
    sample: Sample
    material: RheometerMaterial
    shear: Shear
    numerics: RheometerNumerics = RheometerNumerics()
    sweep: Sweep | None = Field(None, description="the frequency sweep of `orchestrator rheometry`, rad/s")
    expected: tuple[RheometerExpected, ...] = Field((), description="the verification checks (verify sph)")

    @model_validator(mode="after")
    def _consistent(self):
        checks = {row.check for row in self.expected}
        if checks & {"saos_maxwell", "newtonian_cell"} and not self.shear.oscillatory:
            raise ValueError("expected: saos_maxwell and newtonian_cell rows need an oscillatory shear "
                             "(shear.amplitude and shear.omega)")
        steady = sorted(checks & {"steady_ptt", "steady_viscosity"})
        if steady and self.shear.oscillatory:
            raise ValueError(f"expected: {steady[0]} rows need a steady shear (shear.shear_rate and shear.duration)")
        if self.material.storage_plateau > 0.0 and not self.shear.oscillatory:
            raise ValueError(f"material.storage_plateau = {self.material.storage_plateau:g} Pa in a steady shear: the "
                             "plateau is an elastic solid whose stress grows with the strain (no steady state); "
                             "remove it for a steady run")
        return self
