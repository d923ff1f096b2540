"""The oscillating cantilever plate of Gray, Monaghan & Swift (2001): a clamped elastic plate in 2D plane strain
swinging in its first bending mode, on the sph executable; its period against thin-plate theory and the clumping of
its particles, the tensile instability that Monaghan's artificial stress removes (verify solids)."""

from orchestrator.kinds.base import Kind, Verification

KIND = Kind(
    name="cantilever_plate",
    description="a clamped elastic plate swinging in its first mode (SPH); period against thin-plate theory",
    case_model="orchestrator.kinds.cantilever_plate.case:CantileverPlateCase",
    build_scene="orchestrator.kinds.cantilever_plate.scene:build_cantilever_plate",
    measure="orchestrator.kinds.cantilever_plate.analysis:measure_cantilever_plate",
    analyze="orchestrator.kinds.cantilever_plate.analysis:analyze_cantilever_plate_run",
    adapters={"sph": "orchestrator.kinds.cantilever_plate.sph:SphCantileverPlate"},
    quantities="orchestrator.kinds.cantilever_plate.analysis:QUANTITIES",
    expected="orchestrator.kinds.cantilever_plate.analysis:expected_cantilever_plate",
    verification=Verification(
        suite="solids", check="orchestrator.kinds.cantilever_plate.checks:check_run",
        units="orchestrator.kinds.cantilever_plate.checks:UNITS", timeout_s=1800.0, default_engines=("sph",)),
)
