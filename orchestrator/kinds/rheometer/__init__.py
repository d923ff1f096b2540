"""The numerical rheometer (Nutto et al., section 3): a periodic SPH sample of a multi-mode PTT fluid
sheared by Lees-Edwards boundaries, steadily or in small-amplitude oscillation; G'(omega), G''(omega) fitted by
eq. 17 against the multi-mode Maxwell forms (eqs. 18-19)."""

from orchestrator.kinds.base import Kind, Verification

KIND = Kind(
    name="rheometer",
    description="a Lees-Edwards SPH sample of a PTT fluid in steady or oscillatory shear; G', G'' and viscosity",
    case_model="orchestrator.kinds.rheometer.case:RheometerCase",
    build_scene="orchestrator.kinds.rheometer.scene:build_rheometer",
    measure="orchestrator.kinds.rheometer.analysis:measure_rheometer",
    analyze="orchestrator.kinds.rheometer.analysis:analyze_rheometer_run",
    adapters={"sph": "orchestrator.kinds.rheometer.sph:SphRheometer"},
    quantities="orchestrator.kinds.rheometer.analysis:QUANTITIES",
    verification=Verification(
        suite="sph", check="orchestrator.kinds.rheometer.checks:check_run",
        units="orchestrator.kinds.rheometer.checks:UNITS", runs="orchestrator.kinds.rheometer.checks:sweep_runs"),
    commands={"rheometry": "orchestrator.kinds.rheometer.commands.rheometry:COMMAND",
              "calibrate maxwell": "orchestrator.kinds.rheometer.commands.calibrate_maxwell:COMMAND"},
)
