"""Bad case files and bad command lines end in one clear 'error:' line, never a traceback.

Every input below is invalid, so `orchestrator run` stops during validation,
before any engine starts; ORCHESTRATOR_YADE points at a file that does not
exist, so even a validation regression cannot start Yade here (it would fail
with a different message instead). No engine is needed.
"""

from __future__ import annotations

import copy
import math
import os
import subprocess
import sys
import tomllib

import pytest
import tomli_w

from orchestrator.engines import engine_names
from orchestrator.case import load_case
from orchestrator.errors import CaseError
from paths import CASES, TINY_BOWL

PAPER = CASES / "drag_finishing_uhlmann2015.toml"
TINY_TEXT = TINY_BOWL.read_text(encoding="utf-8")
# Every bad case is tiny_bowl.toml with one change; the expected words are
# computed from the fixture, so the test follows edits of the fixture's values.
BASE = tomllib.loads(TINY_TEXT)
ENGINES = ", ".join(engine_names())  # every registered engine, installed or not
DROP = object()


def get(path: str, data: dict = BASE):
    node = data
    for part in path.split("."):
        node = node[int(part)] if part.isdigit() else node[part]
    return node


def variant(changes: dict[str, object]) -> str:
    """tiny_bowl.toml as TOML text with each dotted key ('contacts.0.friction') set, or removed with DROP."""
    data = copy.deepcopy(BASE)
    for path, value in changes.items():
        *parents, last = path.split(".")
        node = data
        for part in parents:
            node = node[int(part)] if part.isdigit() else node.setdefault(part, {})
        if value is DROP:
            del node[int(last) if last.isdigit() else last]
        elif last.isdigit():
            node[int(last)] = value
        else:
            node[last] = value
    return tomli_w.dumps(data)


def text_edit(old: str, new: str) -> str:
    assert TINY_TEXT.count(old) == 1, f"{old!r} occurs {TINY_TEXT.count(old)} times in tiny_bowl.toml"
    return TINY_TEXT.replace(old, new)


MEDIA = BASE["media"]
BOWL = BASE["bowl"]
ROD = BASE["workpiece"]
MATERIALS = ", ".join(sorted(BASE["materials"]))
DURATION = BASE["process"]["duration"]
LAST_CONTACT = len(BASE["contacts"]) - 1
# The bed of TOO_MANY balls is taller than the bowl even at the densest random packing (0.64).
TOO_MANY = 2 * math.ceil(0.64 * math.pi * BOWL["inner_radius"] ** 2 * BOWL["height"]
                         / (4 / 3 * math.pi * MEDIA["radius"] ** 3))
# Keep only the media-media contact: the first missing touching pair (sorted) is named.
MEDIA_ONLY = [c for c in BASE["contacts"] if set(c["pair"]) == {MEDIA["material"]}]
MISSING_PAIR = min(tuple(sorted((MEDIA["material"], BASE[t]["material"]))) for t in ("bowl", "workpiece")
                   if BASE[t]["material"] != MEDIA["material"])
WALL_PATH = BOWL["inner_radius"] - ROD["radius"]
DEEP = 1.5 * MEDIA["fill_height"]
FIRST_MATERIAL = sorted(BASE["materials"])[0]
QUICK_PRESET = {"presets.quick.numerics.stiffness_scale": 0.5, "presets.quick.settling.damping": 0.3}

