"""Drag finishing (Uhlmann et al. 2015): a rod dragged on a circle through a bowl of ceramic media."""

from orchestrator.kinds.base import Kind

KIND = Kind(
    name="drag_finishing",
    description="a rod dragged through a bowl of media; force on the rod, networks, contact intensity",
    case_model="orchestrator.kinds.drag_finishing.case:DragFinishingCase",
    build_scene="orchestrator.kinds.drag_finishing.scene:build_drag_finishing",
    measure="orchestrator.kinds.drag_finishing.analysis:measure_drag_finishing",
    analyze="orchestrator.kinds.drag_finishing.analysis:analyze_drag_finishing_run",
    adapters={"yade": "orchestrator.kinds.drag_finishing.yade:YadeDragFinishing",
              "liggghts": "orchestrator.kinds.drag_finishing.liggghts:LiggghtsDragFinishing"},
    refusals={"reference": "orchestrator.kinds.drag_finishing.reference:refusal"},
    study_pictures="orchestrator.kinds.drag_finishing.study_pictures:drag_finishing_study_pictures",
    quantities="orchestrator.kinds.drag_finishing.analysis:QUANTITIES",
    references="orchestrator.kinds.drag_finishing.analysis:reference_table",
    compare_picture="orchestrator.kinds.drag_finishing.plots:plot_engine_forces",
)
