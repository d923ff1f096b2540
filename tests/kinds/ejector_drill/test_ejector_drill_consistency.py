"""The drill kinds' geometric consistency, refused before anything is built: neighbouring adduction holes and
ejector nozzles must not overlap (the count is bounded by the passages' size, so no count reaches the wall builder),
every passage the scene holds is at least MIN_SPACINGS_ACROSS lattice spacings across, and the feed scene is the kind
ejector_feed. Bad input gives one 'error:' line naming the key and exit code 2; the passages' spacing against a
brute-force test of two neighbouring cylinders."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest

from orchestrator.case.loader import load_case
from orchestrator.cli import main
from orchestrator.drill.case import MIN_SPACINGS_ACROSS
from orchestrator.drill.geometry import most_passages, widest_passage
from paths import CASES

DRILL, FEED = CASES / "ejector_drill_canini.toml", CASES / "ejector_feed_canini.toml"

#: (case file, preset, --set overrides, words the error holds). The case file's drill: groove_depth 1 mm, so the
#: holes leave the groove's outer wall at r = 11 mm; the nozzles leave the inner tube's bore at r = 8 mm, 30 deg
#: rearward; the quick presets' dx: flow_exit_quick 0.5 mm, feed_quick 0.4 mm.
BAD = [
    (DRILL, "flow_exit_quick", ["drill.n_holes=30"],
     ("drill.n_holes = 30", "adduction holes overlap", "allowed: n_holes <= 17", "d_hole <= 2.312 mm")),
    (DRILL, "flow_exit_quick", ["drill.n_holes=1000"], ("drill.n_holes = 1000", "allowed: n_holes <= 17")),
    (DRILL, "drill_head_quick", ["drill.n_holes=18"], ("drill.n_holes = 18",)),
    (DRILL, "flow_exit_quick", ["drill.d_hole=0.1e-3"],
     ("drill.d_hole = 0.1 mm is 0.2 particle spacings across", "allowed: drill.d_hole >= 1.25 mm")),
    (DRILL, "flow_exit_quick", ["drill.d_hole=1.2e-3"], ("drill.d_hole = 1.2 mm is 2.4 particle spacings",)),
    (DRILL, "flow_exit_quick", ["scene.area='feed'"], ("scene.area", "the kind ejector_feed")),
    (FEED, "feed_quick", ["drill.n_ejector_nozzles=80"],
     ("drill.n_ejector_nozzles = 80", "ejector nozzles overlap", "allowed: n_ejector_nozzles <= 50")),
    (FEED, "feed_quick", ["drill.d_ejector_nozzle=0.5e-3"],
     ("drill.d_ejector_nozzle = 0.5 mm is 1.25 particle spacings across",)),
    (FEED, "feed_quick", ["scene.back_pressure=1e5"], ("scene.back_pressure: unknown key",)),
    (FEED, "feed_quick", ["scene.area='feed'"], ("scene.area: unknown key",)),
]


@pytest.mark.parametrize("path, preset, sets, words", BAD, ids=[f"{p.stem}-{s[0]}" for p, _, s, _ in BAD])
def test_bad_geometry_is_refused_with_the_key_named(path, preset, sets, words, tmp_path, capsys):
    out = tmp_path / "run"
    argv = ["run", str(path), "--preset", preset, *[a for s in sets for a in ("--set", s)], "--out", str(out),
            "--no-progress"]
    start = time.perf_counter()
    code = main(argv)
    took = time.perf_counter() - start
    text = capsys.readouterr()
    text = text.err + text.out
    assert code == 2, text
    assert "Traceback" not in text and len([line for line in text.splitlines() if line.startswith("error:")]) == 1
    for word in words:
        assert word in text, text
    assert not out.exists() and took < 10.0  # refused before the scene (its walls take seconds to minutes)


def test_the_limits_themselves_are_accepted():
    """A hole 2.5 spacings across, the most holes of the case's size that fit, a drill-head scene (which holds no
    holes) with narrow ones, the coarsest measured feed (2.5 spacings across a nozzle) all load."""
    assert MIN_SPACINGS_ACROSS == 2.5
    load_case(DRILL, preset="flow_exit_quick", overrides=["drill.d_hole=1.25e-3"])
    load_case(DRILL, preset="flow_exit_quick", overrides=["drill.n_holes=17"])
    load_case(DRILL, preset="drill_head_quick", overrides=["drill.d_hole=0.5e-3"])
    case = load_case(FEED, preset="feed_quick").model
    assert case.network().d_ejector_nozzle / case.numerics.dx == pytest.approx(2.5)


def _overlap(count: int, r: float, tilt: float, d: float) -> bool:
    """Brute force: do two neighbouring cylinders of diameter d overlap? Both axes leave the drill axis at one point
    (the apex), tilted `tilt` out of the cross-section, 2 pi / count apart in azimuth; each cylinder starts where its
    axis reaches radius r. Points sampled in the axes' plane around their bisector, where the cylinders meet first."""
    axes = [np.array([math.cos(a) * math.cos(tilt), math.sin(a) * math.cos(tilt), math.sin(tilt)])
            for a in (0.0, 2 * math.pi / count)]
    start = r / math.cos(tilt)
    along = (axes[0] + axes[1]) / np.linalg.norm(axes[0] + axes[1])
    across = (axes[0] - axes[1]) / np.linalg.norm(axes[0] - axes[1])
    u, v = np.meshgrid(np.linspace(start, 3 * start, 4001), np.linspace(-d, d, 81), indexing="ij")
    points = u.reshape(-1, 1) * along + v.reshape(-1, 1) * across
    inside = []
    for axis in axes:
        s = points @ axis
        inside.append((s >= start) & (np.linalg.norm(points - np.outer(s, axis), axis=1) < 0.5 * d))
    return bool(np.any(inside[0] & inside[1]))


@pytest.mark.parametrize("count, r, tilt", [(3, 11e-3, 0.0), (16, 11e-3, 0.0), (6, 8e-3, math.radians(30.0)),
                                            (50, 8e-3, math.radians(30.0))])
def test_the_widest_passage_is_where_neighbours_touch(count, r, tilt):
    """widest_passage: 2 r tan(pi / count) for radial holes; neighbours 1 % narrower stay apart and 1 % wider
    overlap (brute force); most_passages inverts it."""
    d = widest_passage(count, r, tilt)
    if tilt == 0.0:
        assert d == pytest.approx(2 * r * math.tan(math.pi / count), rel=1e-12)
    assert not _overlap(count, r, tilt, 0.99 * d) and _overlap(count, r, tilt, 1.01 * d)
    assert most_passages(d * (1 - 1e-9), r, tilt) == count and most_passages(1.01 * d, r, tilt) == count - 1
