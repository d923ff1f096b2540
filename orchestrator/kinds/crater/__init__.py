"""Hutchings' crater (Nutto et al., section III, Fig. 4): a hard sphere shot onto a Johnson-Cook target on the sph
executable and on LAMMPS MACHDYN (the cross-check); the crater's diameter against Hutchings' eq. 20 with the measured
mean contact pressure, its depth, the rebound and the energy balance (verify solids)."""

from orchestrator.kinds.base import Kind, Verification

KIND = Kind(
    name="crater",
    description="a hard sphere shot onto a Johnson-Cook target (SPH); crater diameter against Hutchings' eq. 20",
    case_model="orchestrator.kinds.crater.case:CraterCase",
    build_scene="orchestrator.kinds.crater.scene:build_crater",
    measure="orchestrator.kinds.crater.analysis:measure_crater",
    analyze="orchestrator.kinds.crater.analysis:analyze_crater_run",
    adapters={"sph": "orchestrator.kinds.crater.sph:SphCrater",
              "lammps": "orchestrator.kinds.crater.lammps:LammpsCrater"},
    quantities="orchestrator.kinds.crater.analysis:QUANTITIES",
    verification=Verification(
        suite="solids", check="orchestrator.kinds.crater.checks:check_run",
        units="orchestrator.kinds.crater.checks:UNITS", runs="orchestrator.kinds.crater.checks:sweep_runs",
        sweep_check="orchestrator.kinds.crater.checks:check_sweep",
        timeout_s=3600.0, default_engines=("sph",)),
)
