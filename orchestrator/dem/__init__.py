"""DEM knowledge shared by the DEM kinds (impact, drag_finishing): how the paper's contact law
(Uhlmann et al. 2015, eqs. 1-10) maps onto each engine's parameters.

yade_law: Yade 2023's Hertz-Mindlin law (Law2_ScGeom_MindlinPhys_Mindlin) and its damping;
liggghts_law: LIGGGHTS-PUBLIC 3.8's ``model hertz tangential history`` and its damping;
lammps_law: LAMMPS's ``pair_style granular`` (hertz/material, coeff_restitution damping, mindlin/force).
"""

from __future__ import annotations

#: An immovable rigid wall's E on a DEM engine, as a multiple of the stiffest sphere material's.
RIGID_STIFFNESS_FACTOR = 1e6
#: Poisson's ratio given to a rigid wall (it has no effect: its E is RIGID_STIFFNESS_FACTOR times larger).
RIGID_POISSON = 0.3
