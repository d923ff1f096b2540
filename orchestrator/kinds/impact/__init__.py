"""Impacts of spheres on spheres and planes (DEM verification, the sphere drop of Uhlmann et al. 2015)."""

from orchestrator.kinds.base import Kind, Verification

KIND = Kind(
    name="impact",
    description="spheres colliding with spheres and a plane; contact events against closed forms",
    case_model="orchestrator.kinds.impact.case:ImpactCase",
    build_scene="orchestrator.kinds.impact.scene:build_impact",
    measure="orchestrator.kinds.impact.analysis:measure_impact",
    analyze="orchestrator.kinds.impact.analysis:analyze_impact_run",
    adapters={"yade": "orchestrator.kinds.impact.yade:YadeImpact",
              "liggghts": "orchestrator.kinds.impact.liggghts:LiggghtsImpact",
              "lammps": "orchestrator.kinds.impact.lammps:LammpsImpact",
              "reference": "orchestrator.kinds.impact.reference:ReferenceImpact"},
    quantities="orchestrator.kinds.impact.theory:QUANTITIES",
    expected="orchestrator.kinds.impact.analysis:expected_values",
    compare_picture="orchestrator.kinds.impact.plots:plot_compare_curves",
    verification=Verification(
        suite="dem", check="orchestrator.kinds.impact.verification:check_run",
        units="orchestrator.kinds.impact.theory:QUANTITIES",
        picture="orchestrator.kinds.impact.verification:plot_suite", timeout_s=600.0,
        timestep_key="numerics.timestep_factor",
        description="the DEM impacts (Chung & Ooi 2011 tests 1-4 and the sphere drop of Uhlmann et al. 2015) on "
        "every installed DEM engine and the reference DEM, each [[expected]] row against its closed form; "
        "verify_dem.png: normal force in N against time in ms, engines overlaid per scene."),
    commands={"calibrate restitution": "orchestrator.kinds.impact.commands.calibrate_restitution:COMMAND"},
)