# (id, case text or None for "no such file", extra CLI arguments, words stderr must contain)
BAD_INPUTS = [
    ("unknown-top-level-key", variant({"colour": "red"}), [],
     ["colour: unknown key", "allowed here:", "media", "workpiece"]),
    ("unknown-nested-key", variant({"media.colour": "red"}), [],
     ["media.colour: unknown key", "allowed here:", "radius_spread", "fill_height"]),
    ("unknown-key-in-material", variant({f"materials.{FIRST_MATERIAL}.colour": 1}), [],
     [f"materials.{FIRST_MATERIAL}.colour: unknown key", "allowed here:", "young_modulus"]),
    ("count-is-a-string", variant({"media.count": "many"}), [],
     ["media.count", "'many'", "valid integer"]),
    ("count-is-a-boolean", variant({"media.count": True}), [],
     ["media.count", "True", "expected a number"]),
    ("negative-radius", variant({"media.radius": -MEDIA["radius"]}), [],
     [f"media.radius = {-MEDIA['radius']}", "greater than 0"]),
    ("zero-particles", variant({"media.count": 0}), [],
     ["media.count = 0", "greater than or equal to 1"]),
    ("radius-spread-too-wide", variant({"media.distribution": "normal", "media.radius_spread": MEDIA["radius"]}), [],
     [f"media.radius_spread = {MEDIA['radius']}", f"media.radius = {MEDIA['radius']}",
      "allowed: 2 * radius_spread < radius"]),
    ("unknown-distribution", variant({"media.distribution": "gauss"}), [],
     ["media.distribution = 'gauss'", "'normal' or 'uniform'"]),
    ("missing-mesh-file", variant({"workpiece.mesh": "nope.stl"}), [],
     ["workpiece.mesh", "nope.stl", "not found"]),
    ("mesh-not-a-path", variant({"workpiece.mesh": 5}), [],
     ["workpiece.mesh = 5", "expected a file path"]),
    ("fill-height-above-bowl", variant({"media.fill_height": 1.2 * BOWL["height"]}), [],
     [f"media.fill_height = {1.2 * BOWL['height']}", f"bowl.height = {BOWL['height']}",
      "allowed: fill_height < bowl.height"]),
    ("too-many-balls-for-bowl", variant({"media.count": TOO_MANY}), [],
     [f"media.count = {TOO_MANY}", f"bowl.height = {BOWL['height']}", "allowed: fewer balls or a bigger bowl"]),
    ("unknown-engine-in-case", variant({"case.engine": "fluent"}), [],
     ["case.engine = 'fluent'", "unknown engine", f"allowed: {ENGINES}"]),
    ("unknown-engine-option", TINY_TEXT, ["--engine", "fluent"],
     ["unknown engine 'fluent'", f"allowed: {ENGINES}"]),
    ("unknown-preset-none-defined", variant({"presets": DROP} if "presets" in BASE else {}), ["--preset", "fast"],
     ["unknown preset 'fast'", "allowed: (the file defines none)"]),
    ("unknown-preset", variant(QUICK_PRESET), ["--preset", "fast"],
     ["unknown preset 'fast'", "allowed: quick"]),
    ("invalid-value-in-preset", variant({"presets.quick.media.count": -1}), ["--preset", "quick"],
     ["preset 'quick'", "media.count = -1", "greater than or equal to 1"]),
    ("unknown-key-in-preset", variant({"presets.quick.media.colour": 1}), [],
     ["preset 'quick'", "media.colour: unknown key"]),
    ("malformed-toml", text_edit("[media]", "[media"), [],
     ["malformed TOML", f"line {TINY_TEXT[: TINY_TEXT.index('[media]')].count(chr(10)) + 1}"]),
    ("missing-required-key", variant({"workpiece.speed": DROP}), [],
     ["workpiece.speed: required key is missing"]),
    ("unknown-material-in-contact-pair", variant({f"contacts.{LAST_CONTACT}.pair": [MEDIA["material"], "unobtainium"]}),
     [], [f"contacts[{LAST_CONTACT}].pair", "'unobtainium'", "not defined", f"allowed: {MATERIALS}"]),
    ("unknown-media-material", variant({"media.material": "glass"}), [],
     ["media.material = 'glass'", "not defined", f"allowed: {MATERIALS}"]),
    ("missing-contact-pair", variant({"contacts": MEDIA_ONLY}), [],
     [f"contacts has no entry for the pair ({MISSING_PAIR[0]}, {MISSING_PAIR[1]})", "[[contacts]]"]),
    ("restitution-above-one", variant({"contacts.0.restitution": 1.5}), [],
     ["contacts[0].restitution = 1.5", "less than or equal to 1"]),
    ("poisson-ratio-half", variant({f"materials.{FIRST_MATERIAL}.poisson_ratio": 0.5}), [],
     [f"materials.{FIRST_MATERIAL}.poisson_ratio = 0.5", "less than 0.5"]),
    ("network-time-after-process", variant({"output.network_times": [5 * DURATION]}), [],
     ["output.network_times", f"{5 * DURATION} s", f"process.duration = {DURATION}", "allowed: 0 <= t <= duration"]),
    ("impact-window-after-process", variant({"output.impact_window": [2 * DURATION, 3 * DURATION]}), [],
     ["output.impact_window = " + f"[{2 * DURATION}, {3 * DURATION}] s", f"process.duration = {DURATION}",
      "allowed: [start, end] with 0 <= start < end and start < duration"]),
    ("impact-window-reversed", variant({"output.impact_window": [DURATION / 2, 0.0]}), [],
     ["output.impact_window", "0 <= start < end"]),
    ("submersion-below-fill", variant({"workpiece.submersion_depth": DEEP}), [],
     [f"workpiece.submersion_depth = {DEEP}", f"media.fill_height = {MEDIA['fill_height']}",
      "allowed: submersion_depth < fill_height"]),
    ("path-radius-reaches-wall", variant({"workpiece.path_radius": WALL_PATH}), [],
     [f"workpiece.path_radius = {WALL_PATH}", f"bowl.inner_radius = {BOWL['inner_radius']}",
      "allowed: path_radius + radius < inner_radius - 2 * largest ball radius"]),
    ("set-without-equals", TINY_TEXT, ["--set", "media.count"],
     ["--set 'media.count'", "expected KEY=VALUE"]),
    ("set-with-empty-key", TINY_TEXT, ["--set", "=3"],
     ["--set '=3'", "empty"]),
    ("set-into-a-value", TINY_TEXT, ["--set", "media.count.x=1"],
     ["media.count is a value, not a table", "cannot set media.count.x"]),
    ("set-invalid-value", TINY_TEXT, ["--set", "media.radius=-1"],
     ["with --set", "media.radius = -1", "greater than 0"]),
    ("set-unknown-key", TINY_TEXT, ["--set", "media.colour=red"],
     ["with --set", "media.colour: unknown key", "allowed here:"]),
    ("set-case-to-a-value", TINY_TEXT, ["--set", "case=1"],
     ["case = 1 is a value, not a table"]),
    ("case-file-missing", None, [],
     ["case file not found", "missing.toml"]),
    ("unknown-case-kind", variant({"case.kind": "sandblasting"}), [],
     ["case.kind = 'sandblasting'", "not known", "allowed: afm_channel, cantilever_plate, crater, drag_finishing"]),
    ("case-kind-not-a-string", variant({"case.kind": ["drag_finishing"]}), [],
     ["case.kind = ['drag_finishing']", "not known", "allowed: afm_channel, cantilever_plate, crater, drag_finishing"]),
    ("case-kind-missing", variant({"case.kind": DROP}), [],
     ["case.kind: required key is missing", "allowed: afm_channel, cantilever_plate, crater, drag_finishing"]),
    ("settling-stiffer-than-process", variant({"numerics.stiffness_scale": 0.01, "settling.stiffness_scale": 0.1}),
     [], ["settling.stiffness_scale = 0.1", "numerics.stiffness_scale = 0.01",
          "allowed: settling.stiffness_scale <= numerics.stiffness_scale"]),
]


