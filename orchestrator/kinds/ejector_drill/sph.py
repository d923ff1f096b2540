"""The sph executable runs ejector-drill scenes through sph_flow's adapter (the deck template, the particle and
mesh files, the reader of out.h5), with a timing probe (probe.py) for the long presets."""

from __future__ import annotations

import sys
from pathlib import Path

from orchestrator.kinds.ejector_drill.probe import probe_scene, write_probe
from orchestrator.kinds.sph_flow.sph import SphFlow


#: Runs planned above this many fluid particle-steps (the filled scene's fluid particles x planned steps; about a
#: quarter of an hour at 1e6 particle-steps/s, the boundary particles' cost on top) start with a timing probe that
#: prints their estimated wall time.
PROBE_ABOVE_PARTICLE_STEPS = 1.0e9


class EjectorDrillSph(SphFlow):
    """sph_flow's SphFlow on the scene's `flow` part, with the run's planned steps."""

    def write_input(self, engine, scene, workdir: Path) -> None:
        super().write_input(engine, scene.flow, workdir)

    def command(self, engine, scene, workdir: Path):
        return super().command(engine, scene.flow, workdir)

    def read_output(self, engine, scene, workdir: Path):
        return super().read_output(engine, scene.flow, workdir)

    def resume_input(self, engine, scene, workdir: Path):
        return super().resume_input(engine, scene.flow, workdir)

    def planned_steps(self, engine, scene) -> int:
        """Steps at the CFL bound with the inflow speed, cfl h / (c0 + v_in): an upper bound while nothing in the
        scene runs faster than the inflow."""
        return scene.case.planned_steps

    def wants_probe(self, engine, scene) -> bool:
        """True above PROBE_ABOVE_PARTICLE_STEPS: a drill run's cost lies in its fluid particles (the scene fills from
        a few hundred to the filled count, probe_scene) as much as in its steps."""
        return scene.case.planned_steps * probe_scene(scene).n_fluid > PROBE_ABOVE_PARTICLE_STEPS

    def probe_command(self, engine, scene, workdir: Path, steps: int = 200):
        """The probe deck (probe.py: the fluid regions filled with the run's end count) in workdir and the command
        that runs it and prints the run's estimated wall time as a TIMING line."""
        workdir = Path(workdir).resolve()  # the probe runs with workdir as its cwd: a relative path would not exist there
        info = write_probe(scene, workdir, engine.threads, steps)
        command = [sys.executable, "-m", "orchestrator.kinds.ejector_drill.probe", "--deck-dir", str(workdir),
                   "--planned", str(info["planned_steps"]), str(info["start"]), str(info["end"]),
                   "--sph", engine.executable or "sph"]
        return command, engine.environment(scene.case.numerics.thread_wait)


