"""The ejector deep-hole drill's feed (Canini, Gerken, Biermann & Eberhard, Fig. 5): the annular gap down to the
ejector nozzles, which divert V_EN into the inner tube, with C1 before and C2 behind them, in an SPH scene whose
inlets and outlets carry the 1D hydraulic network's state. The case (case.py), where things are (layout.py), the
walls (walls.py), the network at the boundaries (network.py), the scene (build.py), what is measured (analysis.py)
and `orchestrator analyze` beside the network (analysis.py, pictures.py). The drill's geometry, the SPH scene's
shared parts and the sph adapter are orchestrator/drill; the paper's flow-exit and drill-head scenes are the kind
ejector_drill. docs/ejector_feed.md."""

from orchestrator.kinds.base import Kind

KIND = Kind(
    name="ejector_feed",
    description="the ejector deep-hole drill's feed with its ejector nozzles (Canini et al.) on the sph executable, "
                "beside the 1D network",
    case_model="orchestrator.kinds.ejector_feed.case:EjectorFeedCase",
    build_scene="orchestrator.kinds.ejector_feed.build:build_feed_scene",
    measure="orchestrator.kinds.ejector_feed.analysis:measure_feed",
    analyze="orchestrator.kinds.ejector_feed.analysis:analyze_feed_run",
    adapters={"sph": "orchestrator.drill.sph:DrillSph"},
)
