"""No code from case strings: hostile text in every string field that reaches an engine input changes nothing
the engine does, and validation refuses hostile names with a message naming the key and what is allowed.

Two layers are tested. Validation: names (materials, contact pairs, SPH blocks, walls, patches, probes) are
refused unless they are plain identifiers (orchestrator/case/common.py, NAME_RULE). Escaping, tested with the
names put into a validated case behind validation's back: LIGGGHTS decks carry names only in '#' comments that
stay one line (lines compared with the comments removed); Yade scripts carry them as Python string literals
(ASTs compared with the names mapped back); the SPH deck as JSON strings (parsed decks compared). Free text
that validation allows (descriptions, labels, mesh file names) must not change a deck at all.
Finally report.html is autoescaped.
"""

from __future__ import annotations

import ast
import csv
import json
import shutil
from pathlib import Path

import pytest

from orchestrator.kinds import bind
from orchestrator.kinds.sph_flow.sph import TEMPLATE as SPH_TEMPLATE, deck_context

from orchestrator.case import load_case
from orchestrator.errors import OrchestratorError
from orchestrator.kinds import build_scene
from orchestrator.templating import render
from paths import REPO, DATA, TINY_BOWL

DROP = REPO / "cases" / "verification" / "uhlmann2015_sphere_drop.toml"
CHANNEL = DATA / "sph_channel_3d.toml"
DAM_BREAK = REPO / "cases" / "sph" / "dam_break_2d.toml"

#: Appended to a name: what would end a comment, a string or a line, run a shell or expand a variable.
HOSTILE = "\nshell touch pwned\n# \"' ${x} $(touch pwned) `id` \\ \\n & #\r\u2028é&"
#: The same, as one line of printable text (what a label may hold).
HOSTILE_LINE = "x\" ' ${x} $(touch pwned) `id` \\ \\n # & <b>&amp;"


# ---- what an engine reads, with the case's text taken out ----
def liggghts_commands(deck: str) -> list[str]:
    """The deck's lines with '#' comments removed (a '#' inside quotes is text, as LIGGGHTS reads it)."""
    out = []
    for line in deck.split("\n"):
        assert not line.rstrip().endswith("&"), f"a line continues into the next: {line!r}"
        quote, cut = None, len(line)
        for k, c in enumerate(line):
            if quote:
                quote = None if c == quote else quote
            elif c in "\"'":
                quote = c
            elif c == "#":
                cut = k
                break
        out.append(line[:cut].rstrip())
    return out


def python_meaning(script: str, names: dict[str, str]) -> str:
    """The script's AST with each string constant in `names` replaced by its canonical name."""

    class Canonical(ast.NodeTransformer):
        def visit_Constant(self, node):
            if isinstance(node.value, str) and node.value in names:
                return ast.copy_location(ast.Constant(names[node.value]), node)
            return node

    return ast.dump(Canonical().visit(ast.parse(script)))


def json_meaning(value, names: dict[str, str]):
    """The parsed deck with each string in `names` replaced by its canonical name."""
    if isinstance(value, dict):
        return {k: json_meaning(v, names) for k, v in value.items()}
    if isinstance(value, list):
        return [json_meaning(v, names) for v in value]
    return names.get(value, value) if isinstance(value, str) else value


# ---- cases with other names, behind validation's back ----
def renamed_dem(case, suffix: str):
    """The DEM case with every material name (but the reserved 'rigid') given `suffix`, without validation."""
    new = lambda name: name if name == "rigid" else name + suffix  # noqa: E731
    update = {"materials": {new(k): v for k, v in case.materials.items()},
              "contacts": tuple(c.model_copy(update={"pair": tuple(new(n) for n in c.pair)}) for c in case.contacts),
              "case": case.case.model_copy(update={"description": HOSTILE if suffix == HOSTILE else ""})}
    if case.case.kind == "drag_finishing":
        for part in ("media", "bowl", "workpiece"):
            update[part] = getattr(case, part).model_copy(update={"material": new(getattr(case, part).material)})
    else:
        update["spheres"] = tuple(s.model_copy(update={"material": new(s.material)}) for s in case.spheres)
        if case.plane is not None:
            update["plane"] = case.plane.model_copy(update={"material": new(case.plane.material)})
    return case.model_copy(update=update)


