"""`orchestrator bench sph` against LAMMPS SPH: one sph_flow case per peer scene, rendered by each engine's adapter.

Engine-free: the inputs the two adapters write for the periodic 3D block and the 3D dam break, read back and
compared number by number (particles, masses, densities, velocities, h, dt, c0, viscosity, gravity, steps,
periodic box); the ratios and the install hint on made-up rows. With both engines (marked): a smoke run of a few
steps through the bench's own jobs, no timing asserted.
"""

import json
from pathlib import Path
from types import SimpleNamespace

import h5py
import numpy as np
import pytest

from orchestrator.case import load_case
from orchestrator.case.loader import to_toml
from orchestrator.kinds import build_scene
from orchestrator.kinds.sph_flow.bench_scenes import (
    PEER_SCENES,
    block_3d_case,
    block_steps,
)
from orchestrator.kinds.sph_flow.lammps import DATA, DECK, LammpsSphFlow, refusal
from orchestrator.kinds.sph_flow.sph import DECK as SPH_DECK
from orchestrator.kinds.sph_flow.sph import SphFlow
from orchestrator.workflows.bench_lammps import INSTALL_HINT, summary
from orchestrator.workflows.bench_scenes import BenchRow, mean_neighbours
from orchestrator.workflows.bench_sph import format_report, run_bench


def scene_of(case_dict: dict, tmp_path: Path):
    path = tmp_path / "case.toml"
    path.write_text(to_toml(case_dict))
    return build_scene(load_case(path).model)


def read_sph_input(workdir: Path) -> dict:
    """deck.json and particles.h5 of the sph adapter."""
    deck = json.loads((workdir / SPH_DECK).read_text())
    with h5py.File(workdir / deck["particles_file"], "r") as h5:
        arrays = {key: h5[key][()] for key in ("positions", "velocities", "masses", "densities", "kind")}
    return {"deck": deck, **arrays}


def read_lammps_input(workdir: Path) -> dict:
    """The numbers of in.lammps (pair_coeff, timestep, run, gravity, boundary) and of its data file."""
    commands = {}
    for line in (workdir / DECK).read_text().splitlines():
        words = line.split("#")[0].split()
        if words:
            commands.setdefault(words[0], []).append(words[1:])
    rho0, c0, viscosity, cutoff = (float(w) for w in commands["pair_coeff"][0][2:6])
    gravity = [0.0, 0.0, 0.0]
    for words in commands.get("fix", []):
        if words[2] == "gravity":  # fix ID group gravity magnitude vector x y z
            gravity = [float(words[3]) * float(c) for c in words[5:8]]
    text = (workdir / DATA).read_text()
    header, rest = text.split("\nMasses\n")
    box = {line.split()[2][0]: [float(w) for w in line.split()[:2]] for line in header.splitlines()
           if line.endswith("hi")}
    masses = {int(w[0]): float(w[1]) for w in (line.split() for line in rest.split("Atoms")[0].strip().splitlines())}
    atoms = np.array([line.split() for line in text.split("Atoms # sph\n\n")[1].split("\n\nVelocities")[0]
                      .splitlines()], dtype=float)
    velocities = np.array([line.split() for line in text.split("Velocities\n\n")[1].strip().splitlines()], float)
    types = atoms[:, 1].astype(int)
    return {"rho0": rho0, "c0": c0, "viscosity": viscosity, "cutoff": cutoff, "gravity": gravity,
            "dt": float(commands["timestep"][0][0]), "steps": int(commands["run"][0][0]),
            "boundary": commands["boundary"][0], "box": box, "types": types,
            "masses": np.array([masses[t] for t in types]), "densities": atoms[:, 2], "positions": atoms[:, 5:8],
            "velocities": velocities[:, 1:4]}


