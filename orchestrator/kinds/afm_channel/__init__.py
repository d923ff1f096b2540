"""The grain-scale abrasive-flow channel (Nutto et al., section IV, Fig. 5): a hard grain carried by a Newtonian
medium over the edge of a Johnson-Cook workpiece on the sph executable; the grain's path, the contact force, the
plastic strain and heating at the edge, the failed and removed particles, the edge's profile, the flow rate."""

from orchestrator.kinds.base import Kind

KIND = Kind(
    name="afm_channel",
    description="a grain carried by the medium over a Johnson-Cook workpiece's edge (SPH); wear, removal, flow",
    case_model="orchestrator.kinds.afm_channel.case:AfmChannelCase",
    build_scene="orchestrator.kinds.afm_channel.scene:build_afm_channel",
    measure="orchestrator.kinds.afm_channel.analysis:measure_channel",
    analyze="orchestrator.kinds.afm_channel.analysis:analyze_channel_run",
    adapters={"sph": "orchestrator.kinds.afm_channel.sph:SphAfmChannel"},
    quantities="orchestrator.kinds.afm_channel.analysis:QUANTITIES",
    study_pictures="orchestrator.kinds.afm_channel.study_pictures:channel_study_pictures",
)
