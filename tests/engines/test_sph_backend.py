"""The sph backend: golden decks, input files, the out.h5 parser on stored
outputs (no engine needed), bad case values, and real tiny runs through
`orchestrator run` and `orchestrator export` (skipped without the executable).

Numbers in the golden decks are compared within a relative 1e-9 (tests/golden.py).
Regenerate the golden decks after an intended template change with:
UPDATE_GOLDEN=1 pytest tests/engines/test_sph_backend.py
"""

from __future__ import annotations

import json
import shutil

import h5py
import numpy as np
import pytest

from orchestrator.kinds import bind

from orchestrator.kinds.sph_flow.sph import read_sph_output
from orchestrator.case import load_case
from orchestrator.errors import CaseError
from orchestrator.cli import main
from orchestrator.kinds import build_scene

from golden import assert_matches_golden
from paths import REPO, DATA, GOLDEN

DAM_BREAK = REPO / "cases" / "sph" / "dam_break_2d.toml"
CHANNEL = DATA / "sph_channel_3d.toml"
REFERENCE_2D = DATA / "sph_reference_2d.toml"

needs_sph = pytest.mark.sph


def _bound_adapter():
    """The sph adapter bound to an executable that does not exist (files only)."""
    return bind("sph_flow", "sph", executable="/nonexistent/sph")


@pytest.mark.parametrize("case_path,golden", [(DAM_BREAK, "sph_dam_break_2d.json"),
                                              (CHANNEL, "sph_channel_3d.json")])
def test_rendered_deck_matches_golden(case_path, golden, tmp_path):
    scene = build_scene(load_case(case_path).model)
    _bound_adapter().write_input(scene, tmp_path)
    rendered = (tmp_path / "deck.json").read_text()
    assert_matches_golden(rendered, GOLDEN / golden)
    deck = json.loads(rendered)  # valid JSON
    assert deck["c0"] == pytest.approx(scene.case.fluid.c0) and deck["h"] == pytest.approx(scene.h)


@pytest.mark.parametrize("wait,expected", [("passive", {"OMP_WAIT_POLICY": "PASSIVE"}),
                                           ("spin", {"OMP_WAIT_POLICY": "ACTIVE", "GOMP_SPINCOUNT": "10000"})])
def test_thread_wait_sets_the_openmp_environment(wait, expected, tmp_path):
    case = load_case(CHANNEL, overrides=[f"numerics.thread_wait={wait}", "numerics.threads=2"]).model
    bound_adapter = bind("sph_flow", "sph", executable="/nonexistent/sph", threads=2)
    scene = build_scene(case)
    bound_adapter.write_input(scene, tmp_path)
    _, env = bound_adapter.command(scene, tmp_path)
    assert env == {"OMP_NUM_THREADS": "2", **expected}


def test_deck_says_what_the_case_says(tmp_path):
    case = load_case(CHANNEL).model
    scene = build_scene(case)
    _bound_adapter().write_input(scene, tmp_path)
    deck = json.loads((tmp_path / "deck.json").read_text())
    assert deck["physics"] == ["morris_viscosity", "wall_penalty"]  # only what the case switches on
    assert "body_force" not in deck and "alpha" not in deck and "dt" not in deck
    assert deck["h"] == pytest.approx(1.3 * 0.01) and deck["c0"] == 6.0 and deck["viscosity"] == 1e-4
    assert deck["periodic"] == {"axes": [1], "lo": [0.0], "hi": [0.05]}
    assert deck["time_step"] == {"cfl": 0.3, "viscous": 0.125, "force": 0.25}
    assert [m["name"] for m in deck["meshes"]] == ["floor", "lid", "cube"]
    assert deck["inlets"][0]["velocity"] == 0.2 and deck["outlets"][0]["radius"] == 0.04
    assert deck["output"]["flow_planes"][0]["half_extents"] == [0.025, 0.03]


@pytest.mark.parametrize("walls,expected", [([], None), (["physics.artificial_viscosity.walls=true"], None),
                                             (["physics.artificial_viscosity.walls=false"], {"walls": False})])
def test_artificial_viscosity_walls_reach_the_deck(walls, expected, tmp_path):
    """walls = false writes "artificial_viscosity": {"walls": false}; the default writes nothing (decks unchanged)."""
    scene = build_scene(load_case(REFERENCE_2D, overrides=walls).model)
    _bound_adapter().write_input(scene, tmp_path)
    deck = json.loads((tmp_path / "deck.json").read_text())
    assert deck["alpha"] == 0.1 and deck.get("artificial_viscosity") == expected


