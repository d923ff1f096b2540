"""Impacts of spheres on spheres and planes (DEM verification, the sphere drop of Uhlmann et al. 2015)."""

from orchestrator.kinds.base import Kind

KIND = Kind(
    name="impact",
    description="spheres colliding with spheres and a plane; contact events against closed forms",
    case_model="orchestrator.kinds.impact.case:ImpactCase",
    build_scene="orchestrator.kinds.impact.scene:build_impact",
    measure="orchestrator.kinds.impact.analysis:measure_impact",
    analyze="orchestrator.kinds.impact.report:analyze_impact_run",
    adapters={"yade": "orchestrator.kinds.impact.yade:YadeImpact",
              "liggghts": "orchestrator.kinds.impact.liggghts:LiggghtsImpact",
              "reference": "orchestrator.kinds.impact.reference:ReferenceImpact"},
)
