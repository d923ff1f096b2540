"""Contact starts on the rod (kinds/drag_finishing/impacts.py): the prism the engines test against, the events
recomputed from the stored mesh against hand-placed balls, per-face sums, the printed summary, the deck's chunks
and the case's checks. The engines' own rows are checked against this in test_liggghts_run / test_yade_run."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import trimesh

from orchestrator.kinds.drag_finishing.impacts import (
    attach_impacts,
    facet_impacts,
    impact_events,
    impact_summary,
    impact_text,
    rod_prism,
)
from orchestrator.kinds.drag_finishing.intensity import turn_z
from orchestrator.kinds.drag_finishing.liggghts_deck import process_chunks
from orchestrator.kinds.drag_finishing.plots_impacts import plot_impact_speeds
from orchestrator.kinds.drag_finishing.scene import rod_mesh
from paths import CASES, TINY_BOWL

R_ROD, R_PATH, OMEGA, R_BALL, TIP = 0.005, 0.02, 0.5, 3.27e-3, 0.02


def placed_rod():
    """The generated rod (24 sides) at its process start pose: axis at (R_PATH, 0), tip at TIP."""
    rod = rod_mesh(R_ROD, 0.1, 24)
    rod.apply_translation([R_PATH, 0.0, TIP])
    return np.asarray(rod.vertices), np.asarray(rod.faces)


def test_the_generated_rod_is_the_prism_the_engines_test():
    vertices, faces = placed_rod()
    prism = rod_prism(vertices, faces)
    assert prism["segments"] == 24
    assert prism["apothem"] == pytest.approx(R_ROD * math.cos(math.pi / 24), rel=1e-12)
    assert prism["alpha0"] == pytest.approx(math.pi / 24, abs=1e-9)
    np.testing.assert_allclose(prism["axis"], [R_PATH, 0.0], atol=1e-15)
    sphere = trimesh.creation.icosphere(subdivisions=1)
    with pytest.raises(ValueError, match="not a regular vertical prism"):
        rod_prism(np.asarray(sphere.vertices), np.asarray(sphere.faces))


def test_events_from_hand_placed_balls_give_facet_gap_and_normal_speed():
    vertices, faces = placed_rod()
    t_stored, start = 3.0, 1.0  # the mesh is stored at 2 s of process
    stored = turn_z(vertices, OMEGA * (t_stored - start))
    a = R_ROD * math.cos(math.pi / 24)
    rows = []
    # (process time s, side k, height above the tip m, overlap m, approach U m/s, sliding speed along the face m/s)
    cases = [(0.1, 0, 0.010, 1e-7, 0.004, 0.002), (0.7, 6, 0.030, 5e-8, 0.020, 0.0),
             (1.9, 13, 0.002, 2e-7, 0.001, -0.01)]
    for tp, k, height, overlap, u, slide in cases:
        theta = OMEGA * tp
        alpha = math.pi / 24 + k * math.pi / 12
        n = np.array([math.cos(alpha + theta), math.sin(alpha + theta), 0.0])
        along = np.array([-n[1], n[0], 0.0])
        axis = R_PATH * np.array([math.cos(theta), math.sin(theta), 0.0])
        p = axis + (a + R_BALL - overlap) * n + [0.0, 0.0, TIP + height]
        v_rod = OMEGA * np.array([-p[1], p[0], 0.0])
        rows.append((start + tp, p, v_rod - u * n + slide * along))
    raw = {"time": np.array([r[0] for r in rows]), "ball": np.arange(3), "radius": np.full(3, R_BALL),
           "position": np.array([r[1] for r in rows]), "velocity": np.array([r[2] for r in rows]),
           "engine_speed": np.array([c[4] for c in cases])}
    ev = impact_events(raw, stored, faces, OMEGA, start, t_stored)
    np.testing.assert_allclose(ev["impact_speed"].values, [c[4] for c in cases], rtol=1e-9)
    np.testing.assert_allclose(ev["gap"].values, [-c[3] for c in cases], atol=1e-12)
    np.testing.assert_allclose(ev["process_time"].values, [c[0] for c in cases], atol=1e-15)
    tri = stored[faces[ev["facet"].values]]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normal_angle = np.degrees(np.arctan2(normal[:, 1], normal[:, 0]))
    expected = np.degrees([math.pi / 24 + k * math.pi / 12 + OMEGA * (t_stored - start) for _, k, *_ in cases])
    np.testing.assert_allclose(np.mod(normal_angle - expected + 180, 360) - 180, 0.0, atol=1e-9)


def test_wall_contact_starts_are_kept_on_the_rod_approaching_with_the_prism_speed():
    """LIGGGHTS's rows (no engine speed): the starts of any wall contact. Kept: the balls that overlap the rod and
    approach it, in order of time, each with the prism test's u; dropped: a start on the bowl far from the rod and
    one on the rod that recedes. The rod is stored to six digits, as LIGGGHTS's VTK writes it."""
    vertices, faces = placed_rod()
    t_stored, start = 3.0, 1.0
    stored = np.vectorize(lambda x: float(f"{x:.6g}"))(turn_z(vertices, OMEGA * (t_stored - start)))
    a = R_ROD * math.cos(math.pi / 24)
    # (process time s, side k, height above the tip m, overlap m, approach u m/s)
    cases = [(1.9, 13, 0.002, 2e-7, 0.001), (0.1, 0, 0.010, 1e-7, 0.004), (0.7, 6, 0.030, 5e-8, -0.002),
             (0.4, 3, 0.015, -0.012, 0.02)]
    rows = []
    for tp, k, height, overlap, u in cases:
        theta = OMEGA * tp
        alpha = math.pi / 24 + k * math.pi / 12 + theta
        n = np.array([math.cos(alpha), math.sin(alpha), 0.0])
        p = R_PATH * np.array([math.cos(theta), math.sin(theta), 0.0]) + (a + R_BALL - overlap) * n
        p[2] = TIP + height
        rows.append((start + tp, p, OMEGA * np.array([-p[1], p[0], 0.0]) - u * n))
    raw = {"time": np.array([r[0] for r in rows]), "ball": np.arange(4), "radius": np.full(4, R_BALL),
           "position": np.array([r[1] for r in rows]), "velocity": np.array([r[2] for r in rows])}

    class Result:
        attrs = {"process_start_time": start}
        meshes = {"rod": {"vertices": stored, "faces": faces}}
        events = {}

    attach_impacts(Result, raw, OMEGA, t_stored)
    ev = Result.events
    np.testing.assert_array_equal(ev["ball"].values, [1, 0])  # in order of time; the receding and far ones dropped
    np.testing.assert_allclose(ev["impact_speed"].values, [0.004, 0.001], rtol=1e-5)
    np.testing.assert_allclose(ev["engine_speed"].values, ev["impact_speed"].values, rtol=1e-5)
    np.testing.assert_allclose(ev["gap"].values, [-1e-7, -2e-7], atol=3e-8)  # the stored mesh's six digits
    assert Result.meshes["rod"]["impact_count"].sum() == 2


