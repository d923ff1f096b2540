"""Weakly compressible SPH flows (the fluid model of Canini et al.): channels, dam breaks, walls, inlets and outlets."""

from orchestrator.kinds.base import Kind

KIND = Kind(
    name="sph_flow",
    description="weakly compressible SPH flows on the sph executable",
    case_model="orchestrator.kinds.sph_flow.case:SphFlowCase",
    build_scene="orchestrator.kinds.sph_flow.scene:build_sph_flow",
    measure="orchestrator.kinds.sph_flow.analysis:measure_sph_flow",
    analyze="orchestrator.kinds.sph_flow.analysis:analyze_sph_run",
    adapters={"sph": "orchestrator.kinds.sph_flow.sph:SphFlow"},
)
