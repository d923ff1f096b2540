"""The crater's check over its sweep: the slope of log d against log v (eq. 20: 1/2 at a constant dynamic
hardness) with d the cap of the sphere's radius holding the crater's volume, as one more run of the scene in
verify's table."""

from __future__ import annotations

import shutil

import pytest

from orchestrator.case import load_case
from orchestrator.kinds.crater.checks import check_sweep
from orchestrator.workflows.base import CheckedRun
from orchestrator.workflows.verify import with_sweep_checks
from paths import VERIFICATION

CRATER = VERIFICATION / "crater_hutchings_100cr6.toml"
SPEEDS = (40.0, 60.0, 80.0, 100.0)


def _runs(tmp_path, exponent: float, case_file=CRATER) -> list[CheckedRun]:
    runs = []
    for v in SPEEDS:
        folder = tmp_path / f"v_{v:g}"
        folder.mkdir()
        shutil.copy(case_file, folder / "case.toml")
        d = 2.4e-4 * (v / 100.0) ** exponent
        picture = {"speed": v, "volume": d, "diameter": 1.1 * d * (v / 100.0) ** -0.09,
                   "contact": 0.9 * d * (v / 100.0) ** 0.02, "hutchings": 0.95 * d,
                   "hardness": 4.5e9, "pressure": 3.4e9 * (v / 100.0) ** 0.28}
        runs.append(CheckedRun("crater_hutchings_100cr6", "sph", "ok", "", folder, [], 10.0, picture))
    return runs


@pytest.mark.parametrize("exponent, passed", [(0.5, True), (0.46, True), (0.411, False), (0.56, False)])
def test_the_slope_of_log_d_on_log_v_against_one_half(tmp_path, exponent, passed):
    case = load_case(CRATER).model
    (row,) = check_sweep(case, "sph", _runs(tmp_path, exponent))
    assert row["quantity"] == "speed_exponent" and row["value"] == pytest.approx(exponent, rel=1e-9)
    assert row["rel_error"] == pytest.approx(abs(exponent / 0.5 - 1.0), rel=1e-9)
    assert row["passed"] is passed
    assert f"contact chord {exponent + 0.02:.3f}" in row["note"]
    assert f"rim crest {exponent - 0.09:.3f}" in row["note"]


def test_a_missing_diameter_fails_the_slope(tmp_path):
    runs = _runs(tmp_path, 0.5)
    runs[2].picture["volume"] = float("nan")
    (row,) = check_sweep(load_case(CRATER).model, "sph", runs)
    assert row["value"] is None and not row["passed"]


def test_verify_adds_the_sweep_as_one_more_run(tmp_path):
    runs = _runs(tmp_path, 0.48)  # inside the tolerance (0.45 lies on its edge, where the fit's rounding decides)
    out = with_sweep_checks(runs)
    assert out[:4] == runs and len(out) == 5
    sweep = out[4]
    assert sweep.scene == "crater_hutchings_100cr6 over its sweep" and sweep.run_dir == tmp_path
    assert sweep.wall_time_s == pytest.approx(40.0) and sweep.status == "ok"
    assert [row["quantity"] for row in sweep.rows] == ["speed_exponent"] and sweep.rows[0]["passed"]
    assert with_sweep_checks(runs[:1]) == runs[:1]  # one run is no sweep



def test_the_sweep_draws_its_picture_in_its_folder(tmp_path):
    check_sweep(load_case(CRATER).model, "sph", _runs(tmp_path, 0.5))
    assert (tmp_path / "crater_speeds.png").stat().st_size > 10_000