@pytest.mark.parametrize(
    ("text", "args", "expected"),
    [pytest.param(text, args, expected, id=name) for name, text, args, expected in BAD_INPUTS],
)
def test_bad_input_gives_one_clear_error(tmp_path, text, args, expected):
    case = tmp_path / ("missing.toml" if text is None else "case.toml")
    if text is not None:
        case.write_text(text, encoding="utf-8")
    out = tmp_path / "out"
    env = dict(os.environ, ORCHESTRATOR_YADE=str(tmp_path / "no-yade-here"))
    result = subprocess.run(
        [sys.executable, "-m", "orchestrator", "run", str(case), "--out", str(out), "--no-progress", *args],
        cwd=tmp_path, env=env, capture_output=True, text=True, timeout=60,
    )
    stderr = result.stderr
    assert result.returncode != 0, stderr
    assert stderr.startswith("error:"), stderr
    assert "Traceback" not in stderr, stderr
    for words in expected:
        assert words in stderr, f"{words!r} missing from:\n{stderr}"
    assert not out.exists(), "validation should fail before a run directory is made"


def test_bad_inputs_are_distinct():
    ids = [name for name, *_ in BAD_INPUTS]
    assert len(ids) == len(set(ids)) >= 18
    inputs = [(text, tuple(args)) for _, text, args, _ in BAD_INPUTS]
    assert len(inputs) == len(set(inputs))


