"""The ejector deep-hole drill of seed 000 (Canini et al.): its parametric geometry (geometry.py). Not yet a
registered kind: the case model, scene and adapters are to come (docs/ejector_drill.md)."""