def renamed_sph(case, suffix: str):
    """The SPH case with every block, wall, patch and probe name given `suffix`, without validation."""
    rename = lambda items: tuple(i.model_copy(update={"name": i.name + suffix}) for i in items)  # noqa: E731
    output = case.output.model_copy(update={"probes": rename(case.output.probes),
                                            "flow_planes": rename(case.output.flow_planes)})
    return case.model_copy(update={"blocks": rename(case.blocks), "walls": rename(case.walls),
                                   "inlets": rename(case.inlets), "outlets": rename(case.outlets),
                                   "impactors": rename(case.impactors), "output": output})


def _names(case) -> list[str]:
    if case.case.kind == "sph_flow":
        return [i.name for group in (case.blocks, case.walls, case.inlets, case.outlets, case.impactors,
                                     case.output.probes, case.output.flow_planes) for i in group]
    if case.case.kind == "rheometer":
        return []  # a rheometer case names nothing that reaches the deck (its material and block are "sample")
    if case.case.kind in ("taylor_bar", "cantilever_plate", "crater", "scratch"):
        return [case.material.name]
    if case.case.kind == "afm_channel":
        return [case.workpiece.name]  # the medium, grain and blocks are the scene's own names
    if case.case.kind in ("ejector_drill", "ejector_feed"):
        return []  # its deck's names (planes, probes, walls) are the layout's own, none from the case file
    return [n for n in case.materials if n != "rigid"]


def _decks(case_path: Path, engine: str, tmp_path: Path) -> tuple[str, str, dict[str, str]]:
    """(benign deck, hostile deck, rendered name -> canonical name) for one case on one engine."""
    case = load_case(case_path).model
    rename = renamed_sph if case.case.kind == "sph_flow" else renamed_dem
    names = {}
    decks = []
    for suffix in ("_benign", HOSTILE):
        variant = rename(case, suffix)
        for original in _names(case):
            names[original + suffix] = original
            names["/" + original + suffix] = "/" + original  # SPH mesh groups
        scene = build_scene(variant)
        if engine == "sph":
            decks.append(render(SPH_TEMPLATE, deck_context(scene)))
            continue
        bound_adapter = bind(case.case.kind, engine, executable="/x")
        out = tmp_path / f"{engine}{len(decks)}"
        out.mkdir()
        bound_adapter.write_input(scene, out)
        kind = case.case.kind
        deck = {("liggghts", "impact"): "impact.in", ("liggghts", "drag_finishing"): "drag_finishing.in",
                ("yade", "impact"): "impact.py", ("yade", "drag_finishing"): "drag_finishing.py"}[engine, kind]
        decks.append((out / deck).read_text())
    return decks[0], decks[1], names


@pytest.mark.parametrize("case_path", [TINY_BOWL, DROP], ids=["drag_finishing", "impact"])
def test_liggghts_deck_means_the_same_with_hostile_names(case_path, tmp_path):
    benign, hostile, _ = _decks(case_path, "liggghts", tmp_path)
    assert "pwned" in hostile and "pwned" not in benign  # the names did reach the deck, in comments
    assert liggghts_commands(hostile) == liggghts_commands(benign)
    assert not any("pwned" in line for line in liggghts_commands(hostile))


@pytest.mark.parametrize("case_path", [TINY_BOWL, DROP], ids=["drag_finishing", "impact"])
def test_yade_script_means_the_same_with_hostile_names(case_path, tmp_path):
    benign, hostile, names = _decks(case_path, "yade", tmp_path)
    assert python_meaning(hostile, names) == python_meaning(benign, names)
    assert hostile.isascii() and len(hostile.splitlines()) == len(benign.splitlines())