@pytest.mark.parametrize("overrides,expected", [([], None), (["physics.viscosity_correction=true"], True)])
def test_viscosity_correction_reaches_the_deck(overrides, expected, tmp_path):
    """physics.viscosity_correction = true writes "viscosity_correction": true (engine eq. VC1); the default writes
    nothing (decks unchanged); without the Morris term the case is refused, naming the key."""
    scene = build_scene(load_case(REFERENCE_2D, overrides=overrides).model)
    _bound_adapter().write_input(scene, tmp_path)
    assert json.loads((tmp_path / "deck.json").read_text()).get("viscosity_correction") == expected
    with pytest.raises(CaseError, match="physics.viscosity_correction = true needs 'morris_viscosity'"):
        load_case(REFERENCE_2D, overrides=["physics.viscosity_correction=true",
                                           "physics.terms=['artificial_viscosity', 'body_force']"])


@pytest.mark.parametrize("overrides,expected", [([], None),
                                                 (["physics.eddy_viscosity=0.12"], {"model": "smagorinsky", "cs": 0.12, "walls": True}),
                                                 (["physics.eddy_viscosity=0.12", "physics.eddy_viscosity_walls=false"],
                                                  {"model": "smagorinsky", "cs": 0.12, "walls": False})])
def test_eddy_viscosity_reaches_the_deck(overrides, expected, tmp_path):
    """physics.eddy_viscosity = cs writes Smagorinsky's "eddy_viscosity" (engine eqs. SM1-SM2); the default writes
    nothing; a cs outside (0, 1] or a case without the Morris term is refused, naming the key."""
    scene = build_scene(load_case(REFERENCE_2D, overrides=overrides).model)
    _bound_adapter().write_input(scene, tmp_path)
    assert json.loads((tmp_path / "deck.json").read_text()).get("eddy_viscosity") == expected
    with pytest.raises(CaseError, match="eddy_viscosity"):
        load_case(REFERENCE_2D, overrides=["physics.eddy_viscosity=1.5"])
    with pytest.raises(CaseError, match="physics.eddy_viscosity needs 'morris_viscosity'"):
        load_case(REFERENCE_2D, overrides=["physics.eddy_viscosity=0.12",
                                           "physics.terms=['artificial_viscosity', 'body_force']"])


def test_density_diffusion_reaches_the_deck(tmp_path):
    """physics.density_diffusion = delta writes the deck's "density_diffusion" (engine eq. DD1); the default writes
    nothing; a delta outside (0, 1] or a scene of several fluids is refused, naming the key."""
    for overrides, expected in (([], None), (["physics.density_diffusion=0.1"], 0.1)):
        scene = build_scene(load_case(REFERENCE_2D, overrides=overrides).model)
        _bound_adapter().write_input(scene, tmp_path)
        assert json.loads((tmp_path / "deck.json").read_text()).get("density_diffusion") == expected
    with pytest.raises(CaseError, match="density_diffusion"):
        load_case(REFERENCE_2D, overrides=["physics.density_diffusion=0"])
    with pytest.raises(CaseError, match="physics.density_diffusion acts in a scene of one Newtonian fluid"):
        load_case(DATA / "sph_reference_two_materials.toml", overrides=["physics.density_diffusion=0.1"])


def test_input_files_hold_the_scene(tmp_path):
    scene = build_scene(load_case(CHANNEL).model)
    _bound_adapter().write_input(scene, tmp_path)
    with h5py.File(tmp_path / "particles.h5", "r") as h5:
        np.testing.assert_array_equal(h5["positions"][()], scene.positions)
        np.testing.assert_array_equal(h5["kind"][()], scene.kind)
        assert h5["kind"].dtype == np.int8 and h5["masses"][0] == pytest.approx(1000.0 * 0.01**3)
    # 6 x 5 x 5 upstream and 10 x 5 x 5 downstream particles, all fluid
    assert scene.n_particles == scene.n_fluid == 400
    with h5py.File(tmp_path / "meshes.h5", "r") as h5:
        cube = h5["cube"]["vertices"][()]
        np.testing.assert_allclose(cube.min(axis=0), [0.09, 0.015, 0.01])  # the STL in mm, scaled to m
        np.testing.assert_allclose(cube.max(axis=0), [0.11, 0.035, 0.03])
        assert h5["cube"]["faces"].shape == (12, 3) and h5["floor"]["faces"].shape == (2, 3)
        floor = h5["floor"]["vertices"][()]
        np.testing.assert_allclose(floor[:, 2], -0.003)
        np.testing.assert_allclose([floor[:, 0].min(), floor[:, 0].max()], [-0.01, 0.23])


