"""The abrasive-flow channel kind: its case checks (bad input named by its key), the scene (the cell, the workpiece
on a floor of its material, the grain carved from the medium, the body force on the fluid only, the medium's sound
speed), the removal and surface measures on synthetic frames, and (engine) the quick preset."""

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
from orchestrator.kinds.afm_channel.analysis import lubrication_rate, workpiece_quantities
from orchestrator.kinds.afm_channel.scene import section_x
from orchestrator.kinds.sph_flow.sph import deck_context

CHANNEL = CASES / "afm" / "afm_channel_nutto.toml"


def test_the_cell_of_nutto_et_al_fig_5():
    case = load_case(CHANNEL).model
    scene = build_scene(case)
    dx = 5e-6
    # 300 x 130 x 170 um at 5 um: 60 x 26 x 34 sites, the walls 3 layers each, the support 3 layers of 10 rows
    assert len(scene.positions) == 60 * 26 * 34
    assert (scene.kind == 1).sum() == 2 * 60 * 26 * 3 + 3 * 26 * 10
    # the grain: the medium's sites within 25 um of its centre, (100, 65, 60) um
    grain = scene.kind == 4
    centre = np.array([100e-6, 65e-6, 15e-6 + 45e-6])
    assert np.linalg.norm(scene.positions[grain] - centre, axis=1).max() < 25e-6
    assert grain.sum() == np.count_nonzero(np.linalg.norm(scene.positions - centre, axis=1) < 25e-6)
    # the workpiece (material 1) fills 180-260 um x 15-65 um; the floor under it and its support are of its
    # material and reach 3 dx upstream of its face
    workpiece = (scene.material == 1) & (scene.kind == 0)
    assert workpiece.sum() == 16 * 26 * 10
    x = scene.positions
    assert x[workpiece, 0].min() == pytest.approx(182.5e-6) and x[workpiece, 2].max() == pytest.approx(62.5e-6)
    floor = (scene.material == 1) & (scene.kind == 1) & (x[:, 2] < 15e-6)
    assert x[floor, 0].min() == pytest.approx(180e-6 - 3 * dx + 0.5 * dx)
    context = deck_context(scene)
    assert context["body_force_solids"] is False
    assert json.loads(context["grains"][0])["body_force"] == [0.0, 0.0, 0.0]
    materials = [json.loads(m) for m in context["materials"]]
    # c0^2 >= f L / 0.01: the whole cell's drive rho f L on the workpiece compresses the medium by 1 %
    assert materials[0]["c0"] == pytest.approx(math.sqrt(8.0e7 * 300e-6 / 0.01))
    assert materials[0]["viscosity"] == pytest.approx(5.0 / 1000.0)
    # the workpiece's inertia x 16: C0 / 4 and the density x 16
    assert materials[1]["rho0"] == pytest.approx(16 * 2703.0) and materials[1]["bulk_sound_speed"] == 1310.0
    assert section_x(case) == pytest.approx(40e-6)


def test_the_empty_channel_and_lubrication_rates():
    case = load_case(CHANNEL).model
    # plane Poiseuille: centreline f H^2 rho / (8 eta) = 39.2 m/s; lubrication: 140 um over 205 um of the cell in
    # series with 90 um over the workpiece and its support (95 um)
    assert case.medium.centreline_speed(140e-6) == pytest.approx(39.2)
    resistance = 205e-6 / 140e-6**3 + 95e-6 / 90e-6**3
    assert lubrication_rate(case) == pytest.approx(1000 * 8e7 * 300e-6 * 130e-6 / (12 * 5.0 * resistance))


@pytest.mark.parametrize("override, words", [
    ("grain.height=125e-6", "grain.height = 0.000125 m puts the grain (radius 2.5e-05 m) outside the fluid"),
    ("grain.start=170e-6", "grain.start = 0.00017 m, grain.height = 4.5e-05 m: the grain overlaps the workpiece"),
    ("grain.diameter=150e-6", "grain.diameter = 0.00015 m is not smaller than the channel"),
    ("grain.diameter=100e-6", "grain.height = 4.5e-05 m puts the grain (radius 5e-05 m) outside the fluid"),
    ("workpiece.height=85e-6", "workpiece.height = 8.5e-05 m leaves 5.5e-05 m over it"),
    ("grain.density=0", "grain.density"),
    ("medium.density=-1000", "medium.density"),
    ("medium.viscosity=0", "medium.viscosity"),
    ("workpiece.front=181e-6", "workpiece.front = 0.000181 m is not a whole number of numerics.dx"),
    ("workpiece.length=110e-6", "reaches beyond channel.length - 2 dx"),
    ("workpiece.solid.smoothing=0.001", "workpiece.solid.smoothing = 0.001: a workpiece in the medium needs"),
    ("workpiece.mass_scaling=3000", "workpiece.mass_scaling = 3000 leaves a wave speed"),
])
def test_bad_channels_are_named_in_one_line(override, words):
    with pytest.raises(CaseError) as error:
        load_case(CHANNEL, overrides=[override])
    lines = str(error.value).splitlines()
    assert len(lines) == 2 and words in lines[1], lines


