"""Golden files: the LIGGGHTS decks rendered for the sphere drop, the e_n = 0.2 impact (two wall copies) and the
tiny bowl (with and without stiffening); the files the decks read; the profile's command line. No engine needed.

Numbers are compared within a relative 1e-9 (tests/golden.py): their last digits follow the CPU's BLAS kernel.
Regenerate after an intended change with: UPDATE_GOLDEN=1 pytest tests/kinds/drag_finishing/test_liggghts_template.py
"""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

from orchestrator.kinds import bind
import trimesh

from orchestrator.engines import liggghts
from orchestrator.engines.liggghts import LOCAL_MPI_ENV, SINGLETON_ENV, Liggghts
from orchestrator.kinds.drag_finishing.liggghts_deck import process_chunks
from orchestrator.case import load_case
from orchestrator.errors import OrchestratorError
from orchestrator.kinds import build_scene

from golden import assert_matches_golden
from paths import VERIFICATION, TINY_BOWL
from paths import GOLDEN as GOLDEN_DIR

GOLDEN = {
    "liggghts_impact_sphere_drop.in": (VERIFICATION / "uhlmann2015_sphere_drop.toml", ()),
    "liggghts_impact_restitution_020.in": (VERIFICATION / "chung_ooi_test3_restitution_020.toml", ()),
    "liggghts_tiny_bowl.in": (TINY_BOWL, ()),
    "liggghts_tiny_bowl_stiffen.in": (TINY_BOWL, ("settling.stiffness_scale=0.0001",)),
}


def liggghts_adapter(scene):
    """The LIGGGHTS adapter of the scene's kind bound to a LIGGGHTS that is not installed (files only)."""
    return bind(scene.case.case.kind, "liggghts", executable="/nonexistent/liggghts")


@pytest.mark.parametrize("golden", sorted(GOLDEN))
def test_rendered_deck_matches_golden(golden, tmp_path):
    case_file, overrides = GOLDEN[golden]
    scene = build_scene(load_case(case_file, overrides=list(overrides)).model)
    liggghts_adapter(scene).write_input(scene, tmp_path)
    rendered = (tmp_path / ("impact.in" if "impact" in golden else "drag_finishing.in")).read_text()
    assert_matches_golden(rendered, GOLDEN_DIR / golden)
    assert "{{" not in rendered and "{%" not in rendered


def _data_atoms(path: Path) -> np.ndarray:
    lines = path.read_text().splitlines()
    start = lines.index("Atoms") + 2
    end = lines.index("Velocities") - 1 if "Velocities" in lines else len(lines)
    return np.array([line.split() for line in lines[start:end] if line.strip()], dtype=float)


def test_the_cloud_and_meshes_reach_liggghts_unchanged(tmp_path, tiny_bowl_scene):
    scene = tiny_bowl_scene
    liggghts_adapter(scene).write_input(scene, tmp_path)
    atoms = _data_atoms(tmp_path / "balls.data")  # id type diameter density x y z
    np.testing.assert_array_equal(atoms[:, 0], np.arange(1, scene.n_particles + 1))
    np.testing.assert_array_equal(atoms[:, 2] / 2.0, scene.radii)
    np.testing.assert_array_equal(atoms[:, 4:7], scene.positions)
    for name in ("bowl", "rod"):
        mesh = trimesh.load_mesh(tmp_path / f"{name}.stl", process=False)
        np.testing.assert_allclose(mesh.triangles, scene.meshes[name].mesh.triangles, rtol=0, atol=1e-15)
        assert (tmp_path / f"{name}.stl").read_text().startswith(f"solid {name}")  # ASCII: 3.8 reads no binary


def test_impact_spheres_carry_velocity_and_spin(tmp_path):
    scene = build_scene(load_case(VERIFICATION / "chung_ooi_test4_oblique_30deg.toml").model)
    liggghts_adapter(scene).write_input(scene, tmp_path)
    text = (tmp_path / "spheres.data").read_text().splitlines()
    velocities = np.array(text[text.index("Velocities") + 2].split()[1:], dtype=float)
    np.testing.assert_array_equal(velocities, np.concatenate([scene.velocities[0], scene.angular_velocities[0]]))
    triangle = trimesh.load_mesh(tmp_path / "plane.stl", process=False).triangles[0]
    assert np.allclose(triangle[:, 2], 0.0)  # in the plane z = 0


def test_two_spheres_damped_beyond_liggghts_limit_are_refused():
    case = load_case(VERIFICATION / "chung_ooi_test1_sphere_sphere.toml",
                     overrides=["contacts=[{pair=['glass', 'glass'], restitution=0.2, friction=0.0}]",
                                "model.damping='exact'"]).model
    with pytest.raises(OrchestratorError, match=r"contacts \(glass, glass\).*beta = 0\.731.*at most 0\.667"):
        scene = build_scene(case)
        liggghts_adapter(scene).check_scene(scene)


