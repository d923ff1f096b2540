"""Timing probe of a drill run (either drill kind): a few steps of the run's start (the scene as it is written) and
of its end (the scene's fluid regions filled, in flow order, with as many particles as the run can hold at its end:
the start's fluid plus the inflow's volume over the whole duration), each on the run's deck; one 'TIMING s_per_step=...
planned_steps=... estimate_s=...' line (runner protocol) gives the run's wall time as the planned steps x the mean
of the two states' s/step: a step's cost grows with the wetted walls and the fluid, linearly while the scene fills.
A scene that starts filled (nothing to grow) probes its end state only. Measured on the paper-resolution flow-exit
run: start 31.7 ms, end 218 ms per step, so 34.7 min against the run's 37.1 min (the end state's cost
scaled by the particle count, (start + end) / (2 end), had announced 55 min: the boundary particles dominate the
count but not the cost). A filled start's end state lies at rest and underestimates a moving run about 2-fold.

    python -m orchestrator.drill.probe CASE [--preset NAME] [--steps 200] [--dir DIR]

prints the estimate for a case (the sph executable from $ORCHESTRATOR_SPH); DrillSph.probe_command (sph.py) runs
`python -m orchestrator.drill.probe --deck-dir DIR ...` on the probe decks it wrote (DIR the end state's, DIR/start
the start's)."""

from __future__ import annotations

import argparse
import dataclasses
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

from orchestrator.case.loader import load_case
from orchestrator.drill.scene import filled_sites
from orchestrator.engines.sph import Sph
from orchestrator.errors import OrchestratorError
from orchestrator.kinds import build_scene
from orchestrator.kinds.sph_flow.scene import FLUID
from orchestrator.kinds.sph_flow.sph import DECK, TEMPLATE, deck_context, write_meshes, write_particles
from orchestrator.templating import render


def end_particles(scene) -> int:
    """Upper bound of the run's fluid particles at its end: its fluid at the start + its inflow's volume over the
    duration / dx^3 (the boundary particles come on top)."""
    case = scene.drill
    return scene.n_fluid + int(scene.inflow * case.simulation.duration / case.numerics.dx ** 3)


def probe_scene(scene, limit: int | None = None):
    """The scene's SphScene with its fluid regions filled on the lattice at rest, region after region in flow order,
    up to `limit` fluid particles (default end_particles), beside the scene's boundary particles (at rho0: the
    filled state's)."""
    case, layout = scene.drill, scene.layout
    dx, rho0 = case.numerics.dx, case.fluid.density
    limit = end_particles(scene) if limit is None else limit
    points = filled_sites(layout, dx, buffers=False)[:limit]
    flow = scene
    walls = flow.kind != FLUID
    n, nb = len(points), int(np.count_nonzero(walls))
    wall_point = None if flow.wall_point is None else np.vstack([flow.wall_point[walls], np.full((n, 3), np.nan)])
    return dataclasses.replace(flow, positions=np.vstack([flow.positions[walls], points]),
                               velocities=np.zeros((nb + n, 3)), masses=np.full(nb + n, rho0 * dx ** 3),
                               densities=np.full(nb + n, rho0),
                               kind=np.concatenate([flow.kind[walls], np.full(n, FLUID, dtype=np.int8)]),
                               block=np.zeros(nb + n, dtype=np.int32), material=np.zeros(nb + n, dtype=np.int32),
                               wall_point=wall_point)


#: The start state's deck directory inside a probe's directory (the end state's deck is the directory's own).
START = "start"


def _write_deck(flow, workdir: Path, threads: int, steps: int) -> None:
    """flow's particles, meshes and deck in workdir, the deck stopping after `steps` steps with one frame."""
    workdir.mkdir(parents=True, exist_ok=True)
    write_particles(flow, workdir / "particles.h5")
    if flow.meshes:  # penalty walls
        write_meshes(flow, workdir / "meshes.h5")
    deck = json.loads(render(TEMPLATE, deck_context(flow, threads=threads)))
    deck["max_steps"] = int(steps)
    deck["output"]["frame_interval"] = deck["t_end"]
    deck["output"]["series_interval"] = deck["t_end"]
    (workdir / DECK).write_text(json.dumps(deck, indent=1))