@pytest.mark.parametrize("case_path", [CHANNEL, DAM_BREAK], ids=["channel_3d", "dam_break_2d"])
def test_sph_deck_means_the_same_with_hostile_names(case_path, tmp_path):
    benign, hostile, names = _decks(case_path, "sph", tmp_path)
    assert json_meaning(json.loads(hostile), names) == json_meaning(json.loads(benign), names)


# ---- free text that validation allows: no deck changes at all ----
def _render_all(case_path: Path, tmp_path: Path, overrides=(), tag="") -> dict[str, str | bytes]:
    """Every deck the case renders (Yade and LIGGGHTS for DEM, the SPH deck) as name -> text."""
    case = load_case(case_path, overrides=list(overrides)).model
    scene = build_scene(case)
    if case.case.kind == "sph_flow":
        return {"deck.json": render(SPH_TEMPLATE, deck_context(scene))}
    decks = {}
    for bound_adapter in (bind(case.case.kind, "yade", executable="/x"),
                          bind(case.case.kind, "liggghts", executable="/x")):
        out = tmp_path / f"{bound_adapter.adapter.engine}{tag}"
        out.mkdir()
        bound_adapter.write_input(scene, out)
        decks.update({f"{bound_adapter.adapter.engine}/{p.name}": p.read_bytes() for p in out.iterdir()
                      if p.suffix in (".py", ".in", ".stl", ".data")})
    return decks


@pytest.mark.parametrize("case_path", [TINY_BOWL, DROP, CHANNEL], ids=["drag_finishing", "impact", "sph"])
def test_a_hostile_description_changes_no_deck(case_path, tmp_path):
    plain = _render_all(case_path, tmp_path, tag="a")
    hostile = _render_all(case_path, tmp_path, [f"case.description={json.dumps(HOSTILE)}"], tag="b")
    assert hostile == plain


def test_a_hostile_reference_label_changes_no_deck(tmp_path):
    label = f"reference=[{{label={json.dumps(HOSTILE_LINE)}, fn_mean=-1.8, fn_std=0.25}}]"
    assert load_case(TINY_BOWL, overrides=[label]).model.reference[0].label == HOSTILE_LINE
    assert _render_all(TINY_BOWL, tmp_path, [label], tag="b") == _render_all(TINY_BOWL, tmp_path, tag="a")


def test_a_hostile_mesh_file_name_changes_no_deck(tmp_path, tiny_bowl):
    """The rod's STL read from a file whose name would break any deck it were written into: it is read by the
    orchestrator and reaches the engines as rod.stl / arrays, so the decks are those of a plain name."""
    from orchestrator.kinds.drag_finishing.scene import rod_mesh

    case = tiny_bowl
    rod = rod_mesh(case.workpiece.radius, case.workpiece.length, case.workpiece.segments)
    folder = tmp_path / "meshes"
    folder.mkdir()
    plain, hostile = folder / "rod.stl", folder / ("rod $(touch pwned) ${x} \"q\" 'q' #&\\ \nshell x.stl")
    rod.export(plain)
    shutil.copy(plain, hostile)
    decks = [_render_all(TINY_BOWL, tmp_path, [f"workpiece.mesh={json.dumps(str(path))}"], tag=str(k))
             for k, path in enumerate((plain, hostile))]
    assert decks[1] == decks[0]


def test_a_hostile_sph_mesh_file_name_changes_no_deck(tmp_path):
    folder = tmp_path / "case"
    folder.mkdir()
    text = CHANNEL.read_text()
    name = "mesh $(touch pwned) ${x} \"q\" 'q' #&\\ \nshell x.stl"
    shutil.copy(DATA / "sph_obstacle_mm.stl", folder / name)
    assert 'file = "sph_obstacle_mm.stl"' in text
    (folder / "case.toml").write_text(text.replace('file = "sph_obstacle_mm.stl"', f"file = {json.dumps(name)}"))
    assert _render_all(folder / "case.toml", tmp_path) == _render_all(CHANNEL, tmp_path)