def test_dam_break_scene():
    scene = build_scene(load_case(DAM_BREAK).model)
    assert scene.n_fluid == 20 * 40
    # walls of 3 layers: floor 86 x 3, two side walls 3 x 60; no site twice
    assert scene.n_particles - scene.n_fluid == 86 * 3 + 2 * 3 * 60
    assert len(np.unique(np.round(scene.positions / 1e-4), axis=0)) == scene.n_particles
    # hydrostatic start: p at the column's foot = rho0 g (H - y), Tait EOS inverted
    foot = np.argmin(np.where(scene.kind == 0, scene.positions[:, 1], np.inf))
    b = 1000.0 * scene.c0**2 / 7.0
    p = b * ((scene.densities[foot] / 1000.0) ** 7 - 1.0)
    assert p == pytest.approx(1000.0 * 9.81 * (0.292 - scene.positions[foot, 1]), rel=1e-12)


def test_overlapping_blocks_fill_a_site_once_and_the_first_block_keeps_it():
    water = "{name='water',kind='fluid',lo=[0.0,0.0],hi=[0.1,0.1],velocity=[1.0,0.0]}"
    tank = "{name='tank',kind='boundary',lo=[-0.03,-0.03],hi=[0.13,0.05]}"  # overlaps the water's lower half
    case = load_case(REFERENCE_2D, overrides=[f"blocks=[{water},{tank}]"]).model
    scene = build_scene(case)
    assert scene.n_fluid == 100 and scene.n_particles == 100 + 16 * 8 - 10 * 5
    assert np.all(scene.velocities[scene.kind == 0] == [1.0, 0.0]) and np.all(scene.velocities[scene.kind == 1] == 0)


def test_box_and_plane_walls_as_meshes():
    from orchestrator.kinds.sph_flow.case import Wall
    from orchestrator.kinds.sph_flow.scene import wall_mesh

    tank = wall_mesh(Wall(shape="box", name="t", lo=(0.0, 0.0), hi=(2.0, 1.0), open_sides=("+y",)), 2)
    np.testing.assert_array_equal(tank.vertices[tank.faces], [[[0, 0], [2, 0]], [[2, 0], [2, 1]], [[0, 1], [0, 0]]])
    box = wall_mesh(Wall(shape="box", name="b", lo=(0, 0, 0), hi=(1, 2, 3), open_sides=("-z", "+x")), 3)
    normals = np.cross(*(box.vertices[box.faces[:, k]] - box.vertices[box.faces[:, 0]] for k in (1, 2)))
    assert len(box.faces) == 8 and not np.any(normals[:, 2] < 0) and not np.any(normals[:, 0] > 0)
    plane = wall_mesh(Wall(shape="plane", name="p", center=(0, 0, 1), normal=(0, 0, 2), u=(1, 1, 0),
                           half_extents=(1.0, 0.5)), 3)
    area = 0.5 * np.linalg.norm(np.cross(*(plane.vertices[plane.faces[:, k]] - plane.vertices[plane.faces[:, 0]]
                                          for k in (1, 2))), axis=1).sum()
    assert area == pytest.approx(2.0) and np.allclose(plane.vertices[:, 2], 1.0)


def test_parser_reads_a_finished_run():
    result = read_sph_output(DATA / "sph_output_ok")
    assert result.status == "ok" and result.message == ""
    assert result.attrs["n_steps"] == 20 and result.attrs["dt"] == pytest.approx(2e-4)
    assert result.attrs["dimension"] == 2 and "morris_viscosity" in result.attrs["physics"]
    np.testing.assert_allclose(result.time, np.arange(5) * 1e-3, atol=1e-12)
    assert set(result.series) == {"kinetic_energy", "max_density_deviation"}
    assert result.series["kinetic_energy"].units == "J/m" and result.series["kinetic_energy"].values.shape == (5,)
    assert [t for t, _ in result.frames] == pytest.approx([0.0, 4e-3])
    frame = result.frames[-1][1]
    assert frame["positions"].shape == (414, 2) and frame["step"] == 20
    assert np.all(np.diff(frame["ids"]) > 0) and set(np.unique(frame["kind"])) == {0, 1}
    # the stored run starts at rest in the water block: 216 fluid particles at 0.5, 0.3 m/s
    first = result.frames[0][1]
    fluid = first["kind"] == 0
    ke = 0.5 * 1000.0 * 0.01**2 * np.sum(first["velocities"][fluid] ** 2)
    assert result.series["kinetic_energy"].values[0] == pytest.approx(ke, rel=1e-12)