def write_probe(scene, workdir: Path, threads: int, steps: int) -> dict:
    """The end state's deck in workdir and, for a scene that fills (fewer fluid particles at its start than at its
    end), the start state's (the scene's own flow) in workdir/START; returns what the estimate needs."""
    workdir = Path(workdir)
    flow = probe_scene(scene)
    _write_deck(flow, workdir, threads, steps)
    if flow.n_fluid > scene.n_fluid:
        _write_deck(scene, workdir / START, threads, steps)
    return {"planned_steps": scene.drill.planned_steps, "start": scene.n_particles, "end": flow.n_particles}


def _seconds_per_step(workdir: Path, executable: str) -> float:
    """Run the probe deck in workdir; its engine wall time per step, s."""
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
        return float(h5.attrs["wall_time_s"]) / max(1, int(h5.attrs["n_steps"]))


def estimate(workdir: Path, executable: str, planned_steps: int, start: int, end: int
             ) -> tuple[float, float | None, float, float]:
    """Run the probe decks in workdir; (s per step at the end state, s per step at the start state or None, estimate
    s, upper bound s). Without a start deck the end's cost is scaled by the particle counts start, end."""
    per_end = _seconds_per_step(workdir, executable)
    upper = per_end * planned_steps
    if (Path(workdir) / START / DECK).is_file():
        per_start = _seconds_per_step(Path(workdir) / START, executable)
        return per_end, per_start, 0.5 * (per_start + per_end) * planned_steps, max(upper, per_start * planned_steps)
    return per_end, None, upper * (start + end) / (2.0 * end), upper


def main(argv=None) -> int:
    """Command line (see the module docstring)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("case", nargs="?", help="a case file (TOML) of a drill kind (ejector_drill, ejector_feed)")
    parser.add_argument("--preset", help="one of the case file's presets")
    parser.add_argument("--steps", type=int, default=200, help="engine steps the probe runs (default 200)")
    parser.add_argument("--dir", type=Path, default=Path("runs/ejector_drill_probe"),
                        help="where the probe writes its deck and output (default runs/ejector_drill_probe)")
    parser.add_argument("--deck-dir", type=Path, help="run a probe deck written by DrillSph.probe_command")
    parser.add_argument("--planned", type=int, nargs=3, metavar=("STEPS", "START", "END"),
                        help="with --deck-dir: the run's planned steps and its particles at the start and the end")
    parser.add_argument("--sph", default=None, help="the sph executable (default $ORCHESTRATOR_SPH, else "
                        "engines/sph/build/sph, else sph on PATH)")
    args = parser.parse_args(argv)
    if args.deck_dir is not None and args.planned is None:
        parser.error("--deck-dir needs --planned STEPS START END")
    if args.deck_dir is None and args.case is None:
        parser.error("name a case file (or --deck-dir with --planned)")
    executable = args.sph or Sph().executable or "sph"
    if args.deck_dir is not None:
        steps, start, end = args.planned
        workdir = args.deck_dir
    else:
        try:
            case = load_case(args.case, preset=args.preset).model
        except OrchestratorError as err:
            print(f"error: {err}", file=sys.stderr)
            return 2
        scene = build_scene(case)
        info = write_probe(scene, args.dir, case.numerics.threads, args.steps)
        steps, start, end, workdir = info["planned_steps"], info["start"], info["end"], args.dir
    per_step, per_start, typical, upper = estimate(workdir, executable, steps, start, end)
    print(f"TIMING s_per_step={typical / max(1, steps):.6g} planned_steps={steps} estimate_s={typical:.6g}",
          flush=True)
    at_start = "" if per_start is None else f" ({per_start * 1e3:.3g} ms per step at its start)"
    print(f"probe: {end} particles (the run's end), {per_step * 1e3:.3g} ms per step{at_start}; {steps} steps planned; "
          f"the run takes about {typical / 60:.1f} min (at most {upper / 60:.1f} min with the end's particles "
          "throughout)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
