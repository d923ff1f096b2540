"""The grain scratch (Nutto et al., section II-B, Fig. 1): a hard, angular grain shot obliquely into an Al6061-T6
box on the sph executable, with and without Johnson-Cook failure; the kerf, its pile-up, the heating, the plastic
work, the removed particles and chips, and the energy balance."""

from orchestrator.kinds.base import Kind

KIND = Kind(
    name="scratch",
    description="a hard angular grain shot obliquely into a Johnson-Cook target (SPH); kerf, pile-up, removed chips",
    case_model="orchestrator.kinds.scratch.case:ScratchCase",
    build_scene="orchestrator.kinds.scratch.scene:build_scratch",
    measure="orchestrator.kinds.scratch.analysis:measure_scratch",
    analyze="orchestrator.kinds.scratch.analysis:analyze_scratch_run",
    adapters={"sph": "orchestrator.kinds.scratch.sph:SphScratch"},
    quantities="orchestrator.kinds.scratch.analysis:QUANTITIES",
)
