"""The Taylor bar (Taylor 1948): a Johnson-Cook bar shot onto a rigid, frictionless wall, on the sph executable and
on LAMMPS MACHDYN (the cross-check); its final length, face diameter, plastic strain and temperature against a
published solution (verify solids)."""

from orchestrator.kinds.base import Kind, Verification

KIND = Kind(
    name="taylor_bar",
    description="a Johnson-Cook bar shot onto a rigid wall (SPH); final length, face diameter, plastic strain",
    case_model="orchestrator.kinds.taylor_bar.case:TaylorBarCase",
    build_scene="orchestrator.kinds.taylor_bar.scene:build_taylor_bar",
    measure="orchestrator.kinds.taylor_bar.analysis:measure_taylor_bar",
    analyze="orchestrator.kinds.taylor_bar.analysis:analyze_taylor_bar_run",
    adapters={"sph": "orchestrator.kinds.taylor_bar.sph:SphTaylorBar",
              "lammps": "orchestrator.kinds.taylor_bar.lammps:LammpsTaylorBar"},
    quantities="orchestrator.kinds.taylor_bar.analysis:QUANTITIES",
    verification=Verification(
        suite="solids", check="orchestrator.kinds.taylor_bar.checks:check_run",
        units="orchestrator.kinds.taylor_bar.checks:UNITS", picture="orchestrator.kinds.taylor_bar.checks:plot_suite",
        description="the Johnson-Cook solids: the Taylor bar's final shape against a published solution, Hutchings' "
                    "crater against eq. 20, the oscillating cantilever plate against thin-plate theory",
        timeout_s=3600.0, default_engines=("sph",)),
)
