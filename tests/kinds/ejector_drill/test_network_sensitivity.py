"""The 1D network's sensitivity study (`orchestrator network-sensitivity`): its base point is the network's own
solution, a changed parameter is the network solved with that value, the feed pressure moves the way the hydraulics
say, the factors for the paper's 10-20 bar put the feed there, the map holds the band, and bad input is refused
with one error line."""

import csv
import dataclasses
import json
import math

import numpy as np
import pytest
from paths import CASES

from orchestrator.case.loader import load_case
from orchestrator.cli import main
from orchestrator.kinds.ejector_drill import sensitivity as study
from orchestrator.reference.drill_network import LITRE_PER_MIN, solve

CASE = CASES / "ejector_drill_canini.toml"
FLOW = 60.0  # l/min, the paper's standard rate
FACTORS = (0.5, 0.75, 1.0, 1.5, 2.0)


@pytest.fixture(scope="module")
def net():
    return load_case(CASE).model.network()


def _p_feed(network, flow=FLOW):
    return solve(network, flow * LITRE_PER_MIN).gauge_bar("p_feed")


def test_the_base_point_is_the_networks_own_solution(net):
    base, state = study.solve_point(net, FLOW), solve(net, FLOW * LITRE_PER_MIN)
    assert base.p_feed_bar == pytest.approx(state.gauge_bar("p_feed"), rel=1e-12)
    assert base.V_loss == pytest.approx(state.litres_per_min("V_loss"), rel=1e-12)
    assert base.V_EN == pytest.approx(state.litres_per_min("V_EN"), rel=1e-12)
    # the case's network at 60 l/min: 30.1 bar at the feed, the ejector drawing 6.5 l/min from the bore mouth
    assert base.p_feed_bar == pytest.approx(30.14, abs=0.05)
    assert base.V_loss == pytest.approx(-6.47, abs=0.05)
    assert base.buildable and not base.cavitating
    for name in study.BY_NAME:  # factor 1 changes nothing, derived parameters included
        assert study.solve_point(net, FLOW, name, 1.0).p_feed_bar == pytest.approx(base.p_feed_bar, rel=1e-9)


@pytest.mark.parametrize("name, factor, changes", [
    ("d_diff", 1.5, {"d_diff": 1.5e-3}),
    ("n_ejector_nozzles", 2.0, {"n_ejector_nozzles": 12}),
    ("n_ejector_nozzles", 0.75, {"n_ejector_nozzles": 5}),  # 4.5 nozzles round to 5
    ("d_ejector_nozzle", 1.5, {"d_ejector_nozzle": 1.5e-3}),
    ("tube_length", 0.5, {"tube_length": 0.2}),
    ("nozzle_cd", 0.75, {"k_primary": 1.0 / (0.75 / math.sqrt(1.1)) ** 2 - 1.0}),
    ("tube_bore", 0.75, {"d_outer_tube_id": 15e-3, "d_outer_tube_od": 19e-3, "d_inner_tube_id": 11e-3}),
    ("head_clearance", 2.0, {"d_head_body": 30e-3 - 4 * 0.875e-3}),
])
def test_a_scanned_point_is_the_network_solved_with_that_value(net, name, factor, changes):
    point = study.solve_point(net, FLOW, name, factor)
    direct = _p_feed(dataclasses.replace(net, **changes))
    assert point.p_feed_bar == pytest.approx(direct, rel=1e-9)
    assert point.buildable


def test_the_case_values_and_the_scan_read_back(net):
    assert study.parameter_value(net, "nozzle_cd") == pytest.approx(1 / math.sqrt(1.1), rel=1e-12)
    assert study.parameter_value(net, "head_clearance") == pytest.approx(0.875e-3, rel=1e-9)
    points = study.one_at_a_time(net, FLOW, (0.5, 2.0), ["d_diff", "mu"])
    assert [(p.parameter, p.factor) for p in points] == [("d_diff", 0.5), ("d_diff", 2.0), ("mu", 0.5), ("mu", 2.0)]
    assert points[0].value == pytest.approx(0.5e-3) and points[3].value == pytest.approx(2e-3)