@pytest.mark.parametrize("name", list(PEER_SCENES))
def test_both_engines_get_the_same_inputs(name, tmp_path):
    make, steps = PEER_SCENES[name]
    scene = scene_of(make(steps(200), 1), tmp_path)
    assert refusal(scene) == ""  # LAMMPS SPH has this scene's physics
    (tmp_path / "sph").mkdir()
    (tmp_path / "lammps").mkdir()
    SphFlow().write_input(SimpleNamespace(threads=1), scene, tmp_path / "sph")
    LammpsSphFlow().write_input(None, scene, tmp_path / "lammps")
    ours, theirs = read_sph_input(tmp_path / "sph"), read_lammps_input(tmp_path / "lammps")
    deck = ours["deck"]

    n = len(ours["positions"])
    assert n == len(theirs["positions"]) == scene.n_particles
    np.testing.assert_allclose(theirs["positions"], ours["positions"], rtol=0, atol=1e-15)
    np.testing.assert_allclose(theirs["velocities"], ours["velocities"], rtol=0, atol=1e-15)
    np.testing.assert_allclose(theirs["densities"], ours["densities"], rtol=1e-15)
    np.testing.assert_allclose(theirs["masses"], ours["masses"], rtol=1e-15)
    assert np.array_equal(theirs["types"] == 1, ours["kind"] == 0)  # fluid; the rest fixed boundary particles
    assert theirs["cutoff"] / 2 == pytest.approx(deck["h"], rel=1e-15)  # LAMMPS's cutoff is our support 2h
    assert theirs["rho0"] == pytest.approx(deck["rho0"], rel=1e-15)
    assert theirs["c0"] == pytest.approx(deck["c0"], rel=1e-15)
    # Monaghan's Pi_ab: LAMMPS's alpha multiplies its cutoff where ours multiplies h (lammps.py's mapping)
    assert theirs["viscosity"] * theirs["cutoff"] == pytest.approx(deck["alpha"] * deck["h"], rel=1e-14)
    assert deck["beta"] == 0.0
    assert theirs["dt"] == pytest.approx(deck["dt"], rel=1e-15)  # a fixed step in both
    assert theirs["steps"] == deck["max_steps"] == steps(200)
    assert deck["max_steps"] * deck["dt"] < deck["t_end"]  # our run stops at max_steps too
    np.testing.assert_allclose(theirs["gravity"], deck.get("body_force", [0.0, 0.0, 0.0]), rtol=0, atol=1e-14)
    axes = deck["periodic"]["axes"]
    assert [a for a in range(3) if theirs["boundary"][a] == "p"] == axes
    for k, a in enumerate(axes):
        assert theirs["box"]["xyz"[a]] == pytest.approx([deck["periodic"]["lo"][k], deck["periodic"]["hi"][k]],
                                                        rel=1e-15)


def test_the_block_is_periodic_water_in_shear(tmp_path):
    scene = scene_of(block_3d_case(block_steps(200), 1), tmp_path)
    assert scene.n_particles == scene.n_fluid == 25_600 and block_steps(200) == 500
    assert scene.h == pytest.approx(1.5e-3, rel=1e-12) and scene.c0 == pytest.approx(10.0)
    assert scene.timestep == pytest.approx(2e-6)
    u = np.asarray(scene.velocities)
    assert np.abs(u[:, 1:]).max() == 0.0 and np.abs(u[:, 0]).max() == pytest.approx(np.sin(3 * np.pi / 8))
    assert abs(u[:, 0].mean()) < 1e-12  # no net drift
    neighbours = mean_neighbours(scene.positions, scene.kind, 2 * scene.h, [0.04, 0.04, 0.016])
    # lattice sites within 2h = 3 dx: 92 strictly inside, 122 counting those at exactly 3 dx (rounding decides)
    assert 92 <= neighbours <= 122