def test_process_chunks_cut_at_timing_and_snapshots():
    no = {"checkpoint": False, "impacts": False}
    assert process_chunks(4000, [1500]) == [{"steps": 500, "timing": True, "networks": [], **no},
                                            {"steps": 1000, "timing": False, "networks": [0], **no},
                                            {"steps": 2500, "timing": False, "networks": [], **no}]
    chunks = process_chunks(300, [300, 100])
    assert [c["steps"] for c in chunks] == [100, 200] and chunks[0]["networks"] == [1]
    assert chunks[1]["networks"] == [0] and sum(c["steps"] for c in chunks) == 300


def test_process_chunks_cut_at_checkpoints_but_not_at_the_end():
    chunks = process_chunks(4000, [1500], checkpoint_steps=1000)
    assert [c["steps"] for c in chunks] == [500, 500, 500, 500, 1000, 1000]
    assert [c["checkpoint"] for c in chunks] == [False, True, False, True, True, False]
    assert chunks[2]["networks"] == [0] and sum(c["steps"] for c in chunks) == 4000


def test_profile_command_single_and_mpi(monkeypatch, tmp_path):
    fake = tmp_path / "liggghts"
    fake.write_text("#!/bin/sh\n")
    monkeypatch.setenv("ORCHESTRATOR_LIGGGHTS", str(fake))
    monkeypatch.setenv("ORCHESTRATOR_MPIRUN", "/usr/bin/mpirun")
    for name in ("ORCHESTRATOR_LIGGGHTS_MPI", "ORCHESTRATOR_MPI_LOCAL", *LOCAL_MPI_ENV, *SINGLETON_ENV):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setattr(liggghts, "network_namespace", lambda: [])
    command, env = Liggghts().command("impact.in")
    assert command[-7:] == [str(fake), "-in", "impact.in", "-log", "none", "-echo", "none"]
    assert "mpirun" not in " ".join(command) and env["OMP_WAIT_POLICY"] == "PASSIVE"
    # one rank: an isolated MPI singleton on shared memory (no orted, no TCP transport: no listening socket)
    assert env["OMPI_MCA_ess_singleton_isolated"] == "1" and env["OMPI_MCA_btl"] == "self,vader"
    monkeypatch.setattr(os, "geteuid", lambda: 0)
    command, env = Liggghts(mpi_ranks=2).command("impact.in")
    assert command[:4] == ["/usr/bin/mpirun", "-np", "2", "--allow-run-as-root"]
    assert env["OMPI_MCA_mpi_yield_when_idle"] == "1"
    assert env["OMPI_MCA_oob_tcp_if_include"] == "lo" and "OMPI_MCA_ess_singleton_isolated" not in env
    monkeypatch.setattr(os, "geteuid", lambda: 1000)
    monkeypatch.setenv("ORCHESTRATOR_LIGGGHTS_MPI", "3")
    command, _ = Liggghts().command("impact.in")
    assert command[:3] == ["/usr/bin/mpirun", "-np", "3"] and "--allow-run-as-root" not in command
    # in a user and network namespace of its own mpirun is root, and its listeners reach no outside interface
    namespace = ["/usr/bin/unshare", "--user", "--map-root-user", "--net", "sh", "-c", "...", "/usr/bin/ip"]
    monkeypatch.setattr(liggghts, "network_namespace", lambda: namespace)
    command, _ = Liggghts().command("impact.in")
    assert command[:12] == namespace + ["/usr/bin/mpirun", "-np", "3", "--allow-run-as-root"]
    # what the user exported wins; ORCHESTRATOR_MPI_LOCAL=0 runs OpenMPI as configured (multi-node)
    monkeypatch.setenv("OMPI_MCA_btl", "self,vader,tcp")
    _, env = Liggghts().command("impact.in")
    assert "OMPI_MCA_btl" not in env and env["OMPI_MCA_pml"] == "ob1"
    monkeypatch.setenv("ORCHESTRATOR_MPI_LOCAL", "0")
    command, env = Liggghts().command("impact.in")
    assert command[0] == "/usr/bin/mpirun" and not any(k.startswith("OMPI_MCA_") and k != "OMPI_MCA_mpi_yield_when_idle"
                                                        for k in env)
    with pytest.raises(OrchestratorError, match="MPI ranks = 0"):
        Liggghts(mpi_ranks=0)


def test_network_namespace_runs_a_program_with_loopback_only():
    prefix = liggghts.network_namespace()
    if not prefix:
        pytest.skip("no user namespaces here (unshare -rn), or no unshare / ip")
    shown = subprocess.run(prefix + ["cat", "/proc/net/dev"], capture_output=True, text=True, timeout=30).stdout
    interfaces = [line.split(":")[0].strip() for line in shown.splitlines()[2:]]
    assert interfaces == ["lo"]


def test_mpi_on_an_engine_without_it_is_refused(tmp_path):
    from orchestrator.run import run_case

    with pytest.raises(OrchestratorError, match="--mpi 2: the reference engine does not run under MPI"):
        run_case(load_case(VERIFICATION / "chung_ooi_test2_sphere_plane.toml"), engine="reference", out_dir=tmp_path,
                 progress=False, mpi_ranks=2)
    assert not (tmp_path / "run.h5").exists()
