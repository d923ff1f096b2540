"""Weakly compressible SPH flows (the fluid model of Canini et al.): channels, dam breaks, walls, inlets and outlets."""

from orchestrator.kinds.base import Kind, Verification

KIND = Kind(
    name="sph_flow",
    description="weakly compressible SPH flows on the sph executable",
    case_model="orchestrator.kinds.sph_flow.case:SphFlowCase",
    build_scene="orchestrator.kinds.sph_flow.scene:build_sph_flow",
    measure="orchestrator.kinds.sph_flow.analysis:measure_sph_flow",
    analyze="orchestrator.kinds.sph_flow.analysis:analyze_sph_run",
    adapters={"sph": "orchestrator.kinds.sph_flow.sph:SphFlow",
              "lammps": "orchestrator.kinds.sph_flow.lammps:LammpsSphFlow"},
    quantities="orchestrator.kinds.sph_flow.analysis:QUANTITIES",
    benches={"sph": "orchestrator.kinds.sph_flow.bench_scenes"},
    verification=Verification(
        suite="sph", check="orchestrator.kinds.sph_flow.checks:check_run",
        units="orchestrator.kinds.sph_flow.checks_base:UNITS",
        picture="orchestrator.kinds.sph_flow.pictures:plot_scenes", timeout_s=3600.0, default_engines=("sph",),
        description="the SPH flows (cases/verification/sph_*.toml: Poiseuille and Couette start-up against the "
        "series of Morris et al. 1997, a hydrostatic tank, the 2D dam break against Koshizuka & Oka 1996 and "
        "Martin & Moyce 1952, penalty walls against eq. 14, a jet through a slot against von Mises 1917, and the "
        "rheometer's scenes) on the sph executable; verify_sph.png: profiles, pressure, surge front, wall forces, "
        "stresses (the 3D annulus takes ~750 s on one core)."),
)
