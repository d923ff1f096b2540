"""The case stored in a run.h5 read back (runh5.stored_case): one that no longer validates is refused with one line
per problem naming its key, through `orchestrator analyze` as one error paragraph."""

from __future__ import annotations

import tomllib

import h5py
import pytest

from orchestrator.case.loader import to_toml
from orchestrator.cli import main
from orchestrator.errors import ReadError
from orchestrator.runh5 import RUN_FILE, stored_case

from conftest import DATA

#: What pydantic's own message carries and ours must not.
PYDANTIC_TEXT = ("validation error for", "[type=", "For further information", "input_value")


def _stale_case() -> str:
    """tests/data/tiny_bowl.toml as an older or newer version might have stored it: a value now refused, a key
    this version does not know and a required key missing."""
    data = tomllib.loads((DATA / "tiny_bowl.toml").read_text())
    data["media"]["count"] = -5
    data["bowl"]["shape"] = "round"
    del data["workpiece"]["speed"]
    return to_toml(data)


def _problem_lines(message: str) -> list[str]:
    first, *rest = message.splitlines()
    assert "no longer validates" in first and "another version of orchestrator" in first
    return rest


def test_a_stale_case_names_each_key_on_a_line_of_its_own():
    run = {"case": {"attrs": {"toml": _stale_case()}}}
    with pytest.raises(ReadError) as caught:
        stored_case(run, "runs/old/run.h5")
    message = str(caught.value)
    assert message.startswith("runs/old/run.h5: the case stored in run.h5 no longer validates")
    lines = _problem_lines(message)
    assert len(lines) == 3, lines
    assert any(line.startswith("media.count = -5: ") for line in lines), lines
    assert any(line.startswith("bowl.shape: unknown key; allowed here: ") for line in lines), lines
    assert "workpiece.speed: required key is missing" in lines
    assert not [text for text in PYDANTIC_TEXT if text in message]


def test_a_valid_stored_case_reads_back():
    text = (DATA / "tiny_bowl.toml").read_text()
    case = stored_case({"case": {"attrs": {"toml": text}}}, "run.h5")
    assert case.media.count == 120 and case.workpiece.speed == pytest.approx(0.01, rel=1e-12)


@pytest.mark.parametrize("run, says", [
    ({}, "has no /case group"),
    ({"case": {"attrs": {"toml": "[case]\nkind = 'no_such_kind'\n"}}}, "not a case this version knows"),
    ({"case": {"attrs": {"toml": "not toml = = 1"}}}, "not a case this version knows"),
])
def test_a_case_that_cannot_be_read_is_one_line(run, says):
    with pytest.raises(ReadError) as caught:
        stored_case(run, "run.h5")
    assert says in str(caught.value) and len(str(caught.value).splitlines()) == 1


def test_analyze_of_a_run_whose_case_no_longer_validates(synthetic_run, capsys):
    with h5py.File(synthetic_run / RUN_FILE, "r+") as f:
        f["case"].attrs["toml"] = _stale_case()
    assert main(["analyze", str(synthetic_run)]) == ReadError.exit_code
    out, err = capsys.readouterr()
    assert err.startswith("error: ") and err.count("error:") == 1 and "Traceback" not in err
    lines = _problem_lines(err.strip())
    assert {line.split(" ", 1)[0].rstrip(":") for line in lines} == {"media.count", "bowl.shape", "workpiece.speed"}
    assert not [text for text in PYDANTIC_TEXT if text in err]
