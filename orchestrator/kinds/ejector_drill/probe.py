"""Timing probe of an ejector-drill run: the scene's fluid regions filled, in flow order, with as many particles as
the run can hold at its end (the prefill plus the inflow's volume over the whole duration), run for a few steps on
the same deck; one 'TIMING s_per_step=... planned_steps=... estimate_s=...' line (runner protocol) gives the run's
wall time as s/step of that state x the planned steps x (start + end particles) / (2 end particles), the mean of a
count that grows linearly while the scene fills.

    python -m orchestrator.kinds.ejector_drill.probe CASE [--preset NAME] [--steps 200] [--dir DIR]

prints the estimate for a case (the sph executable from $ORCHESTRATOR_SPH); EjectorDrillSph.probe_command runs
`python -m orchestrator.kinds.ejector_drill.probe --deck-dir DIR ...` on a probe deck it wrote."""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np

from orchestrator.case.loader import load_case
from orchestrator.engines.sph import Sph
from orchestrator.kinds import build_scene
from orchestrator.kinds.ejector_drill.build import filled_sites
from orchestrator.kinds.sph_flow.scene import FLUID
from orchestrator.kinds.sph_flow.sph import DECK, TEMPLATE, deck_context, write_meshes, write_particles
from orchestrator.templating import render


def end_particles(scene) -> int:
    """Upper bound of the run's fluid particles at its end: prefill + inflow volume over the duration / dx^3 (the
    boundary particles come on top)."""
    case, layout = scene.case, scene.layout
    if layout.area == "feed":  # it starts filled (feed_build.py): what flows in, flows out
        return scene.n_fluid
    ring = layout.channel
    inflow = case.scene.inlet_velocity * math.pi * (ring.r_out ** 2 - layout.inlet_inner_radius ** 2) \
        if layout.area == "flow_exit" else case.scene.inlet_velocity * math.pi * (ring.r_out ** 2 - ring.r_in ** 2)
    return scene.n_fluid + int(inflow * case.simulation.duration / case.numerics.dx ** 3)


def probe_scene(scene, limit: int | None = None):
    """The scene's SphScene with its fluid regions filled on the lattice at rest, region after region in flow order,
    up to `limit` fluid particles (default end_particles), beside the scene's boundary particles (at rho0: the
    filled state's)."""
    case, layout = scene.case, scene.layout
    dx, rho0 = case.numerics.dx, case.fluid.density
    limit = end_particles(scene) if limit is None else limit
    points = filled_sites(layout, dx, buffers=False)[:limit]
    flow = scene.flow
    walls = flow.kind != FLUID
    n, nb = len(points), int(np.count_nonzero(walls))
    wall_point = None if flow.wall_point is None else np.vstack([flow.wall_point[walls], np.full((n, 3), np.nan)])
    return dataclasses.replace(flow, positions=np.vstack([flow.positions[walls], points]),
                               velocities=np.zeros((nb + n, 3)), masses=np.full(nb + n, rho0 * dx ** 3),
                               densities=np.full(nb + n, rho0),
                               kind=np.concatenate([flow.kind[walls], np.full(n, FLUID, dtype=np.int8)]),
                               block=np.zeros(nb + n, dtype=np.int32), material=np.zeros(nb + n, dtype=np.int32),
                               wall_point=wall_point)


def write_probe(scene, workdir: Path, threads: int, steps: int) -> dict:
    """Write the probe's particles, meshes and deck into workdir; returns what the estimate needs."""
    workdir = Path(workdir)
    flow = probe_scene(scene)
    write_particles(flow, workdir / "particles.h5")
    if flow.meshes:  # penalty walls
        write_meshes(flow, workdir / "meshes.h5")
    deck = json.loads(render(TEMPLATE, deck_context(flow, threads=threads)))
    deck["max_steps"] = int(steps)
    deck["output"]["frame_interval"] = deck["t_end"]
    deck["output"]["series_interval"] = deck["t_end"]
    (workdir / DECK).write_text(json.dumps(deck, indent=1))
    return {"planned_steps": scene.case.planned_steps, "start": scene.n_particles, "end": flow.n_particles}


def estimate(workdir: Path, executable: str, planned_steps: int, start: int, end: int) -> tuple[float, float, float]:
    """Run the probe deck in workdir; (s per step at `end` particles, estimate s, upper bound s)."""
    try:
        done = subprocess.run([executable, DECK], cwd=workdir, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                              text=True)
    except OSError as err:
        raise SystemExit(f"error: cannot start the sph executable {executable!r} ({err.strerror}): build it with "
                         "'make sph' or set ORCHESTRATOR_SPH") from None
    if done.returncode != 0:
        raise SystemExit(f"error: the timing probe failed: {done.stderr.strip().splitlines()[-1:]}")
    import h5py

    with h5py.File(Path(workdir) / "out.h5", "r") as h5:
        per_step = float(h5.attrs["wall_time_s"]) / max(1, int(h5.attrs["n_steps"]))
    upper = per_step * planned_steps
    return per_step, upper * (start + end) / (2.0 * end), upper


def main(argv=None) -> int:
    """Command line (see the module docstring)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("case", nargs="?", help="an ejector_drill case file (TOML)")
    parser.add_argument("--preset", help="one of the case file's presets")
    parser.add_argument("--steps", type=int, default=200, help="engine steps the probe runs (default 200)")
    parser.add_argument("--dir", type=Path, default=Path("runs/ejector_drill_probe"),
                        help="where the probe writes its deck and output (default runs/ejector_drill_probe)")
    parser.add_argument("--deck-dir", type=Path, help="run a probe deck written by EjectorDrillSph.probe_command")
    parser.add_argument("--planned", type=int, nargs=3, metavar=("STEPS", "START", "END"),
                        help="with --deck-dir: the run's planned steps and its particles at the start and the end")
    parser.add_argument("--sph", default=None, help="the sph executable (default $ORCHESTRATOR_SPH, else "
                        "engines/sph/build/sph, else sph on PATH)")
    args = parser.parse_args(argv)
    executable = args.sph or Sph().executable or "sph"
    if args.deck_dir is not None:
        steps, start, end = args.planned
        workdir = args.deck_dir
    else:
        case = load_case(args.case, preset=args.preset).model
        scene = build_scene(case)
        args.dir.mkdir(parents=True, exist_ok=True)
        info = write_probe(scene, args.dir, case.numerics.threads, args.steps)
        steps, start, end, workdir = info["planned_steps"], info["start"], info["end"], args.dir
    per_step, typical, upper = estimate(workdir, executable, steps, start, end)
    print(f"TIMING s_per_step={per_step:.6g} planned_steps={steps} estimate_s={typical:.6g}", flush=True)
    print(f"probe: {end} particles (the run's end), {per_step * 1e3:.3g} ms per step; {steps} steps planned; the run "
          f"takes about {typical / 60:.1f} min (at most {upper / 60:.1f} min with the end's particles throughout)",
          file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