def test_lammps_ratios_and_install_hint():
    def row(scene, engine, per_core):
        return BenchRow(scene, engine, 1, 100, 100, 10, 100.0, 1.0, 1.0, 2 * per_core, per_core)

    rows = [row("bench_block_3d", "sph 0.1.0", 3e6), row("bench_block_3d", "lammps 22 Jul 2025", 2e6),
            row("bench_dam_break_3d", "sph 0.1.0", 1e6), row("bench_dam_break_3d", "lammps 22 Jul 2025", 0.5e6)]
    s = summary(rows)
    assert s["ratio_lammps_block_3d"] == pytest.approx(1.5)
    assert s["ratio_lammps_dam_break_3d"] == pytest.approx(2.0)
    assert s["ratio_lammps_wall_block_3d"] == pytest.approx(1.5)
    report = format_report(rows)
    assert "3D block, 1 thread, sph / LAMMPS SPH: 1.50 per CPU second" in report
    assert "3D dam break, 1 thread, sph / LAMMPS SPH: 2.00 per CPU second" in report
    assert INSTALL_HINT in format_report(rows[:1]) and INSTALL_HINT not in report
    assert not any(key.startswith("speedup") for key in summary(rows))  # LAMMPS's rows are no thread counts of ours
    assert not any("2ranks" in key for key in s)


def test_two_ranks_against_our_two_threads():
    def row(engine, threads, rate, cpu_rate, wait="-", ranks=1):
        return BenchRow("bench_block_3d", engine, threads, 100, 100, 10, 100.0, 1.0, 1.0, rate, cpu_rate,
                        wait=wait, ranks=ranks)

    rows = [row("sph 0.1.0", 1, 3e6, 3e6), row("sph 0.1.0", 2, 5e6, 2.6e6, "spin"),
            row("sph 0.1.0", 2, 5.5e6, 2.8e6, "passive"), row("lammps 22 Jul 2025", 1, 1e6, 1e6),
            row("lammps 22 Jul 2025", 1, 1.6e6, 0.8e6, ranks=2)]
    s = summary(rows)
    assert s["ratio_lammps_block_3d"] == pytest.approx(3.0)  # the 1-rank row, not the 2-rank one
    assert s["ratio_lammps_2ranks_block_3d"] == pytest.approx(5.5 / 1.6)  # the faster of our 2-thread rows
    assert s["ratio_lammps_2ranks_cpu_block_3d"] == pytest.approx(2.8 / 0.8)
    assert s["lammps_2ranks_speedup_block_3d"] == pytest.approx(1.6)
    report = format_report(rows)
    assert "3D block, 2 cores, sph on 2 threads / LAMMPS SPH on 2 MPI ranks: 3.44 per wall second" in report
    assert "1 x 2 ranks" in report


@pytest.mark.sph
@pytest.mark.lammps
def test_smoke_run_of_both_engines(tmp_path):
    rows = run_bench(tmp_path, steps_2d=2, steps_3d=2, threads=(1,), with_pysph=False, with_lammps=True,
                     steps_shear=1)
    peers = [r for r in rows if r.scene in ("bench_block_3d", "bench_dam_break_3d")]
    assert all(r.status == "ok" for r in peers), [r.note for r in peers]
    assert sorted(r.ranks for r in peers if r.engine.startswith("lammps")) == [1, 1, 2, 2]
    by = {(r.scene, r.engine.split()[0]): r for r in peers if r.ranks == 1}
    assert set(by) == {(s, e) for s in ("bench_block_3d", "bench_dam_break_3d") for e in ("sph", "lammps")}
    for scene, steps, particles in (("bench_block_3d", 5, 25_600), ("bench_dam_break_3d", 2, 25_360)):
        ours, theirs = by[(scene, "sph")], by[(scene, "lammps")]
        assert ours.particles == theirs.particles == particles and ours.steps == theirs.steps == steps
        assert ours.neighbours == theirs.neighbours
        assert theirs.cpu_s > 0 and theirs.wall_s > 0
    assert (tmp_path / "lammps_block_3d" / "run" / "run.h5").is_file()  # each run is an `orchestrator run` directory
    assert "ratio_lammps_block_3d" in summary(rows)