def test_at_an_edge_the_speed_is_along_the_normal_from_the_edge():
    vertices, faces = placed_rod()
    edge = math.pi / 12  # the edge between the first two sides, at the vertices' angle (rod radius R_ROD)
    n = np.array([math.cos(edge), math.sin(edge), 0.0])
    p = np.array([R_PATH, 0.0, TIP + 0.02]) + (R_ROD + R_BALL - 1e-7) * n
    v = 0.5 * np.array([-p[1], p[0], 0.0]) - 0.01 * n
    raw = {"time": np.array([1.0]), "ball": np.array([0]), "radius": np.array([R_BALL]), "position": p[None],
           "velocity": v[None], "engine_speed": np.array([0.01 * math.cos(math.pi / 24)])}
    ev = impact_events(raw, vertices, faces, 0.5, 1.0, 1.0)
    assert ev["impact_speed"].values[0] == pytest.approx(0.01, rel=1e-9)  # the prism test's face normal: 0.99 of it
    assert ev["gap"].values[0] == pytest.approx(-1e-7, abs=1e-12)


def test_per_face_counts_mean_and_peak():
    out = facet_impacts(np.array([2, 2, 5]), np.array([0.01, 0.03, 0.02]), 6)
    np.testing.assert_array_equal(out["impact_count"], [0, 0, 2, 0, 0, 1])
    np.testing.assert_allclose(out["impact_speed_mean"], [0, 0, 0.02, 0, 0, 0.02])
    np.testing.assert_allclose(out["impact_speed_max"], [0, 0, 0.03, 0, 0, 0.02])