@pytest.mark.parametrize("name, sign", [
    ("d_diff", -1), ("n_ejector_nozzles", -1), ("d_ejector_nozzle", -1), ("d_hole", -1), ("cd_hole", -1),
    ("tube_length", +1), ("mu", +1), ("roughness", +1),
])
def test_the_feed_pressure_moves_the_way_the_hydraulics_say(net, name, sign):
    """A wider passage or more of them lowers the feed pressure; a longer or rougher tube or a thicker coolant raises
    it (over the buildable factors; Cd above 1 is not)."""
    points = [study.solve_point(net, FLOW, name, f) for f in FACTORS]
    p = np.array([pt.p_feed_bar for pt in points if pt.buildable])
    assert len(p) >= 4
    assert np.all(sign * np.diff(p) > 0.0), (name, p)


def test_the_gap_and_the_nozzles_carry_the_feed_pressure(net):
    """The annular gap halved nearly triples the feed pressure (88 bar), doubled it leaves 10 bar, the ejector then
    leaking 16 l/min; doubled nozzle diameter 7 bar; the drilled depth and the guide pads move it under 0.1 bar."""
    gap = {f: study.solve_point(net, FLOW, "d_diff", f) for f in (0.5, 2.0)}
    assert gap[0.5].p_feed_bar == pytest.approx(88.4, abs=0.3)
    assert gap[2.0].p_feed_bar == pytest.approx(10.4, abs=0.1) and gap[2.0].V_loss == pytest.approx(16.3, abs=0.2)
    assert study.solve_point(net, FLOW, "d_ejector_nozzle", 2.0).p_feed_bar == pytest.approx(7.0, abs=0.1)
    base = study.solve_point(net, FLOW).p_feed_bar
    for name in ("bore_depth", "pad_blockage", "k_secondary"):
        assert all(abs(study.solve_point(net, FLOW, name, f).p_feed_bar - base) < 0.1 for f in (0.5, 2.0))


def test_geometry_that_cannot_be_built_is_marked(net):
    wide = study.solve_point(net, FLOW, "tube_bore", 1.5)  # a 34 mm outer tube in the 30 mm bore
    assert not wide.buildable and "wider than the bore" in wide.note
    cd = study.solve_point(net, FLOW, "nozzle_cd", 1.5)
    assert not cd.buildable and "above 1" in cd.note and math.isfinite(cd.p_feed_bar)


def test_the_band_edges_put_the_feed_at_10_and_20_bar(net):
    edges = {(e.parameter, e.target_bar): e for e in study.band_edges(net, FLOW, ["n_ejector_nozzles", "d_diff"])}
    for (name, target), e in edges.items():
        p = study.solve_point(net, FLOW, name, e.factor, whole_counts=False)
        assert p.p_feed_bar == pytest.approx(target, abs=1e-3)
    # the nozzles' area x1.65-3.07 reaches the band with the ejector drawing; the gap alone only leaking
    assert edges["n_ejector_nozzles", 20.0].factor == pytest.approx(1.654, abs=0.005)
    assert edges["n_ejector_nozzles", 10.0].factor == pytest.approx(3.07, abs=0.01)
    assert edges["n_ejector_nozzles", 20.0].V_loss < -10.0 and edges["n_ejector_nozzles", 10.0].V_loss < -10.0
    assert edges["d_diff", 20.0].value == pytest.approx(1.267e-3, rel=0.005) and edges["d_diff", 20.0].V_loss > 0.0
    assert math.isnan(study.factor_for(net, FLOW, "bore_depth", 20.0))


def test_the_flows_at_the_band_edges(net):
    q20 = study.flow_for(net, 20.0)
    assert q20 == pytest.approx(48.4, abs=0.1) and _p_feed(net, q20) == pytest.approx(20.0, abs=1e-3)
    assert study.flow_for(net, 10.0) == pytest.approx(33.5, abs=0.1)