def test_parser_reads_an_unstable_run():
    result = read_sph_output(DATA / "sph_output_unstable")
    assert result.status == "unstable"
    assert "density deviates from rho0" in result.message
    assert result.attrs["last_good_frame"] == len(result.frames) - 1 == 2
    assert result.frames[-1][0] == pytest.approx(0.006) and np.all(np.isfinite(result.frames[-1][1]["positions"]))


def test_parser_without_output_takes_the_engine_error(tmp_path):
    (tmp_path / "engine.log").write_text("error: unknown key 'viscosityy'; allowed keys: dimension, ...\n")
    result = read_sph_output(tmp_path)
    assert result.status == "failed" and result.message.startswith("unknown key 'viscosityy'")
    assert read_sph_output(tmp_path / "nothing").message == "the engine wrote no out.h5"


def test_parser_of_a_killed_run(tmp_path):
    shutil.copy(DATA / "sph_output_ok" / "out.h5", tmp_path / "out.h5")
    with h5py.File(tmp_path / "out.h5", "a") as h5:
        h5.attrs["status"] = "running"
    result = read_sph_output(tmp_path)
    assert result.status == "failed" and "without finishing" in result.message and len(result.frames) == 2


def test_stored_output_through_run_h5_analyze_and_export(capsys, tmp_path):
    """Engine-free: the stored output becomes run.h5 (as run_case writes it), which analyze and export read."""
    from orchestrator.kinds import measure
    from orchestrator.runh5 import RUN_FILE, read_run, write_run

    loaded = load_case(REFERENCE_2D)
    result = read_sph_output(DATA / "sph_output_ok", build_scene(loaded.model))
    result.measured = measure(loaded.model, result)
    root = {"engine": "sph", "engine_version": "0.1.0", "case_name": loaded.name, "case_kind": loaded.kind,
            "n_particles": 414, "wall_time_s": 0.1}
    write_run(tmp_path / RUN_FILE, result, root, loaded.toml_text, loaded.resolved, "log")
    run = read_run(tmp_path)
    np.testing.assert_array_equal(run["frames"]["1"]["positions"], result.frames[1][1]["positions"])
    assert run["measured"]["attrs"]["fluid_particles_last"] == 216
    assert run["measured"]["attrs"]["kinetic_energy_last"] == result.series["kinetic_energy"].values[-1]
    assert main(["analyze", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "kinetic_energy_last" in out and (tmp_path / "series.png").is_file()
    assert (tmp_path / "last_frame.png").is_file()
    assert main(["export", str(tmp_path)]) == 0
    exported = sorted(p.name for p in (tmp_path / "vtk").iterdir() if not p.name.startswith("."))
    assert exported == ["particles.pvd", "particles_0.vtu", "particles_1.vtu"]
    assert (tmp_path / "vtk" / ".orchestrator-run").is_file()  # the folder is claimed as ours


BAD_VALUES = [
    ("fluid.max_speed=-1", ["fluid.max_speed", "greater than 0"]),
    ("fluid.sound_speed=20.0", ["fluid.sound_speed = 20.0", "10 x fluid.max_speed"]),
    ("numerics.dx=0.01", ["blocks[0] (column)", "numerics.dx = 0.01"]),
    ("numerics.dt=1e-4", ["numerics.dt", "numerics.cfl", "give one of them"]),
    ("physics.terms=['body_force']", ["physics.artificial_viscosity is given", "physics.terms"]),
    ("physics.terms=['body_force','artificial_viscosity','vortex']", ["physics.terms", "'vortex'", "morris_viscosity"]),
    ("physics.body_force=[0.0,0.0,-9.81]", ["physics.body_force", "3 values", "allowed: 2"]),
    ("domain.periodic=[2]", ["domain.periodic", "axis 2"]),
    ("blocks.0.velocity=[4.0,0.0]", ["blocks[0].velocity", "fluid.max_speed"]),
    ("blocks.0.kind='gas'", ["blocks[0].kind", "'fluid' or 'boundary'"]),
    ("output.frame_interval=1.0", ["output.frame_interval = 1.0", "simulation.duration"]),
    ("output.probes.0.point=[0.1]", ["output.probes[0].point"]),
    ("walls=[{shape='box',name='w',lo=[0.0,0.0],hi=[1.0,1.0],radius=1.0}]", ["walls[0].radius", "unknown key"]),
    ("walls=[{shape='plane',name='w',center=[0.0,0.0],normal=[0.0,1.0]}]", ["walls[0]", "needs half_extents"]),
    ("case.engine='yade'", ["case.engine = 'yade'", "sph_flow", "allowed: lammps, sph"]),
    ("inlets=[{name='in',center=[0.0,0.1],normal=[1.0,0.0],radius=0.05,velocity=1.0,layers=2}]",
     ["inlets[0].layers = 2", "2h"]),
]


@pytest.mark.parametrize("override,words", BAD_VALUES, ids=[o.split("=")[0] for o, _ in BAD_VALUES])
def test_bad_values_name_the_key(override, words, capsys, tmp_path):
    code = main(["run", str(DAM_BREAK), "--set", override, "--out", str(tmp_path / "r")])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("error: ") and "Traceback" not in err
    for word in words:
        assert word in err, (word, err)
    assert not (tmp_path / "r").exists()


def test_a_wall_needs_wall_penalty(capsys, tmp_path):
    code = main(["run", str(DAM_BREAK), "--set", "walls=[{shape='plane',name='w',center=[0.0,0.0],"
                 "normal=[0.0,1.0],half_extents=[1.0]}]", "--out", str(tmp_path / "r")])
    err = capsys.readouterr().err
    assert code == 2 and "'wall_penalty' is not in physics.terms" in err


def test_missing_executable_says_how_to_build_it(monkeypatch, capsys, tmp_path):
    monkeypatch.setenv("ORCHESTRATOR_SPH", str(tmp_path / "no-sph"))
    code = main(["run", str(DAM_BREAK), "--preset", "tiny", "--out", str(tmp_path / "r")])
    err = capsys.readouterr().err
    assert code == 3 and f"ORCHESTRATOR_SPH={tmp_path / 'no-sph'} does not exist" in err and "make sph" in err


def test_engine_and_kind_must_match(capsys, tmp_path):
    drop = REPO / "cases" / "verification" / "uhlmann2015_sphere_drop.toml"
    code = main(["run", str(drop), "--set", "case.engine='sph'", "--out", str(tmp_path / "r")])
    assert code == 2 and "case.engine = 'sph' does not run impact cases" in capsys.readouterr().err
    code = main(["run", str(drop), "--engine", "sph", "--out", str(tmp_path / "r")])
    err = capsys.readouterr().err
    assert code == 2 and "--engine sph does not run impact cases; allowed: lammps, liggghts, reference, yade" in err
    code = main(["run", str(DAM_BREAK), "--engine", "yade", "--out", str(tmp_path / "r")])
    assert code == 2 and "--engine yade does not run sph_flow cases; allowed: lammps, sph" in capsys.readouterr().err
    assert not (tmp_path / "r").exists()


def _internal_energy(rho, rho0: float, c0: float, gamma: float = 7.0):
    """Specific internal energy of the Tait fluid, int_rho0^rho p / rho'^2 drho', J/kg (zero at rho0)."""
    b, x = rho0 * c0**2 / gamma, np.asarray(rho) / rho0
    return b / rho0 * (x ** (gamma - 1.0) / (gamma - 1.0) + 1.0 / x - 1.0 / (gamma - 1.0) - 1.0)


@needs_sph
def test_tiny_dam_break_through_run_and_export(capsys, tmp_path):
    """The first 20 ms of the dam break: run.h5 holds the engine's series and frames, and energy is conserved:
    the kinetic energy gained equals the potential energy lost plus the compression energy released by the
    hydrostatic start (Tait EOS), within 5 % (artificial viscosity and the boundary particles are the rest)."""
    from orchestrator.runh5 import read_run

    out = tmp_path / "run"
    code = main(["run", str(DAM_BREAK), "--preset", "tiny", "--out", str(out), "--no-progress", "--json"])
    summary = json.loads(capsys.readouterr().out)
    assert code == 0 and summary["status"] == "ok" and summary["engine"] == "sph"
    assert summary["n_particles"] == 1418 and summary["n_steps"] > 100
    run = read_run(out)
    assert run["attrs"]["status"] == "ok" and run["attrs"]["simulated_time"] == pytest.approx(0.02)
    assert {"kinetic_energy", "max_density_deviation", "pressure_probe_right_wall_toe",
            "flow_rate_mid_tank"} <= set(run["series"])
    frames = [run["frames"][k] for k in sorted((k for k in run["frames"] if k != "attrs"), key=int)]
    assert [f["attrs"]["time"] for f in frames] == pytest.approx([0.0, 0.01, 0.02])
    first, last = frames[0], frames[-1]
    fluid = first["kind"] == 0
    mass = 1000.0 * 0.0073**2
    potential_lost = mass * 9.81 * np.sum(first["positions"][fluid, 1] - last["positions"][fluid, 1])
    c0 = load_case(DAM_BREAK).model.fluid.c0
    released = mass * np.sum(_internal_energy(first["densities"][fluid], 1000.0, c0)
                             - _internal_energy(last["densities"][fluid], 1000.0, c0))
    kinetic = run["series"]["kinetic_energy"][-1]
    assert kinetic == pytest.approx(0.5 * mass * np.sum(last["velocities"][fluid] ** 2), rel=1e-9)
    assert kinetic == pytest.approx(potential_lost + released, rel=0.05)
    assert released > 0.05 * kinetic  # the compression energy is not negligible here
    assert run["measured"]["attrs"]["max_density_deviation"] < 0.02

    assert main(["export", str(out)]) == 0
    import meshio

    vtu = meshio.read(out / "vtk" / "particles_2.vtu")
    assert vtu.points.shape == (1418, 3) and np.all(vtu.points[:, 2] == 0.0)
    assert {"density", "pressure", "velocity", "kind"} <= set(vtu.point_data)
    np.testing.assert_allclose(vtu.point_data["velocity"][:, :2], last["velocities"])


@needs_sph
def test_unstable_run_keeps_its_last_good_frame(capsys, tmp_path):
    out = tmp_path / "run"
    code = main(["run", str(REFERENCE_2D), "--set", "numerics.dt=2e-3", "--set", "simulation.duration=0.04",
                 "--out", str(out), "--no-progress"])
    err = capsys.readouterr().err
    assert code == 7 and "numerically unstable" in err and "density deviates" in err
    from orchestrator.runh5 import read_run

    run = read_run(out)
    attrs = run["attrs"]
    assert attrs["status"] == "unstable" and f"step {attrs['n_steps']}" in attrs["message"]
    # the last good frame is the state one step before the step that failed, and it is the last frame kept
    k = attrs["last_good_frame"]
    assert k == max(int(key) for key in run["frames"] if key != "attrs")
    last = run["frames"][str(k)]
    assert last["attrs"]["step"] == attrs["n_steps"] - 1
    assert last["attrs"]["time"] == pytest.approx(attrs["simulated_time"] - 2e-3, rel=1e-9)
    assert np.all(np.isfinite(last["positions"]))


@needs_sph
def test_channel_with_inlet_outlet_and_walls_runs(capsys, tmp_path):
    """Every part of the schema reaches the engine and comes back: inflow, outflow, wall forces, flow planes."""
    out = tmp_path / "run"
    code = main(["run", str(CHANNEL), "--out", str(out), "--no-progress", "--json"])
    assert code == 0, capsys.readouterr().err
    from orchestrator.runh5 import read_run

    series = read_run(out)["series"]
    for name in ("inflow_in", "outflow_out", "wall_force_cube", "wall_force_floor", "flow_rate_section",
                 "flow_rate_disc", "pressure_probe_behind_cube"):
        assert name in series
    assert series["wall_force_cube"].shape[1] == 3
    # The inlet feeds fluid at 0.2 m/s through 50 mm x 50 mm: 5e-4 m^3/s once it runs (first record excepted).
    inflow = series["inflow_in"][1:]
    assert np.mean(inflow) == pytest.approx(0.2 * 0.05 * 0.05, rel=0.25)


@pytest.mark.parametrize("overrides,expected", [([], None), (["fluid.min_pressure=-0.99e5"], -0.99e5)])
def test_a_cavitation_floor_reaches_the_deck(overrides, expected, tmp_path):
    """fluid.min_pressure writes "min_pressure" (engine eos.h: the pressure's floor); the default writes nothing;
    a floor at or above the rest pressure is refused, naming both keys."""
    scene = build_scene(load_case(REFERENCE_2D, overrides=overrides).model)
    _bound_adapter().write_input(scene, tmp_path)
    assert json.loads((tmp_path / "deck.json").read_text()).get("min_pressure") == expected
    with pytest.raises(CaseError, match="fluid.min_pressure = 0 Pa must lie below the rest pressure"):
        load_case(REFERENCE_2D, overrides=["fluid.min_pressure=0"])
