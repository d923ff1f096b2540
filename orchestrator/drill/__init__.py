"""The ejector deep-hole drill of Canini, Gerken, Biermann & Eberhard, as its two kinds share it: the parametric
geometry (geometry.py), the case tables both kinds' cases hold (case.py), the fluid regions and patches of a scene
(regions.py), walls of boundary particles (walls.py), the SPH scene and the sph executable's adapter with its timing
probe (scene.py, sph.py, probe.py), a run's series (series.py) and the drawing of its pictures (drawing.py).

kinds/ejector_drill builds the paper's flow-exit and drill-head scenes from it, kinds/ejector_feed the feed with the
ejector nozzles. This package is not a kind: it registers nothing and imports neither kind."""