# ---- a valid case, overrides, presets, immutability (in process, no engine) ----


def test_valid_case_loads():
    loaded = load_case(TINY_BOWL)
    case = loaded.model
    assert loaded.name == "tiny_bowl" and loaded.kind == "drag_finishing"
    assert case.media.count == MEDIA["count"]
    assert case.media.radius == pytest.approx(MEDIA["radius"])
    assert case.process.duration == pytest.approx(DURATION)
    assert case.contact(MEDIA["material"], MEDIA["material"]).friction >= 0
    assert loaded.preset is None
    assert len(loaded.hash) == 64


def test_set_changes_the_count():
    assert load_case(TINY_BOWL, overrides=["media.count=50"]).model.media.count == 50
    assert load_case(TINY_BOWL, overrides=["media.count=50"]).hash != load_case(TINY_BOWL).hash


def test_preset_applies(tmp_path):
    case = tmp_path / "case.toml"
    case.write_text(variant(QUICK_PRESET), encoding="utf-8")
    plain = load_case(case).model
    quick = load_case(case, preset="quick")
    assert plain.numerics.stiffness_scale == pytest.approx(BASE["numerics"]["stiffness_scale"])
    assert quick.preset == "quick"
    assert quick.model.numerics.stiffness_scale == pytest.approx(0.5)
    assert quick.model.settling.damping == pytest.approx(0.3)
    # --set is applied after the preset
    assert load_case(case, preset="quick", overrides=["numerics.stiffness_scale=0.25"]).model.numerics.stiffness_scale == 0.25


def test_paper_case_presets_apply():
    """Every value of each [presets.NAME] of the paper's case ends up in the loaded model."""
    presets = tomllib.loads(PAPER.read_text(encoding="utf-8"))["presets"]
    assert presets, "the paper case defines presets"
    for name, patch in presets.items():
        model = load_case(PAPER, preset=name).model
        for table, values in patch.items():
            for key, value in values.items():
                got = getattr(getattr(model, table), key)
                assert got == (pytest.approx(tuple(value)) if isinstance(value, list) else pytest.approx(value)), \
                    f"preset {name}: {table}.{key}"


def test_case_model_is_immutable(tiny_bowl):
    case = tiny_bowl
    with pytest.raises(Exception) as info:
        case.media.count = 1
    assert "frozen" in str(info.value).lower()
    with pytest.raises(Exception):
        case.media = None
    with pytest.raises(Exception):
        case.materials[FIRST_MATERIAL].density = 1.0
    assert case.media.count == MEDIA["count"]


def test_load_case_raises_case_error():
    with pytest.raises(CaseError, match=r"media\.count = 0"):
        load_case(TINY_BOWL, overrides=["media.count=0"])
