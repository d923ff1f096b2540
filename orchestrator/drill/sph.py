"""The sph executable runs the drill kinds' scenes: sph_flow's adapter (the deck template, the particle and mesh
files, the reader of out.h5) on the scene itself (a drill/scene.DrillSphScene is an SphScene), with the run's
planned steps and a timing probe (probe.py) for the long presets."""

from __future__ import annotations

import sys
from pathlib import Path

from orchestrator.drill.probe import probe_scene, write_probe
from orchestrator.kinds.sph_flow.sph import SphFlow

#: Runs planned above this many fluid particle-steps (the filled scene's fluid particles x planned steps; about a
#: quarter of an hour at 1e6 particle-steps/s, the boundary particles' cost on top) start with a timing probe that
#: prints their estimated wall time.
PROBE_ABOVE_PARTICLE_STEPS = 1.0e9


class DrillSph(SphFlow):
    """sph_flow's SphFlow with the drill case's planned steps and a timing probe over the filled scene."""

    def planned_steps(self, profile, scene) -> int:
        """Steps at the CFL bound with the case's fastest speed, cfl h / (c0 + v) (DrillCase.planned_steps)."""
        return scene.drill.planned_steps

    def wants_probe(self, profile, scene) -> bool:
        """True above PROBE_ABOVE_PARTICLE_STEPS: a drill run's cost lies in its fluid particles (the scene fills from
        its start to the filled count, probe_scene) as much as in its steps."""
        return scene.drill.planned_steps * probe_scene(scene).n_fluid > PROBE_ABOVE_PARTICLE_STEPS

    def probe_command(self, profile, scene, workdir: Path, steps: int = 200):
        """The probe deck (probe.py: the fluid regions filled with the run's end count) in workdir and the command
        that runs it and prints the run's estimated wall time as a TIMING line."""
        workdir = Path(workdir).resolve()  # the probe runs in workdir: a relative path would not exist there
        info = write_probe(scene, workdir, profile.threads, steps)
        command = [sys.executable, "-m", "orchestrator.drill.probe", "--deck-dir", str(workdir),
                   "--planned", str(info["planned_steps"]), str(info["start"]), str(info["end"]),
                   "--sph", profile.executable or "sph"]
        return command, profile.environment(scene.drill.numerics.thread_wait)