# ---- validation ----
NAME_KEYS = [
    (TINY_BOWL, "media.material", "{h}"), (TINY_BOWL, "bowl.material", "{h}"), (TINY_BOWL, "workpiece.material", "{h}"),
    (TINY_BOWL, "contacts[0].pair[1]", "contacts.0.pair=['ceramic', {h}]"),
    (DROP, "spheres[0].material", "{h}"), (DROP, "plane.material", "{h}"),
    (CHANNEL, "blocks[0].name", "{h}"), (CHANNEL, "walls[0].name", "{h}"), (CHANNEL, "inlets[0].name", "{h}"),
    (CHANNEL, "outlets[0].name", "{h}"), (CHANNEL, "output.probes[0].name", "{h}"),
    (CHANNEL, "output.flow_planes[0].name", "{h}"),
]
HOSTILE_NAMES = ["steel\nshell touch pwned\n#", 'steel"', "steel'", "steel ${x}", "$(touch pwned)", "steel\\",
                 "steel#", "steel&", "", "1steel", "_steel", "é", "s" * 65]


def _override(key: str, template: str, name: str) -> str:
    if template == "{h}":
        dotted = key.replace("[", ".").replace("]", "")
        return f"{dotted}={json.dumps(name)}"
    return template.format(h=json.dumps(name))


@pytest.mark.parametrize("case_path,key,template", NAME_KEYS, ids=[k for _, k, _ in NAME_KEYS])
@pytest.mark.parametrize("name", HOSTILE_NAMES, ids=range(len(HOSTILE_NAMES)))
def test_hostile_names_are_refused_naming_key_and_rule(case_path, key, template, name):
    with pytest.raises(OrchestratorError) as caught:
        load_case(case_path, overrides=[_override(key, template, name)])
    message = str(caught.value)
    assert f"{key} = " in message and "allowed: a letter, then up to 63 letters, digits" in message, message


@pytest.mark.parametrize("name", HOSTILE_NAMES[:8] + ["1steel"], ids=range(9))
def test_a_hostile_material_key_is_refused(name, tmp_path):
    text = TINY_BOWL.read_text()
    assert "[materials.ceramic]" in text
    (tmp_path / "case.toml").write_text(text.replace("[materials.ceramic]", f"[materials.{json.dumps(name)}]"))
    with pytest.raises(OrchestratorError, match=r"materials = .*the material name .* is not allowed; allowed: a "
                                                r"letter, then up to 63 letters"):
        load_case(tmp_path / "case.toml")


def test_a_label_over_two_lines_is_refused():
    with pytest.raises(OrchestratorError, match=r"reference\[0\]\.label = .*allowed: one line of printable text"):
        load_case(TINY_BOWL, overrides=['reference=[{label="a\\nshell touch pwned", fn_mean=-1.8, fn_std=0.25}]'])


def test_every_shipped_name_is_still_a_name():
    from orchestrator.case.common import check_name

    for path in sorted((REPO / "cases").rglob("*.toml")) + sorted((DATA).glob("*.toml")):
        if "studies" in path.parts:
            continue
        for name in _names(load_case(path).model):
            check_name(name)


# ---- report.html ----
def test_study_report_escapes_what_the_study_says(tmp_path):
    from orchestrator.study.report import write_study_report

    rows = [{"run_id": k * 64, "engine": "yade", "run_dir": str(tmp_path / k), "param:case.description": text,
             "status": "ok", "wall_time_s": wall, "dt": dt, "fn_mean": fn}
            for k, text, wall, dt, fn in (("a", "<img src=x onerror=alert(2)>", 100.0, 1e-7, -2.0),
                                          ("b", "plain", 10.0, 1e-6, -1.99))]
    with open(tmp_path / "index.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    (tmp_path / "study.json").write_text(json.dumps({"name": "s", "description": "<script>alert(1)</script>"}))
    html = write_study_report(tmp_path, quantity="fn_mean", tolerance=0.05).read_text()
    assert "<script>" not in html and "&lt;script&gt;alert(1)&lt;/script&gt;" in html
    assert "<img src=x" not in html and "&lt;img src=x onerror=alert(2)&gt;" in html
    assert html.startswith("<!DOCTYPE html>") and "<h1>Study " in html and 'src="data:image/png;base64,' in html