def _frame(x, kind, damage=None):
    return {"positions": x, "kind": kind, "damage": np.zeros(len(x)) if damage is None else damage}


def test_the_edge_drop_and_the_removed_particles_on_synthetic_frames():
    case = load_case(CHANNEL, preset="quick").model
    dx, wall = 10e-6, 30e-6
    i, j, k = np.meshgrid(np.arange(7), np.arange(13), np.arange(5), indexing="ij")
    x0 = np.column_stack([180e-6 + (i.ravel() + 0.5) * dx, (j.ravel() + 0.5) * dx, wall + (k.ravel() + 0.5) * dx])
    kind = np.zeros(len(x0), dtype=int)
    x = x0.copy()
    # the front top particle of column y = 5 um pushed down by half a spacing; the one at y = 65 um failed and
    # carried 5 dx up into the medium
    front_top = (np.abs(x0[:, 0] - 185e-6) < 1e-9) & (np.abs(x0[:, 2] - 75e-6) < 1e-9)
    pushed = front_top & (np.abs(x0[:, 1] - 5e-6) < 1e-9)
    torn = front_top & (np.abs(x0[:, 1] - 65e-6) < 1e-9)
    x[pushed, 2] -= 0.5 * dx
    x[torn, 2] += 5 * dx
    damage = np.where(torn, 1.0, 0.0)
    out = workpiece_quantities(case, _frame(x0, kind), _frame(x, kind, damage), [])
    assert out["removed_count"] == 1 and out["failed_count"] == 1
    assert out["removed_volume"] == pytest.approx(dx**3)
    # the torn column lays the row below bare: one dx down; the pushed one half a dx
    assert out["edge_drop"] == pytest.approx(dx)
    assert out["lowered_volume"] == pytest.approx(1.5 * dx**3)


@pytest.mark.sph
def test_the_quick_channel(tmp_path, capsys):
    """10 um spacing, 2 threads, about a minute: the grain is carried over the edge and presses it; the workpiece
    in the flowing medium stays elastic and still away from the edge; the flow rate lies below lubrication
    theory's."""
    from orchestrator.runh5 import read_run

    out = tmp_path / "run"
    assert main(["run", str(CHANNEL), "--preset", "quick", "--out", str(out)]) == 0
    run = read_run(out)
    m = run["measured"]["attrs"]
    # measured: the grain travels 208 um at 13.8 m/s on average (18.6 at most) and turns 1.6 rad; it presses the
    # edge for 0.79 us with up to 33.1 mN over every step (32.4 in the series' samples, one step in 25); the medium
    # passes at 0.72 of the lubrication estimate
    assert m["grain_travel"] > 150e-6 and m["grain_speed_max"] < 1.2 * 39.2
    assert m["edge_penetration"] > 0.0 and m["contact_force_max"] > 10e-3 and 0.0 < m["contact_time"] < 15e-6
    sampled = np.linalg.norm(np.asarray(run["series"]["grain_grain_contact"]), axis=1)
    assert sampled.max() <= m["contact_force_max"] < 1.5 * sampled.max()  # the peak of every step holds the samples'
    assert m["contact_impulse"] < np.trapezoid(sampled, np.asarray(run["series"]["time"]))  # |int F| < int |F|
    assert m["grain_turn"] > 0.5  # it rolls over the step, turning clockwise seen along -y (omega_y > 0)
    assert 0.5 < m["flow_rate"] / m["flow_rate_lubrication"] < 1.0
    assert m["failed_count"] == 0
    frames = sorted((k for k in run["frames"] if k != "attrs"), key=int)
    first, last = run["frames"][frames[0]], run["frames"][frames[-1]]
    workpiece = (np.asarray(last["material"]) == 1) & (np.asarray(last["kind"]) == 0)
    # before eq. FS2 the medium's shear entered the solid's velocity gradient: its rows slid and yielded far from
    # any contact; now only the edge the grain presses yields (4.4e-4 at most in this run)
    x0 = np.asarray(first["positions"])
    far = workpiece & ((x0[:, 0] > 180e-6 + 30e-6) | (x0[:, 2] < 80e-6 - 30e-6))
    assert np.asarray(last["plastic_strain"])[far].max() < 1e-12
    assert np.linalg.norm(np.asarray(last["velocities"])[workpiece], axis=1).max() < 0.01 * 39.2
    assert main(["analyze", str(out)]) == 0
    assert "edge_drop" in capsys.readouterr().out and (out / "channel.png").is_file()
