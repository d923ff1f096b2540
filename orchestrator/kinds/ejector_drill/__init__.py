"""The ejector deep-hole drill's coolant flow in the paper's two SPH scenes (Canini, Gerken, Biermann & Eberhard):
the flow-exit area (the annular gap, the adduction holes, the clearances to the bore) and the drill-head area (the
head clearance, the cutting zone, the chip mouth). The case (case.py), where things are (layout.py), the walls
(walls.py), the scene with its outlets and columns (build.py, columns.py), what is measured (analysis.py) and
`orchestrator analyze` beside the 1D hydraulic network (comparison.py, analysis.py, pictures.py), and what the
network's feed pressure hangs on, `orchestrator network-sensitivity` (sensitivity.py, commands/). The drill's
geometry, the SPH scene's shared parts and the sph adapter are orchestrator/drill; the feed with its ejector nozzles
is the kind ejector_feed. docs/ejector_drill.md."""

from orchestrator.kinds.base import Kind

KIND = Kind(
    name="ejector_drill",
    description="the ejector deep-hole drill's flow-exit and drill-head scenes (Canini et al.) on the sph "
                "executable, beside the 1D network",
    case_model="orchestrator.kinds.ejector_drill.case:EjectorDrillCase",
    build_scene="orchestrator.kinds.ejector_drill.build:build_drill_scene",
    measure="orchestrator.kinds.ejector_drill.analysis:measure_drill",
    analyze="orchestrator.kinds.ejector_drill.analysis:analyze_drill_run",
    adapters={"sph": "orchestrator.drill.sph:DrillSph"},
    commands={"network-sensitivity": "orchestrator.kinds.ejector_drill.commands.network_sensitivity:COMMAND"},
)
