"""Reference solvers: independent numpy/scipy implementations of the models
the engines run, for small scenes, and closed-form solutions to check them.

- contact: the DEM contact law of Uhlmann et al. 2015 (Hertz-Mindlin no-slip,
  Tsuji damping, Coulomb limit) as pure functions.
- closed_form: Hertz impact, damped Hertz impact (restitution <-> alpha),
  oblique impact with friction, bounce sequence.
- dem: a small vectorised DEM (spheres, planes, triangles) with that law.
"""
