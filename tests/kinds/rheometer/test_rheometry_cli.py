"""`orchestrator rheometry`: the sweep's frequencies and errors, and (with the executable) a two-frequency sweep of
one UCM mode against Maxwell, the figure, and the moduli unchanged when the quasi-static criterion is tightened."""

import json

import pytest

from orchestrator.cli import main
from orchestrator.errors import OrchestratorError
from orchestrator.kinds.rheometer.commands.rheometry import frequencies_of, run_point
from paths import REPO

ROOT = REPO
UCM = ROOT / "cases" / "rheometry" / "ucm_one_mode.toml"
MF20 = ROOT / "cases" / "rheometry" / "mf20_table3.toml"


def test_frequencies_come_from_the_option_the_sweep_or_the_case():
    assert frequencies_of(MF20) == [0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0]
    assert frequencies_of(MF20, [10.0, 1.0, 10.0]) == [1.0, 10.0]
    assert frequencies_of(UCM) == [1.0]


def test_bad_sweeps_are_refused(capsys):
    with pytest.raises(OrchestratorError, match="--frequencies -1: allowed: angular frequencies above 0"):
        frequencies_of(UCM, [-1.0])
    with pytest.raises(OrchestratorError, match="shear is steady"):
        frequencies_of(ROOT / "cases" / "verification" / "sph_steady_ptt.toml")
    with pytest.raises(OrchestratorError, match="rheometry runs rheometer cases"):
        frequencies_of(ROOT / "cases" / "verification" / "sph_couette_morris1997.toml")
    assert main(["rheometry", str(UCM), "--frequencies", "0"]) == 2
    assert "--frequencies 0" in capsys.readouterr().err


@pytest.mark.sph
def test_sweep_of_one_mode_and_a_tighter_criterion(tmp_path, capsys):
    code = main(["rheometry", str(UCM), "--frequencies", "1", "10", "--out", str(tmp_path / "sweep"), "--json",
                 "--workers", "2"])
    report = json.loads(capsys.readouterr().out)
    assert code == 0 and [p["omega"] for p in report["points"]] == [1.0, 10.0]
    for p in report["points"]:  # Maxwell: G = 1000 Pa, lambda = 1 s; measured 0.01 % and 0.35 %
        assert p["maxwell_storage_modulus"] == pytest.approx(1000 * p["omega"] ** 2 / (1 + p["omega"] ** 2))
        assert p["storage_error"] < 0.01 and p["loss_error"] < 0.01
    assert (tmp_path / "sweep" / "rheometry.png").stat().st_size > 10_000
    tight = run_point(UCM, 10.0, tmp_path / "tight", overrides=["numerics.quasi_static=40"])
    loose = report["points"][1]
    assert tight.sample_density == pytest.approx(loose["sample_density"] / 4)  # rho ~ 1/N^2
    assert tight.storage_modulus == pytest.approx(loose["storage_modulus"], rel=1e-3)
    assert tight.loss_modulus == pytest.approx(loose["loss_modulus"], rel=1e-3)
