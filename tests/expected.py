"""Numbers several test modules check against, computed once and kept here."""

#: Rebound produced by eq. 10's alpha when the normal force may not pull (our
#: default and Yade's Law2_ScGeom_MindlinPhys_Mindlin), from the integrated
#: dimensionless impact (closed_form.restitution_from_alpha, rtol 1e-11).
EQ10_REBOUND_WITHOUT_TENSION = {0.2: 0.324863, 0.5: 0.550283, 0.68: 0.700702, 0.86: 0.863970, 0.95: 0.950507}
