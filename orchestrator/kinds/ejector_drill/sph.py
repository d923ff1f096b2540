"""The sph executable runs ejector-drill scenes through sph_flow's adapter (the deck template, the particle and
mesh files, the reader of out.h5); filled_flow_scene fills every fluid region (the densest state a run reaches),
for timing probes (bench/ejector_drill_probe.py)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from orchestrator.kinds.sph_flow.scene import FLUID, lattice
from orchestrator.kinds.sph_flow.sph import SphFlow


class EjectorDrillSph(SphFlow):
    """sph_flow's SphFlow on the scene's `flow` part, with the run's planned steps."""

    def write_input(self, engine, scene, workdir: Path) -> None:
        super().write_input(engine, scene.flow, workdir)

    def command(self, engine, scene, workdir: Path):
        return super().command(engine, scene.flow, workdir)

    def read_output(self, engine, scene, workdir: Path):
        return super().read_output(engine, scene.flow, workdir)

    def planned_steps(self, engine, scene) -> int:
        """Steps at the CFL bound with the inflow speed, cfl h / (c0 + v_in): an upper bound while nothing in the
        scene runs faster than the inflow."""
        return scene.case.planned_steps


def filled_flow_scene(scene):
    """The scene's SphScene with every fluid region of its layout filled on the lattice, at rest."""
    case, layout = scene.case, scene.layout
    dx, rho0 = case.numerics.dx, case.fluid.density
    r = layout.r_max - case.geometry().workpiece_wall
    k = int(np.ceil(r / dx))
    z_lo = layout.z_lo + case.geometry().workpiece_wall
    z_hi = max(p.center[2] for p in layout.outlets.values())
    z_hi = max(z_hi, layout.inlet.center[2])
    points = lattice((-k * dx, -k * dx, z_lo), (k * dx, k * dx, z_lo + np.ceil((z_hi - z_lo) / dx) * dx), dx)
    points = points[layout.contains(points)]
    n = len(points)
    return dataclasses.replace(scene.flow, positions=points, velocities=np.zeros((n, 3)),
                               masses=np.full(n, rho0 * dx ** 3), densities=np.full(n, rho0),
                               kind=np.full(n, FLUID, dtype=np.int8), block=np.zeros(n, dtype=np.int32),
                               material=np.zeros(n, dtype=np.int32))
