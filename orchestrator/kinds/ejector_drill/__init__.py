"""The ejector deep-hole drill of Canini et al.: its parametric geometry (case_geometry.py), the case
(case.py), the paper's two SPH scenes (layout.py, build.py) and the feed with the ejector nozzles (feed_*.py), run
by sph_flow's adapter (sph.py), and what is measured against the 1D hydraulic network (analysis.py, report.py);
dispatch.py picks by [scene] area. docs/ejector_drill.md."""

from orchestrator.kinds.base import Kind

KIND = Kind(
    name="ejector_drill",
    description="the ejector deep-hole drill's coolant flow (Canini et al.) on the sph executable, beside the 1D network",
    case_model="orchestrator.kinds.ejector_drill.case:EjectorDrillCase",
    build_scene="orchestrator.kinds.ejector_drill.dispatch:build_scene",
    measure="orchestrator.kinds.ejector_drill.dispatch:measure",
    analyze="orchestrator.kinds.ejector_drill.dispatch:analyze",
    adapters={"sph": "orchestrator.kinds.ejector_drill.sph:EjectorDrillSph"},
)