def test_summary_sectors_text_and_picture(tmp_path):
    vertices, faces = placed_rod()
    # three balls at process time 0 (rod axis at (R_PATH, 0), v_w along +y): in front, behind, at the outer side
    p = np.array([[R_PATH, 0.009, 0.05], [R_PATH, -0.009, 0.05], [R_PATH + 0.009, 0.0, 0.05]])
    run = {"events": {"impact_speed": np.array([0.01, 0.02, 0.03]), "process_time": np.zeros(3), "position": p,
                      "facet": np.array([0, 1, 2]), "engine_speed": np.array([0.01, 0.02, 0.03 + 1e-6])},
           "case": {"attrs": {"workpiece.path_radius": R_PATH, "workpiece.speed": OMEGA * R_PATH,
                              "output.impact_window": np.array([0.0, 0.5])}},
           "meshes": {"rod": {"vertices": vertices, "faces": faces}}}
    res = impact_summary(run)
    np.testing.assert_allclose(res["phi"], [0.0, 180.0, 90.0], atol=1e-9)
    text = impact_text(res)
    assert "from 0 to 0.5 s of process): 3, 6.0 per s" in text
    assert "median 20.00 mm/s" in text and "max 30.00 mm/s" in text
    assert "front 33 %, outer side 33 %, back 33 %, inner side 0 %" in text
    assert "agree on the speed to 1e-6 m/s for 66.7 % of the contacts" in text
    assert "not recorded (set output.impact_window" in impact_text(None)
    path = plot_impact_speeds(res, np.array([0.005, 0.015]), TIP, 0.07, tmp_path / "impacts.png")
    assert path.stat().st_size > 20_000


def test_the_deck_cuts_its_process_runs_at_the_impact_window():
    chunks = process_chunks(4000, [], impact_steps=(1000, 2500))
    assert [(c["steps"], c["impacts"]) for c in chunks] == [(500, False), (500, False), (1500, True), (1500, False)]
    assert [c["impacts"] for c in process_chunks(300, [], impact_steps=(0, 300))] == [True]


def assert_engine_impacts(run: dict) -> None:
    """What a tiny engine run with output.impact_window must hold: contact starts inside the window, each
    overlapping by less than one step of approach at the mesh's faces (or an edge's rounding, 0.05 mm at 8 sides),
    approaching, and the engine's prism test agreeing with the stored mesh's speed (to 1e-6 m/s); per-face sums
    that add up to the events."""
    ev, dt = run["events"], run["attrs"]["dt"]
    window = run["case"]["attrs"]["output.impact_window"]
    speed = ev["impact_speed"]
    assert len(speed) >= 3
    assert np.all((ev["process_time"] >= window[0] - dt) & (ev["process_time"] <= window[1] + dt))
    assert np.all(speed > 0)
    # on a face the engine's prism test and the mesh agree; at an edge the contact normal turns by at most half a
    # side's angle from the face normal the test takes, which bounds the difference by |v_rel| 2 sin(pi / 2n)
    attrs = run["case"]["attrs"]
    omega = attrs["workpiece.speed"] / attrs["workpiece.path_radius"]
    p, v = np.asarray(ev["position"]), np.asarray(ev["velocity"])
    v_rel = np.linalg.norm(v - omega * np.column_stack([-p[:, 1], p[:, 0], np.zeros(len(p))]), axis=1)
    difference = np.abs(ev["engine_speed"] - speed)
    assert np.mean(difference <= 1e-6) >= 0.5
    assert np.all(difference <= v_rel * 2 * np.sin(np.pi / (2 * attrs["workpiece.segments"])) + 1e-9)
    assert np.all(ev["gap"] <= speed * dt + 1e-12 + 5e-5) and np.all(ev["gap"] >= -speed * dt - 1e-9)
    rod = run["meshes"]["rod"]
    assert rod["impact_count"].sum() == len(speed)
    assert rod["impact_speed_max"].max() == pytest.approx(speed.max(), rel=1e-12)


