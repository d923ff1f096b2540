"""The paper's contact law (Uhlmann et al. 2015, eqs. 1-10) on Yade 2023.

What Yade 2023.02a runs (Law2_ScGeom_MindlinPhys_Mindlin, checked on the
installed build by tests/kinds/impact/test_yade_impact.py):

- normal force k_n0 delta^(3/2), k_n0 = 4/3 E_eq sqrt(R_eq), never pulling
  (the sum with the dash-pot is clipped at zero);
- a sphere on a wall or facet has R_eq = R only with hertzian=True;
- damping c_n = 2 betan sqrt(m_eq k_n') with the tangent stiffness
  k_n' = 3/2 k_n0 delta^(1/2): Tsuji's form with alpha = sqrt(6) betan.
  Given en, Yade sets betan by Thornton et al. (2013)'s polynomial fit;
- tangential stiffness k_t0 delta^(1/2) with k_t0 = 8 sqrt(R_eq) G*,
  1/G* = (2 - nu_1)/G_1 + (2 - nu_2)/G_2 (Mindlin), and c_t = 2 betas
  sqrt(m_eq k_t0 delta^(1/2)); the Coulomb limit bounds the elastic part only.

The paper's law (eqs. 5, 9) has k_t0 = 4 sqrt(R_eq) G_m / (2 - nu_m) (means
of G and nu; the same as Mindlin's for like materials, 19 % more for ceramic
on steel) and c_t = c_n. To run it, Yade gets betan = alpha / sqrt(6) and
betas = alpha / 2 sqrt(k_n0 / k_t0) (yade_damping_parameters), and the
impact template sets each new contact's k_t0 to eq. 5's. A deck of another
engine that must damp as Yade does for a given en takes yade_native_alpha.
"""

from __future__ import annotations

import math

#: Thornton, Cummins & Cleary (2013), Powder Technol. 233, eq. B7: h_1..h_10 (Yade 2023's en -> betan).
THORNTON_COEFFICIENTS = (-6.918798, -16.41105, 146.8049, -796.4559, 2928.711, -7206.864, 11494.29, -11342.18,
                         6276.757, -1489.915)


def thornton_betan(restitution: float) -> float:
    """Yade 2023's betan for a given en (Thornton et al. 2013, eqs. B6-B7), -."""
    if restitution >= 1.0:
        return 0.0
    exponent = 0.0
    for h in reversed(THORNTON_COEFFICIENTS):
        exponent = restitution * (h + exponent)
    return math.sqrt(1.0 / (1.0 - (1.0 + restitution) ** 2 * math.exp(exponent)) - 1.0)


def yade_native_alpha(restitution: float) -> float:
    """The Tsuji alpha Yade 2023 runs for en = restitution: sqrt(6) betan, -."""
    return math.sqrt(6.0) * thornton_betan(restitution)


def mindlin_shear_coefficient(young_1, poisson_1, young_2, poisson_2) -> float:
    """Yade 2023's k_t0 / sqrt(R_eq) = 8 G*, Pa, with 1/G* = (2 - nu_1)/G_1 + (2 - nu_2)/G_2 (E in Pa, nu -)."""
    g_1, g_2 = young_1 / (2 * (1 + poisson_1)), young_2 / (2 * (1 + poisson_2))
    return 8.0 / ((2 - poisson_1) / g_1 + (2 - poisson_2) / g_2)


def yade_damping_parameters(alpha: float, normal_coefficient: float, shear_coefficient: float) -> tuple[float, float]:
    """(betan, betas), -, that make Yade run c_n = c_t = alpha sqrt(m_eq k_n0) delta^(1/4).

    alpha: Tsuji constant, -; normal_coefficient: k_n0 / sqrt(R_eq) = 4/3 E_eq, Pa;
    shear_coefficient: the k_t0 / sqrt(R_eq) Yade runs with, Pa.
    """
    return alpha / math.sqrt(6.0), 0.5 * alpha * math.sqrt(normal_coefficient / shear_coefficient)
