"""Contact chains (analysis.contact_chains), rod contact intensity (analysis.contact_intensity) and their
report and pictures (plots_chains), on snapshots built so that the answer is known."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orchestrator.kinds.drag_finishing.chains import (angle_to_velocity, binned_mean, chain_strength, conditional_means,
                                                  find_chains, force_peaks, lagged_correlation, peak_coincidence,
                                                  rod_pose, strong_threshold)
from orchestrator.kinds.drag_finishing.intensity import (approach_speeds, nearest_facet, point_triangle_distance,
                                                     sector_sums)

R_BALL = 0.003  # m
R_ROD = 0.005  # m
AXIS = np.array([0.02, 0.0])  # the rod axis at process time 0 (angle 0 on a 20 mm path): v_w = +y, outwards = +x
ALPHA, BETA = math.radians(30.0), math.radians(20.0)  # column: 30 deg downwards, 20 deg outwards of v_w
DIRECTION = np.array([math.sin(BETA) * math.cos(ALPHA), math.cos(BETA) * math.cos(ALPHA), -math.sin(ALPHA)])
F_CHAIN, F_WEAK = 1.0, 0.1  # N


class Snapshot:
    """A contact snapshot built contact by contact (point1 = ball centre, point2 = other centre or wall point)."""

    def __init__(self):
        self.rows: list[tuple] = []

    def add(self, id1, id2, role, p1, p2, fn, force_on_2=None):
        p1, p2 = np.asarray(p1, float), np.asarray(p2, float)
        unit = (p2 - p1) / np.linalg.norm(p2 - p1)
        self.rows.append((id1, id2, role, p1, p2, fn, fn * unit if force_on_2 is None else force_on_2))

    def arrays(self) -> dict:
        id1, id2, role, p1, p2, fn, vec = zip(*self.rows)
        return {"id1": np.array(id1), "id2": np.array(id2), "body2_role": np.array(role, dtype=np.int8),
                "point1": np.array(p1), "point2": np.array(p2), "normal_force": np.array(fn),
                "normal_force_vector": np.array(vec), "tangential_force": np.zeros((len(fn), 3)),
                "attrs": {"time": 1.0, "process_time": 0.0}}


def column_snapshot(broken: bool = False, detour: bool = False) -> tuple[dict, np.ndarray]:
    """Four balls in a straight column from the rod (z = 40 mm) to the bowl, 1 N per contact, and 30 weak
    (0.1 N) contacts among 20 balls off to the side, two weak rod contacts behind the rod and two weak
    bowl contacts. broken: the column's middle contact is weak; detour: a longer strong route
    ball 0 -> 10 -> 11 -> bowl besides. Returns (snapshot, ball centres)."""
    s = Snapshot()
    start = np.array([*AXIS, 0.04]) + R_ROD * DIRECTION  # the rod contact point (rod taken as locally spherical)
    centres = start + (R_BALL + 2 * R_BALL * np.arange(4))[:, None] * DIRECTION
    s.add(0, 900, 2, centres[0], start, F_CHAIN, force_on_2=-F_CHAIN * DIRECTION)
    for i in range(3):
        s.add(i, i + 1, 0, centres[i], centres[i + 1], F_WEAK if broken and i == 1 else F_CHAIN)
    s.add(3, 800, 1, centres[3], centres[3] + R_BALL * DIRECTION, F_CHAIN)
    side = np.array([-0.02, -0.02, 0.01]) + np.arange(20)[:, None] * np.array([0.0, 0.002, 0.001])
    for k in range(30):
        i, j = 20 + k % 20, 20 + (k * 7 + 3) % 20
        if i != j:
            s.add(i, j, 0, side[i - 20], side[j - 20], F_WEAK)
    back = np.array([*AXIS, 0.03]) - np.array([0.0, R_ROD, 0.0])
    for i, z in ((20, 0.03), (21, 0.05)):
        s.add(i, 901, 2, back + [0, -R_BALL, z - 0.03], back + [0, 0, z - 0.03], 0.05,
              force_on_2=np.array([0.0, 0.05, 0.0]))  # pushes the rod forwards
    s.add(22, 801, 1, side[2], side[2] + [0, 0, -R_BALL], F_WEAK)
    s.add(23, 802, 1, side[3], side[3] + [0, 0, -R_BALL], F_WEAK)
    if detour:
        turn = centres[0] + 2 * R_BALL * np.array([1.0, 0.0, 0.0])
        far = turn + 2 * R_BALL * DIRECTION
        s.add(0, 10, 0, centres[0], turn, F_CHAIN)
        s.add(10, 11, 0, turn, far, F_CHAIN)
        s.add(11, 803, 1, far, far + 10 * R_BALL * DIRECTION, F_CHAIN)
    return s.arrays(), centres


def test_one_straight_column_is_one_chain_of_known_length_orientation_and_share():
    snap, _ = column_snapshot()
    fn = snap["normal_force"]
    assert strong_threshold(fn) == pytest.approx(fn.mean() + fn.std(), rel=1e-12)
    assert F_WEAK < strong_threshold(fn) < F_CHAIN
    axis, vw = rod_pose(0.0, 0.02, 0.01)
    np.testing.assert_allclose(axis, AXIS, atol=1e-15)
    np.testing.assert_allclose(vw, [0.0, 1.0], atol=1e-15)
    c = find_chains(snap, vw=vw)
    assert c["n_strong"] == 5 and c["n_chains"] == 1
    assert c["n_contacts"].tolist() == [5]  # rod, three ball-ball, bowl
    assert c["path_length"][0] == pytest.approx(8 * R_BALL, rel=1e-9)  # 3 + 6 + 6 + 6 + 3 mm
    assert c["span"][0] == pytest.approx(8 * R_BALL, rel=1e-9)
    assert c["angle_to_vw"][0] == pytest.approx(20.0, abs=1e-9)  # outwards of v_w
    assert c["elevation"][0] == pytest.approx(-30.0, abs=1e-9)
    assert c["angle_xy"][0] == pytest.approx(70.0, abs=1e-9)
    assert c["angle_xz"][0] == pytest.approx(math.degrees(math.atan2(DIRECTION[2], DIRECTION[0])), abs=1e-9)
    assert c["share"] == pytest.approx(1.0 / 1.1, rel=1e-12)  # 1 N of the rod's 1 + 2 x 0.05 N
    along = math.cos(BETA) * math.cos(ALPHA)  # the chain's force along v_w against the rod, N
    assert c["share_fn"] == pytest.approx(along / (along - 0.1), rel=1e-12)
    assert c["contacts"][0].tolist() == [0, 1, 2, 3, 4]


def test_broken_column_has_no_chain_and_the_shortest_route_is_taken():
    broken = find_chains(column_snapshot(broken=True)[0], vw=np.array([0.0, 1.0]))
    assert broken["n_chains"] == 0 and broken["n_strong"] == 4
    assert broken["share"] == 0.0
    detour = find_chains(column_snapshot(detour=True)[0], vw=np.array([0.0, 1.0]))
    assert detour["n_chains"] == 1 and detour["path_length"][0] == pytest.approx(8 * R_BALL, rel=1e-9)
    # an absolute threshold above the column's force leaves nothing strong
    assert find_chains(column_snapshot()[0], threshold=1.5)["n_chains"] == 0


def test_chain_strength_is_the_bottleneck_of_the_widest_rod_to_bowl_path():
    assert chain_strength(column_snapshot()[0]) == pytest.approx(F_CHAIN)
    # broken: the column's weak 0.1 N link beats the weak side route (0.05 N at the rod)
    assert chain_strength(column_snapshot(broken=True)[0]) == pytest.approx(F_WEAK)
    snap = column_snapshot(broken=True)[0]
    snap["normal_force"][snap["body2_role"] == 1] = -1.0  # no compressive contact on the bowl: no path
    assert chain_strength(snap) == 0.0
    # under any threshold T a chain exists exactly when B > T
    rng = np.random.default_rng(7)
    for _ in range(20):
        s = column_snapshot(broken=bool(rng.integers(2)), detour=bool(rng.integers(2)))[0]
        s["normal_force"] = s["normal_force"] * rng.uniform(0.3, 1.7, len(s["normal_force"]))
        b = chain_strength(s)
        for thr in (0.5 * b, 0.999 * b, 1.001 * b, 0.05, 0.3):
            assert (find_chains(s, threshold=thr)["n_chains"] > 0) == (b > thr)


def test_conditional_means_peaks_coincidence_and_lag():
    cond = conditional_means(np.array([-3.0, -3.2, -1.0, -1.2, -1.4]), np.array([1, 1, 0, 0, 0], bool))
    assert cond["with_mean"] == pytest.approx(-3.1) and cond["without_mean"] == pytest.approx(-1.2)
    assert (cond["with_n"], cond["without_n"]) == (2, 3)
    assert cond["with_std"] == pytest.approx(math.sqrt(0.02))

    t = np.arange(0.0, 4.0, 0.005)
    drag = 2.0 + sum(1.5 * np.exp(-(((t - c) / 0.02) ** 2)) for c in (1.0, 2.0, 3.0))
    drag[(t > 2.495) & (t < 2.515)] = 3.0  # two threshold crossings 0.01 s apart: one peak
    drag[(t > 2.519) & (t < 2.53)] = 3.2
    times, values, thr = force_peaks(t, drag)
    assert thr == pytest.approx(drag.mean() + drag.std())
    np.testing.assert_allclose(times, [1.0, 2.0, 2.52, 3.0], atol=1e-9)
    np.testing.assert_allclose(values, [3.5, 3.5, 3.2, 3.5], atol=1e-9)

    t_snap = np.arange(0.0, 4.0, 0.05)
    has = np.isin(np.round(t_snap, 3), [1.0, 3.0])
    co = peak_coincidence(times, t_snap, has)
    assert co["n_peaks"] == 4 and co["fraction"] == pytest.approx(0.5) and co["window"] == pytest.approx(0.025)
    assert co["base_rate"] == pytest.approx(2 / 80)

    signal = np.sin(2 * np.pi * t / 1.3)
    counts = np.sin(2 * np.pi * (t_snap + 0.1) / 1.3)  # the signal follows the counts by 0.1 s
    lags = np.arange(-40, 41) * 0.005
    r = lagged_correlation(t_snap, counts, t, signal, lags)
    assert lags[np.nanargmax(r)] == pytest.approx(0.1, abs=1e-9)
    assert np.nanmax(r) == pytest.approx(1.0, abs=1e-4)


def test_force_against_angle_to_vw_and_height():
    pts = np.array([[0.02, 0.01, 0.0], [0.02, -0.01, 0.0], [0.03, 0.0, 0.0], [0.02 + 0.01, 0.01, 0.0]])
    np.testing.assert_allclose(angle_to_velocity(pts, AXIS, np.array([0.0, 1.0])), [0.0, 180.0, 90.0, 45.0],
                               atol=1e-9)
    mean, std, count = binned_mean(np.array([5.0, 15.0, 25.0, 35.0]), np.array([1.0, 2.0, 3.0, 5.0]),
                                   np.array([0.0, 20.0, 40.0]))
    np.testing.assert_allclose(mean, [1.5, 4.0])
    np.testing.assert_allclose(std, [0.5, 1.0])
    assert count.tolist() == [2, 2]


def test_facet_mapping_distances_sectors_and_approach_speeds():
    tri = np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
                    [[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]]])
    pts = np.array([[0.2, 0.2, 0.3], [2.0, 0.0, 0.0], [0.2, 0.2, 0.9]])
    d = point_triangle_distance(pts, tri)
    np.testing.assert_allclose(d[:, 0], [0.3, 1.0, 0.9], atol=1e-12)
    np.testing.assert_allclose(d[1, 1], math.sqrt(2.0), atol=1e-12)
    vertices, faces = tri.reshape(-1, 3), np.arange(6).reshape(2, 3)
    assert nearest_facet(pts, vertices, faces).tolist() == [0, 0, 1]
    sums = sector_sums(np.array([0.0, 44.0, 90.0, 180.0, -170.0, -90.0]), np.array([1.0, 2.0, 4.0, 8.0, 16.0, 32.0]))
    assert sums == {"front": 3.0, "outer side": 4.0, "back": 24.0, "inner side": 32.0}

    omega = 0.5  # rad/s; the rod surface at x = 0.0275 m moves at +y 13.75 mm/s
    positions = np.array([[AXIS[0] + R_ROD + R_BALL + 1e-4, 0.0, 0.04],  # 0.1 mm off, approaching at 20 mm/s
                          [AXIS[0] + R_ROD + R_BALL + 1e-4, 0.0, 0.04],  # moving with the rod: no approach
                          [AXIS[0] + R_ROD + R_BALL + 2e-3, 0.0, 0.04],  # too far
                          [AXIS[0] + R_ROD + R_BALL + 1e-4, 0.0, 0.001]])  # below the tip
    velocities = np.array([[-0.02, 0.0, 0.0], [0.0, omega * positions[1, 0], 0.0], [-0.02, 0.0, 0.0],
                           [-0.02, 0.0, 0.0]])
    speeds = approach_speeds(positions, np.full(4, R_BALL), velocities, AXIS, omega, R_ROD, (0.01, 1.0), 3e-4)
    np.testing.assert_allclose(speeds, [0.02], atol=1e-12)


def test_analyze_prints_chains_and_intensity_on_the_synthetic_run(synthetic_run, capsys):
    from orchestrator.report import analyze_run

    analyze_run(synthetic_run, render=False)
    out = capsys.readouterr().out
    fn = np.linspace(0.05, 1.2, 14)
    fn[3], fn[9] = -0.01, 0.0
    comp = fn[fn > 0]
    assert "contact chains (1 snapshot): strong contact = normal force > mean + 1 std" in out
    assert f"strong threshold {comp.mean() + comp.std():.4f} N" in out
    assert "chains per snapshot 0.00 (min 0, max 0)" in out  # the random contacts link no rod ball to the bowl
    assert "without -2.469 N (n 1)" in out  # F_n of the series at the snapshot (0.15 s of process)
    assert "correlation and peak coincidence need a series of snapshots" in out
    assert "sum |F| dt = 0.320 N s over 32 facets" in out  # linspace(0, 0.02, 32).sum()
    assert "snapshots: 2 rod contacts" in out and "largest contact normal force 1.200 N" in out


def test_pictures_of_a_column_and_of_the_synthetic_run(tmp_path, synthetic_run):
    from orchestrator.kinds.drag_finishing.plots_chains import plot_chain_network, report_chains
    from orchestrator.runh5 import read_run, stored_case

    snap, _ = column_snapshot()
    axis, vw = rod_pose(0.0, 0.02, 0.01)
    chains = dict(find_chains(snap, vw=vw), axis=axis, vw=vw, snapshot=snap)
    path = plot_chain_network(chains, 0.042, R_ROD, 0.02, 0.07, tmp_path / "chains.png")
    assert path.stat().st_size > 20_000
    run = read_run(synthetic_run)
    out = report_chains(synthetic_run, run, stored_case(run, synthetic_run), render=True)
    assert sorted(out) == ["chain_fn", "chains", "profiles", "rod_3d", "rod_map"]  # one snapshot: no peak view
    for name, file in out.items():
        assert file.parent == synthetic_run and file.stat().st_size > 5_000, name


def test_summary_file_keeps_identity_measured_and_report(synthetic_run, tmp_path, capsys):
    import json

    from orchestrator.cli import main
    from orchestrator.runh5 import read_run

    path = tmp_path / "kept" / "summary.json"
    assert main(["analyze", str(synthetic_run), "--no-render", "--summary", str(path)]) == 0
    out = capsys.readouterr().out
    data = json.loads(path.read_text())
    run = read_run(synthetic_run)
    assert data["run"]["engine"] == "synthetic" and data["run"]["n_particles"] == run["attrs"]["n_particles"]
    assert data["measured"]["fn_mean"] == pytest.approx(run["measured"]["attrs"]["fn_mean"], rel=1e-15)
    assert "[case]" in data["case"] and 'name = "tiny_bowl"' in data["case"]
    assert any(line.startswith("contact chains (1 snapshot)") for line in data["report"])
    assert "\n".join(data["report"]) in out and f"summary  {path}" in out
    blocked = tmp_path / "a_file"
    blocked.write_text("")
    assert main(["analyze", str(synthetic_run), "--no-render", "--summary", str(blocked / "s.json")]) == 2
    err = capsys.readouterr().err
    assert f"--summary {blocked} is a file, not a folder" in err and "Traceback" not in err