def test_the_map_holds_the_base_point_and_the_band(net):
    m = study.area_gap_map(net, FLOW, [0.5, 1.0, 2.0, 3.0], [0.75e-3, 1.0e-3, 1.5e-3])
    base = study.solve_point(net, FLOW)
    assert m.p_feed_bar[1, 1] == pytest.approx(base.p_feed_bar, rel=1e-9)
    assert m.base_area == pytest.approx(6 * 0.25 * math.pi * 1e-6) and m.areas[2] == pytest.approx(2 * m.base_area)
    band = study.in_band(m)
    assert band[1, 2] and band[1, 3] and not band[1, 1]  # at d_Diff = 1 mm: area x2 and x3 in, the case out
    assert np.all((m.p_feed_bar[band] >= 10.0) & (m.p_feed_bar[band] <= 20.0) & (m.V_loss[band] < 0.0))
    p = np.where(m.buildable, m.p_feed_bar, np.nan)
    assert np.all(np.diff(p, axis=1) < 0.0) and np.all(np.diff(p, axis=0) < 0.0)


def test_the_command_writes_its_tables_and_pictures(tmp_path, capsys):
    out = tmp_path / "study"
    code = main(["network-sensitivity", str(CASE), "--factors", "0.5,2", "--parameters", "d_diff,n_ejector_nozzles",
                 "--map-points", "6", "--out", str(out)])
    text = capsys.readouterr().out
    assert code == 0 and "p_feed [bar gauge] at 60 l/min" in text and "annular gap d_Diff" in text
    rows = list(csv.DictReader((out / "network_sensitivity.csv").open()))
    assert [(r["parameter"], float(r["factor"])) for r in rows] == [
        ("d_diff", 0.5), ("d_diff", 2.0), ("n_ejector_nozzles", 0.5), ("n_ejector_nozzles", 2.0)]
    assert float(rows[1]["p_feed_bar"]) == pytest.approx(10.43, abs=0.02) and float(rows[1]["value"]) == 2.0
    result = json.loads((out / "network_sensitivity.json").read_text())
    assert result["base"]["p_feed_bar"] == pytest.approx(30.14, abs=0.05)
    assert len(list(csv.DictReader((out / "network_map.csv").open()))) == 36
    for png in ("network_sensitivity.png", "network_map.png"):
        assert (out / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("argv, words", [
    (["--factors", "abc"], "--factors 'abc'"),
    (["--factors", "1"], "other than 1"),
    (["--factors=-0.5"], "numbers above 0"),
    (["--flow", "0"], "--flow 0"),
    (["--flow", "inf"], "--flow inf"),
    (["--parameters", "nozzle_count"], "unknown nozzle_count"),
    (["--map-points", "1"], "--map-points 1"),
])
def test_bad_input_is_one_error_line(tmp_path, capsys, argv, words):
    out = tmp_path / "never"
    assert main(["network-sensitivity", str(CASE), *argv, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error:") and words in err[0]
    assert not out.exists()


def test_json_reports_what_did_not_solve_as_null(tmp_path, capsys):
    code = main(["network-sensitivity", str(CASE), "--parameters", "tube_bore", "--factors", "0.75,1.5",
                 "--map-points", "0", "--json", "--out", str(tmp_path / "j")])
    result = json.loads(capsys.readouterr().out)
    assert code == 0 and result["flow_lpm"] == 60.0
    narrow, wide = result["points"]
    assert narrow["p_feed_bar"] == pytest.approx(41.05, abs=0.05) and narrow["note"] == ""
    assert wide["p_feed_bar"] is None and "wider than the bore" in wide["note"]
    assert result["flows_for_band_lpm"]["20"] == pytest.approx(48.35, abs=0.05)


def test_a_bad_case_value_is_refused_by_the_case_loader(tmp_path, capsys):
    assert main(["network-sensitivity", str(CASE), "--set", "drill.d_diff=-1", "--out", str(tmp_path / "no")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error:") and "drill.d_diff = -1" in err and "Traceback" not in err


def test_a_case_without_a_drill_is_refused(capsys):
    assert main(["network-sensitivity", str(CASES / "rheometry" / "ucm_one_mode.toml")]) == 2
    assert "reads the [drill] table" in capsys.readouterr().err
