"""Measured surge-front positions of the 2D dam break (collapse of a water column).

A column of width a and height n^2 a (here n^2 = 2) stands against the left
wall of a dry tank and is released at t = 0. Every table here is
dimensionless in the convention of Martin & Moyce:

    T = t sqrt(2 g / a)      (note the factor 2; some authors use t sqrt(g / a) = T / sqrt(2))
    Z = x / a                (leading edge measured from the back wall, so Z = 1 at T = 0)

Sources of the numbers (digitised by others from the papers' figures and
tables; nothing here was read off a figure by us):

- Martin, J. C. & Moyce, W. J. (1952). Part IV. An experimental study of the
  collapse of liquid columns on a rigid horizontal plane. Phil. Trans. R. Soc.
  Lond. A 244(882), 312-324, doi:10.1098/rsta.1952.0006. Fig. 3, n^2 = 2, for
  a = 1.125 in and a = 2.25 in: as digitised in PySPH,
  https://github.com/pypr/pysph/blob/483e4449f50719350fc2857e8163ea3aae637cc7/pysph/examples/db_exp_data.py
  (mm_data_1, mm_data_2; BSD licence). A second, independent digitisation of
  the n^2 = 2 series (Z in steps of 2/9, i.e. quarter inches of the 1.125 in
  column) is in the Lethe project,
  https://github.com/chaos-polymtl/lethe/blob/129b71aa1040b73367e6aa0ada4d020ad8a2a194/examples/multiphysics/dam-break/dam-break-2d.py
  (x_exp, y_exp; LGPL); we keep it to show how far two digitisations differ.
- Koshizuka, S. & Oka, Y. (1996). Moving-particle semi-implicit method for
  fragmentation of incompressible fluid. Nucl. Sci. Eng. 123, 421-434: their
  experiment (column L = 0.146 m wide, 2L high, tank 4L long), Z = z/L against
  T = t sqrt(2 g / L), as digitised in the same PySPH file (ko_data).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

INCH = 0.0254  # m

#: PySPH's db_exp_data.py at the commit cited in the module docstring.
PYSPH_SOURCE = ("https://github.com/pypr/pysph/blob/483e4449f50719350fc2857e8163ea3aae637cc7/"
                "pysph/examples/db_exp_data.py")
LETHE_SOURCE = ("https://github.com/chaos-polymtl/lethe/blob/129b71aa1040b73367e6aa0ada4d020ad8a2a194/"
                "examples/multiphysics/dam-break/dam-break-2d.py")
MARTIN_MOYCE_1952 = ("Martin & Moyce (1952), Phil. Trans. R. Soc. Lond. A 244(882):312-324, "
                     "doi:10.1098/rsta.1952.0006")
KOSHIZUKA_OKA_1996 = "Koshizuka & Oka (1996), Nucl. Sci. Eng. 123:421-434"


@dataclass(frozen=True)
class SurgeFrontData:
    """One measured surge-front series: Z = x/a (-) at T = t sqrt(2 g / a) (-).

    column_width: a, m; height_ratio: column height / a (Martin & Moyce's n^2);
    experiment: the paper; digitised_by: URL of the file the numbers come from.
    """

    name: str
    T: tuple[float, ...]
    Z: tuple[float, ...]
    column_width: float
    height_ratio: float
    experiment: str
    digitised_by: str

    @property
    def T_range(self) -> tuple[float, float]:
        """First and last dimensionless time of the series."""
        return self.T[0], self.T[-1]

    def front_at(self, T) -> np.ndarray:
        """Z interpolated linearly at dimensionless times T (within T_range; nan outside)."""
        return np.interp(np.asarray(T, dtype=float), self.T, self.Z, left=math.nan, right=math.nan)


MARTIN_MOYCE_SMALL = SurgeFrontData(
    name="martin_moyce_1952_a1.125in",
    T=(0.849, 1.212, 1.602, 2.283, 2.950, 3.598, 3.905, 4.592, 4.961, 5.316),
    Z=(1.245, 1.443, 1.884, 2.689, 3.728, 4.528, 4.999, 5.841, 6.271, 6.717),
    column_width=1.125 * INCH, height_ratio=2.0, experiment=MARTIN_MOYCE_1952, digitised_by=PYSPH_SOURCE)

MARTIN_MOYCE_LARGE = SurgeFrontData(
    name="martin_moyce_1952_a2.25in",
    T=(0.832, 1.219, 1.997, 2.547, 3.345, 4.034, 4.418, 5.091, 5.685, 6.306, 6.822, 7.439, 8.031, 8.633, 9.237),
    Z=(1.217, 1.474, 2.292, 2.995, 4.134, 4.944, 5.881, 6.980, 7.945, 8.966, 9.986, 10.963, 11.977, 13.005,
       13.970),
    column_width=2.25 * INCH, height_ratio=2.0, experiment=MARTIN_MOYCE_1952, digitised_by=PYSPH_SOURCE)

MARTIN_MOYCE_LETHE = SurgeFrontData(
    name="martin_moyce_1952_lethe",
    T=(0.0, 0.41, 0.84, 1.19, 1.43, 1.63, 1.82, 1.97, 2.2, 2.32, 2.5, 2.64, 2.82, 2.96),
    Z=(1.0, 1.11, 1.23, 1.44, 1.67, 1.89, 2.11, 2.33, 2.56, 2.78, 3.0, 3.22, 3.44, 3.67),
    column_width=1.125 * INCH, height_ratio=2.0, experiment=MARTIN_MOYCE_1952, digitised_by=LETHE_SOURCE)

KOSHIZUKA_OKA = SurgeFrontData(
    name="koshizuka_oka_1996",
    T=(0.0, 0.381, 0.769, 1.153, 1.537, 1.935, 2.323, 2.719, 3.096),
    Z=(1.000, 1.111, 1.252, 1.505, 1.892, 2.241, 2.615, 3.003, 3.624),
    column_width=0.146, height_ratio=2.0, experiment=KOSHIZUKA_OKA_1996, digitised_by=PYSPH_SOURCE)

#: The series a verification compares with, by name.
SURGE_FRONT_DATA = {d.name: d for d in (MARTIN_MOYCE_SMALL, MARTIN_MOYCE_LARGE, MARTIN_MOYCE_LETHE, KOSHIZUKA_OKA)}


def dimensionless_time(t, column_width, gravity: float = 9.81):
    """T = t sqrt(2 g / a): t in s, column_width a in m, gravity g in m/s^2."""
    return np.asarray(t, dtype=float) * math.sqrt(2.0 * gravity / column_width)


def dimensionless_front(x, column_width):
    """Z = x / a: front position x (m, from the back wall) over the column width a (m)."""
    return np.asarray(x, dtype=float) / column_width