@pytest.mark.liggghts  # the engine is checked before the scene
def test_an_impact_window_on_a_rod_that_is_no_prism_is_refused(tmp_path, capsys):
    from orchestrator.cli import main

    sphere = trimesh.creation.icosphere(subdivisions=2, radius=0.002)
    sphere.apply_translation([0.0, 0.0, 0.002])
    sphere.export(tmp_path / "ball.stl")
    tiny = TINY_BOWL
    code = main(["run", str(tiny), "--engine", "liggghts", "--out", str(tmp_path / "run"),
                 "--set", f"workpiece.mesh={json.dumps(str(tmp_path / 'ball.stl'))}"])
    err = capsys.readouterr().err
    assert code == 2, err
    assert "output.impact_window is set but the rod" in err and "allowed: remove output.impact_window" in err
    assert "Traceback" not in err and not (tmp_path / "run" / "drag_finishing.in").exists()


def test_an_empty_window_turns_the_test_off():
    from orchestrator.case import load_case

    paper = CASES / "drag_finishing_uhlmann2015.toml"
    assert load_case(paper).model.output.impact_window == (0.5, 2.0)
    assert load_case(paper, overrides=["output.impact_window=[]"]).model.output.impact_window is None
    short = load_case(paper, overrides=["process.duration=1.2", "output.network_times=[1.0]"]).model
    assert short.output.impact_window == (0.5, 2.0) and short.impact_window == (0.5, 1.2)  # cut to the process


def test_liggghts_refuses_an_impact_window_where_a_ball_can_touch_rod_and_bowl_side():
    import dataclasses

    from orchestrator.case import load_case
    from orchestrator.errors import OrchestratorError
    from orchestrator.kinds import build_scene
    from orchestrator.kinds.drag_finishing.liggghts_deck import drag_context

    scene = build_scene(load_case(TINY_BOWL).model)
    assert drag_context(scene)["impact_window"] == (0.0, 0.1)
    rod = scene.meshes["rod"].mesh
    wide = rod_mesh(0.009, 0.03, 8)  # a user's mesh wider than workpiece.radius: 6 mm from the bowl's side
    axis = rod_prism(np.asarray(rod.vertices), np.asarray(rod.faces))["axis"]
    wide.apply_translation([axis[0], axis[1], np.asarray(rod.vertices)[:, 2].min()])
    scene.meshes["rod"] = dataclasses.replace(scene.meshes["rod"], mesh=wide)
    with pytest.raises(OrchestratorError, match=r"rod, 6(\.\d+)? mm from the bowl's side, .*allowed: remove"):
        drag_context(scene)


def test_a_frictionless_rod_gets_the_second_selection_for_tip_contacts(tmp_path):
    """With friction a start's force has an x part on the tip too (its tangential part); without, a tip contact
    pushes along z alone, so the deck adds a dump for zero x and non-zero z force. Neither dump is flushed."""
    from orchestrator.case import load_case
    from orchestrator.kinds import build_scene
    from orchestrator.kinds.drag_finishing.liggghts_deck import TEMPLATE, drag_context
    from orchestrator.templating import render

    frictionless = ["contacts=[{pair=['ceramic', 'ceramic'], restitution=0.86, friction=0.34}, "
                    "{pair=['ceramic', 'steel'], restitution=0.68, friction=0.0}]"]
    decks = [render(TEMPLATE, drag_context(build_scene(load_case(TINY_BOWL, overrides=o).model)))
             for o in ([], frictionless)]
    assert "impacts_z" not in decks[0] and decks[0].count("flush no") == decks[0].count("dump impacts ") == 3
    assert decks[1].count("dump impacts_z all custom 1") == decks[1].count("undump impacts_z") == 3
    assert "thresh f_force_walls[1] == 0 thresh f_force_walls[3] != 0" in decks[1]
