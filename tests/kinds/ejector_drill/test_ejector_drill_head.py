"""The drill head's guide pads and cutting edges ([head], kinds/ejector_drill/head.py): where they sit and how much
of the clearance and the front gap they take against the case's keys, their boundary particles' wall points on their
faces, the bad values refused by name, and the flow measured around them (head_flow.py) on a frame whose flow is
set by hand on the drill-head scene's lattice."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest

from orchestrator.case.loader import load_case
from orchestrator.cli import main
from orchestrator.drill.scene import filled_sites
from orchestrator.kinds import build_scene
from orchestrator.kinds.ejector_drill.head import TAU, edge_mouths, edge_solids, pad_solids
from orchestrator.kinds.ejector_drill.head_flow import dead_share, edge_flow, head_finding, pad_flow
from paths import CASES

CASE = CASES / "ejector_drill_canini.toml"


@pytest.fixture(scope="module")
def quick():
    case = load_case(CASE, preset="drill_head_quick").model
    return case, build_scene(case)


def test_pads_and_edge_sit_where_the_keys_put_them(quick):
    """Two pads at 84 and 180 degrees, 5 mm of arc at the bore (19.1 degrees), 12 mm long from the face, across the
    0.875 mm clearance; one 4 mm blade at 0 across the 2 mm front gap from the mouth's rim (6 mm) to the bore, its
    40-degree chip mouth ahead of it (negative angles); the fluid volume is the plain head's less the pads and the
    blade plus the chip mouth, in closed form."""
    case, scene = quick
    pads, edges, mouths = pad_solids(case), edge_solids(case), edge_mouths(case)
    assert [math.degrees(p.mid_angle) for p in pads] == pytest.approx([84.0, 180.0])
    for pad in pads:
        assert pad.span * 15.0e-3 == pytest.approx(5.0e-3)
        assert (pad.r_in, pad.r_out, pad.z_lo, pad.z_hi) == pytest.approx((14.125e-3, 15.0e-3, 0.0, 12.0e-3))
        # 0.5 span (r_b^2 - r_h^2) L = 53.2 mm^3
        assert pad.volume() == pytest.approx(0.5 * (5.0 / 15.0) * (15.0 ** 2 - 14.125 ** 2) * 12.0 * 1e-9, rel=1e-12)
        assert pad.volume() == pytest.approx(50.97e-9, rel=1e-3)
    (edge,), (mouth,) = edges, mouths
    assert math.degrees(edge.mid_angle) == pytest.approx(0.0, abs=1e-12)
    assert math.degrees(edge.span) == pytest.approx(math.degrees(4.0 / 15.0))
    assert (edge.r_in, edge.r_out, edge.z_lo, edge.z_hi) == pytest.approx((6.0e-3, 15.0e-3, -2.0e-3, 0.0))
    assert mouth.a0 + mouth.span == pytest.approx(edge.a0) and math.degrees(mouth.span) == pytest.approx(40.0)
    plain = build_scene(load_case(CASE, preset="drill_head_quick",
                                  overrides=["head.pad_angles=[]", "head.edge_angles=[]"]).model).layout
    expected = plain.fluid_volume() - 2 * pads[0].volume() - edge.volume() + mouth.volume()
    assert scene.layout.fluid_volume() == pytest.approx(expected, rel=1e-12)
    # the lattice: no fluid site inside a pad or the blade; the walls hold a pad's sites within 2h = 1.2 mm of its
    # wetted faces (its sides and ends): the pad less a core (5 mm of arc at its mid radius less 2.4 mm) x (12 mm
    # less 2.4 mm), 59.6 % of it; the blade's, within 2h of its sides, most of its 2 mm of height
    sites = filled_sites(scene.layout, case.numerics.dx, buffers=False)
    reach, dv = 2 * case.numerics.h, case.numerics.dx ** 3
    for pad in pads:
        assert not pad.contains(sites).any()
        arc = pad.span * 0.5 * (pad.r_in + pad.r_out)
        shell = pad.volume() * (1.0 - (1.0 - 2 * reach / arc) * (1.0 - 2 * reach / (pad.z_hi - pad.z_lo)))
        assert shell / pad.volume() == pytest.approx(0.596, abs=0.002)
        # (0.5 % and 6 % here: the 0.875 mm clearance holds two or three lattice layers, depending on the angle)
        assert pad.contains(scene.walls.positions).sum() * dv == pytest.approx(shell, rel=0.1)
    assert not edge.contains(sites).any()
    assert 0.6 < edge.contains(scene.walls.positions).sum() * dv / edge.volume() <= 1.0


def test_the_pads_boundary_particles_have_their_wall_points_on_the_pads_faces(quick):
    """A boundary particle inside a pad takes the nearest point of the pad's wetted faces: its two side faces (at
    the sector's edge angles), its rear end (z = 12 mm) or its front end on the front gap (z = 0), never a point of
    the clearance inside the pad."""
    case, scene = quick
    w = scene.walls
    for pad in pad_solids(case):
        rows = pad.contains(w.positions)
        assert rows.sum() > 100
        q = w.wall_points[rows]
        angle = np.arctan2(q[:, 1], q[:, 0])
        side = np.minimum(*(np.abs(np.mod(angle - a + math.pi, TAU) - math.pi) for a in (pad.a0, pad.a0 + pad.span)))
        end = np.minimum(np.abs(q[:, 2] - pad.z_hi), np.abs(q[:, 2] - pad.z_lo))
        assert np.all((side < 1e-9) | (end < 1e-12))
        d = np.linalg.norm(q - w.positions[rows], axis=1)
        assert d.max() <= 2 * case.numerics.h + 1e-12 and d.min() > 0.0


#: (--set overrides, words the one error line holds) on the drill_head_quick preset (dx 0.4 mm; the head clearance
#: 0.875 mm; the inlet at 16 mm, its prefill from 14 mm; the chip mouth's plane IB at 2.5 mm).
BAD = [
    (["head.pad_height=1.2e-3"], ("head.pad_height = 1.2 mm does not fit in the head clearance", "0.875 mm")),
    (["head.pad_height=0.6e-3"], ("head.pad_height = 0.6 mm leaves 0.275 mm over the pad",)),
    (["head.pad_length=15e-3"], ("head.pad_length = 15 mm", "the inlet's prefill at 14 mm")),
    (["head.pad_angles=[84.0, 95.0]"], ("head.pad_angles = 84 and 95 degrees: the guide pads overlap",)),
    (["head.pad_width=0.3e-3"], ("head.pad_width = 0.3 mm is narrower than numerics.dx",)),
    (["head.edge_mouth_depth=3e-3"], ("head.edge_mouth_depth = 3 mm reaches past the chip mouth's flow plane IB",)),
    (["head.edge_mouth_radius=14e-3"], ("head.edge_mouth_radius = 14 mm must lie between",)),
    (["head.edge_angles=[0.0, 20.0]"], ("head.edge_angles = 0 and 20 degrees", "overlap")),
    (["head.edge_width=0.5e-3"], ("head.edge_width = 0.5 mm at the bore",)),
    (["physics.walls='penalty'"], ("head.pad_angles, head.edge_angles", "physics.walls = 'particles'")),
    (["head.pad_length=-1e-3"], ("head.pad_length",)),
]


@pytest.mark.parametrize("sets, words", BAD, ids=[s[0] for s, _ in BAD])
def test_a_pad_or_edge_that_does_not_fit_is_refused_by_name(sets, words, tmp_path, capsys):
    out = tmp_path / "run"
    argv = ["run", str(CASE), "--preset", "drill_head_quick", *[a for s in sets for a in ("--set", s)], "--out",
            str(out), "--no-progress"]
    start = time.perf_counter()
    code = main(argv)
    text = capsys.readouterr()
    text = text.err + text.out
    assert code == 2, text
    assert "Traceback" not in text and len([line for line in text.splitlines() if line.startswith("error:")]) == 1
    for word in words:
        assert word in text, text
    assert not out.exists() and time.perf_counter() - start < 10.0


def test_a_pad_over_part_of_the_clearance_leaves_a_resolved_gap(quick):
    """pad_height 0.475 mm leaves 0.4 mm (one spacing) over each pad: a fluid sector there, the pad lower."""
    case = load_case(CASE, preset="drill_head_quick", overrides=["head.pad_height=0.475e-3"]).model
    from orchestrator.kinds.ejector_drill.layout import drill_layout

    layout = drill_layout(case)
    over = [r for r in layout.regions if r.name.startswith("over_pad")]
    assert len(over) == 2 and over[0].r_in == pytest.approx(14.6e-3) and over[0].r_out == pytest.approx(15.0e-3)
    assert layout.fluid_volume() == pytest.approx(quick[1].layout.fluid_volume() + 2 * over[0].volume(), rel=1e-12)


def _frame(case, layout, lee: str) -> dict:
    """A frame on the scene's lattice: the clearance flowing down at 10 m/s, the front gap inward at 10 m/s, the
    pads' lee (the front gap's outer ring under them) 'moving' so too, 'still' at rest or 'empty'; 0.5 bar in the two
    spacings in front of the pads' rear ends and 0.2 bar along the blade's rake face, 0 elsewhere."""
    dx = case.numerics.dx
    x = filled_sites(layout, dx, buffers=False)
    r, angle, z = np.hypot(x[:, 0], x[:, 1]), np.arctan2(x[:, 1], x[:, 0]), x[:, 2]
    v = np.zeros_like(x)
    v[z >= 0.0, 2] = -10.0
    inward = z < 0.0
    v[inward, :2] = -10.0 * x[inward, :2] / np.maximum(r[inward], 1e-9)[:, None]
    p = np.zeros(len(x))
    keep = np.ones(len(x), dtype=bool)
    for pad in pad_solids(case):
        mine = np.abs(np.mod(angle - pad.mid_angle + math.pi, TAU) - math.pi) < 0.5 * pad.span
        p[mine & (z >= pad.z_hi) & (z < pad.z_hi + 2 * dx)] = 0.5e5
        lee_sites = mine & (z < 0.0) & (r >= pad.r_in)
        v[lee_sites & (lee == "still")] = 0.0
        keep &= ~(lee_sites & (lee == "empty"))
    edge = edge_solids(case)[0]
    p[(z < 0.0) & (r >= edge.r_in) & (np.mod(edge.a0 - angle, TAU) < 2 * dx / np.maximum(r, dx))] = 0.2e5
    return {"positions": x[keep], "velocities": v[keep], "pressures": p[keep],
            "kind": np.zeros(int(keep.sum()), dtype=np.int8), "attrs": {"time": 1.5e-3}}


def test_the_dead_share_of_a_window():
    """1 less the moving particles' lattice volume over the window's: 100 particles of dx = 0.4 mm in 8 mm^3 leave
    20 %; a window over-full by lattice sampling counts 0, an empty one 1."""
    assert dead_share(100, 0.4e-3, 8.0e-9) == pytest.approx(0.2)
    assert dead_share(130, 0.4e-3, 8.0e-9) == 0.0 and dead_share(0, 0.4e-3, 8.0e-9) == 1.0


@pytest.mark.parametrize("lee", ["still", "empty"])
def test_the_flow_at_the_pads_and_the_edge_is_measured_where_it_was_put(quick, lee):
    """pad_flow finds the 10 m/s approach (0.5 bar of 1/2 rho v^2), the 0.5 bar set before each pad's rear end, the
    10 m/s past the pads, their lee dead (still or empty) against the open window full of moving fluid (within the
    lattice's sampling of the 0.875 mm ring); edge_flow the 0.2 bar across the blade and its faces' and the front
    gap's moving fluid; the finding names the dead zone, and none once the lee moves."""
    case, scene = quick
    frame = _frame(case, scene.layout, lee)
    pads, edges = pad_flow(case, frame), edge_flow(case, frame)
    assert pads["approach"] == pytest.approx(10.0) and pads["dynamic"] == pytest.approx(0.5e5)
    assert pads["rise"] == pytest.approx([0.5e5, 0.5e5]) and pads["past"] == pytest.approx([10.0, 10.0])
    assert pads["wake_dead"] == pytest.approx([1.0, 1.0]) and pads["open_dead"] < 0.1
    assert edges["jump"] == pytest.approx([0.2e5]) and edges["face_dead"][0] < 0.1 and edges["gap_dead"] < 0.1
    assert edges["mouth_speed"] == pytest.approx([10.0])
    text = head_finding(case, frame)
    assert "by 0.5 bar (1 x the 1/2 rho v^2 of the clearance's 10 m/s), the flow passes them at 10 m/s" in text
    assert "no moving fluid on up to 100 % of its volume" in text and "a dead zone beyond the open flow's own" in text
    moving = _frame(case, scene.layout, "moving")
    assert max(pad_flow(case, moving)["wake_dead"]) < 0.1
    assert "no dead zone beyond the open flow's own by more than 10 points" in head_finding(case, moving)


def test_analyze_prints_the_table_and_the_finding_and_draws_the_sections(quick, tmp_path, capsys):
    """print_head_flow prints a row per frame and the finding; draw_head_sections draws the picture time 1.5 ms and
    the last frame, 2.5 ms (a resumed run's), and nothing for a head without pads and edges."""
    from orchestrator.kinds.ejector_drill.analysis import print_head_flow
    from orchestrator.kinds.ejector_drill.pictures import draw_head_sections

    case, scene = quick
    first, last = _frame(case, scene.layout, "moving"), _frame(case, scene.layout, "empty")
    last = {**last, "attrs": {"time": 2.5e-3}}
    frames = {"3": first, "5": last}
    print_head_flow(case, frames)
    text = capsys.readouterr().out
    assert "   1.5     10    0.5  0.5/0.5" in text and "   2.5     10    0.5  0.5/0.5" in text
    assert "finding: at 2.5 ms the guide pads raise the pressure" in text
    drawn = draw_head_sections(frames, case, lambda name: tmp_path / f"{name}.png")
    assert sorted(drawn) == ["head_sections_1.50ms", "head_sections_2.50ms"]
    assert all(path.stat().st_size > 50_000 for path in drawn.values())
    plain = load_case(CASE, preset="drill_head_quick", overrides=["head.pad_angles=[]", "head.edge_angles=[]"]).model
    assert draw_head_sections(frames, plain, lambda name: tmp_path / f"{name}.png") == {}
