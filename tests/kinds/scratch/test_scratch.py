"""The scratch kind: its case checks, the scene (the grain's clump, mass, velocity and start clear of the
target), the kerf, the removed particles and chips on synthetic frames, and (engine) the quick preset with and
without failure."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from paths import CASES

from orchestrator.case import load_case
from orchestrator.cli import main
from orchestrator.errors import CaseError
from orchestrator.kinds import build_scene
from orchestrator.kinds.scratch.analysis import kerf
from orchestrator.kinds.sph_flow.removal import chips, removed
from orchestrator.kinds.scratch.scene import clump, grain_mass, grain_spheres
from orchestrator.kinds.sph_flow.sph import deck_context

SCRATCH = CASES / "scratch" / "scratch_al6061.toml"


def lattice(nx: int, ny: int, nz: int, dx: float) -> np.ndarray:
    """Particle centres of a box nx x ny x nz of spacing dx whose top face is z = 0, m."""
    i, j, k = np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij")
    return np.column_stack([(i.ravel() + 0.5) * dx, (j.ravel() + 0.5) * dx, -(k.ravel() + 0.5) * dx])


def test_the_grain_is_a_clump_leading_with_a_corner_at_300_m_s_and_60_degrees_from_the_normal():
    case = load_case(SCRATCH, preset="quick").model
    scene = build_scene(case)
    dx = case.numerics.dx
    assert (scene.kind == 0).sum() == 32 * 16 * 8 and (scene.kind == 1).sum() == 32 * 16 * 3
    deck = json.loads(deck_context(scene)["impactors"][0])
    assert deck["velocity"] == pytest.approx([259.8076211, 0.0, -150.0], rel=1e-9)
    # the union of a central sphere R = 30 um / 1.3 and four corners r = 0.3 R centred on its surface (the lens of
    # each corner inside the central sphere, pi r^2 (8 R r - 3 r^2) / (12 R), counted once), alumina 3950 kg/m^3
    big, small = 30e-6 / 1.3, 0.3 * 30e-6 / 1.3
    lens = math.pi * small**2 * (8.0 * big * small - 3.0 * small**2) / (12.0 * big)
    volume = 4.0 / 3.0 * math.pi * (big**3 + 4.0 * small**3) - 4.0 * lens
    assert grain_mass(case) == pytest.approx(3950.0 * volume, rel=1e-3)
    assert deck["mass"] == pytest.approx(grain_mass(case)) and deck["mass"] == pytest.approx(2.1556e-10, rel=1e-3)
    spheres = grain_spheres(case)
    lowest = spheres[:, 2] - spheres[:, 3]
    assert int(np.argmin(lowest)) == 1 and lowest.min() == pytest.approx(0.25 * dx)  # the leading corner
    # the leading corner carried along the velocity meets z = 0 at target.entry = 60 um from the -x face
    assert spheres[1, 0] + lowest.min() / math.tan(math.radians(30.0)) == pytest.approx(-120e-6 + 60e-6)
    np.testing.assert_allclose(np.linalg.norm(clump(case)[1:, :3], axis=1), big, rtol=1e-12)


def test_without_failure_the_deck_has_no_failure_table():
    with_failure = build_scene(load_case(SCRATCH, preset="quick").model)
    without = build_scene(load_case(SCRATCH, preset="quick", overrides=["material.fails=false"]).model)
    assert "failure" in json.loads(deck_context(with_failure)["materials"][0])
    assert "failure" not in json.loads(deck_context(without)["materials"][0])


@pytest.mark.parametrize("override, words", [
    ("target.size=[241e-6, 120e-6, 60e-6]", "target.size along x = 0.000241 m is not a whole number"),
    ("grain.size=10e-6", "grain.size = 1e-05 m gives corner spheres of radius"),
    ("grain.size=150e-6", "grain.size = 0.00015 m is wider than the target"),
    ("target.entry=10e-6", "target.entry = 1e-05 m puts the first contact less than half the grain"),
    ("grain.angle=95", "grain.angle"),
    ("grain.angle=0", "grain.angle"),
    ("material.solid.melting_temperature=200", "material.solid.melting_temperature = 200 K is not above"),
])
def test_bad_scratches_are_named(override, words):
    with pytest.raises(CaseError, match=words.replace(".", r"\.").replace("[", r"\[")):
        load_case(SCRATCH, overrides=[override])


def test_removed_particles_are_failed_and_separated_and_chips_are_their_clusters():
    dx = 1e-6
    slab = lattice(6, 6, 3, dx)
    failed_on_top = np.array([[3.0 * dx, 3.0 * dx, 0.5 * dx]])  # touching the slab: still attached
    chip = np.array([[2.0, 2.0, 5.0], [3.0, 2.0, 5.0], [3.0, 3.0, 5.0]]) * dx  # 3 linked, far above
    lone = np.array([[10.0 * dx, 10.0 * dx, 0.0]])
    x = np.vstack([slab, failed_on_top, chip, lone])
    damage = np.r_[np.zeros(len(slab)), 1.0, 1.0, 1.0, 1.0, 1.2]
    gone = removed(x, damage, np.ones(len(x), dtype=bool), dx)
    assert gone.sum() == 4 and not gone[len(slab)] and gone[-4:].all()
    damage[-2] = 0.99  # an unfailed particle in a chip anchors it and its neighbours
    assert removed(x, damage, np.ones(len(x), dtype=bool), dx).sum() == 1
    labels = chips(x[gone], dx)
    assert labels.max() + 1 == 2 and sorted(np.bincount(labels)) == [1, 3]


def test_the_kerf_is_the_sunk_columns_and_the_pile_up_is_ahead_of_them():
    dx = 1e-6
    x0 = lattice(10, 8, 4, dx)
    x = x0.copy()
    column = np.floor(x0[:, :2] / dx).astype(int)
    groove = (column[:, 0] >= 2) & (column[:, 0] <= 4) & (column[:, 1] >= 3) & (column[:, 1] <= 4)
    x[groove, 2] -= 2.0 * dx
    ahead = (column[:, 0] == 6) & (column[:, 1] == 3) & (x0[:, 2] > -dx)
    x[ahead, 2] += 0.5 * dx
    out = kerf(x0, x, np.ones(len(x), dtype=bool), dx)
    assert out["kerf_length"] == pytest.approx(3 * dx) and out["kerf_width"] == pytest.approx(2 * dx)
    assert out["kerf_depth"] == pytest.approx(2 * dx) and out["pile_up"] == pytest.approx(0.5 * dx)
    # a removed top particle lays the one below it bare: the column's surface is one dx deeper
    keep = ~((column[:, 0] == 8) & (column[:, 1] == 6) & (x0[:, 2] > -dx))
    assert kerf(x0, x0, keep, dx)["kerf_depth"] == pytest.approx(dx)


@pytest.mark.sph
def test_the_quick_scratch_with_and_without_failure(tmp_path, capsys):
    """7.5 um spacing, one thread: a kerf, energy within 2 %, failed particles torn off only with failure."""
    from orchestrator.runh5 import read_run

    measured = {}
    for fails in ("true", "false"):
        out = tmp_path / fails
        code = main(["run", str(SCRATCH), "--preset", "quick", "--set", f"material.fails={fails}", "--out", str(out)])
        assert code == 0
        measured[fails] = read_run(out)["measured"]["attrs"]
    for m in measured.values():
        assert m["kerf_depth"] > 0.25 * 7.5e-6 and m["kerf_length"] > 0.0 and m["kerf_width"] > 0.0
        assert abs(m["energy_balance"]) < 0.02
        assert 0.2 < m["plastic_work_fraction"] < 0.9 and m["max_temperature"] > 330.0
    assert measured["true"]["removed_count"] > 0 and measured["true"]["chips"] > 0
    assert measured["true"]["removed_mass"] == pytest.approx(measured["true"]["removed_count"] * 2703.0 * 7.5e-6**3)
    assert measured["false"]["removed_count"] == 0 and measured["false"]["failed_count"] == 0
    assert main(["analyze", str(tmp_path / "true")]) == 0
    assert "removed_count" in capsys.readouterr().out and (tmp_path / "true" / "scratch.png").is_file()
