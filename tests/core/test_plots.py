"""PNG figures of a run: the force plot (matplotlib, Agg) and the network rendering (pyvista, off-screen)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from orchestrator.errors import ReadError
from orchestrator.kinds.drag_finishing.plots import _rod_at, plot_drag_finishing_forces, render_network
from orchestrator.report import analyze_run
from orchestrator.runh5 import stored_case
from orchestrator.runh5 import read_run


def _image(path):
    from matplotlib.image import imread

    assert path.is_file()
    assert path.stat().st_size > 20_000, f"{path} is suspiciously small ({path.stat().st_size} bytes)"
    return imread(path)[..., :3]


def _assert_not_blank(rgb):
    assert rgb.std() > 0.05, "the image is (almost) one colour"
    colours = np.unique((rgb * 255).astype(np.uint8).reshape(-1, 3), axis=0)
    assert len(colours) > 50


def test_force_plot_is_written_and_not_blank(synthetic_run):
    run = read_run(synthetic_run)
    path = plot_drag_finishing_forces(run, stored_case(run, "run.h5"), synthetic_run / "forces.png")
    assert path == synthetic_run / "forces.png"
    rgb = _image(path)
    assert rgb.shape[0] > 600 and rgb.shape[1] > 800
    _assert_not_blank(rgb)


def test_force_plot_without_process_phase(synthetic_run, tmp_path):
    run = read_run(synthetic_run)
    run["series"]["phase"] = np.zeros_like(run["series"]["phase"])
    run["attrs"]["process_start_time"] = math.nan
    run["attrs"]["status"] = "timeout"
    path = plot_drag_finishing_forces(run, stored_case(run, "run.h5"), tmp_path / "sub" / "forces.png")
    _assert_not_blank(_image(path))


def test_network_rendering_is_written_coloured_and_not_blank(synthetic_run):
    run = read_run(synthetic_run)
    path = render_network(run, synthetic_run / "network.png")
    rgb = _image(path)
    assert rgb.shape[:2] == (900, 1200)
    _assert_not_blank(rgb)
    red = (rgb[..., 0] > 0.55) & (rgb[..., 1] < 0.3) & (rgb[..., 2] < 0.3)
    green = (rgb[..., 1] > 0.35) & (rgb[..., 0] < 0.3) & (rgb[..., 2] < 0.35)
    assert red.sum() > 500, "no red tube: the largest forces are not drawn"
    assert green.sum() > 100, "no green tube: the smallest forces are not drawn"


def test_network_rendering_of_a_missing_snapshot_is_a_read_error(synthetic_run, tmp_path):
    with pytest.raises(ReadError, match="no contact snapshot 5"):
        render_network(read_run(synthetic_run), tmp_path / "n.png", k=5)


def test_network_without_compressive_contacts_still_renders(synthetic_run, tmp_path):
    run = read_run(synthetic_run)
    run["contacts"]["0"]["normal_force"] = -np.abs(run["contacts"]["0"]["normal_force"])
    _assert_not_blank(_image(render_network(run, tmp_path / "n.png")))


def test_rod_is_turned_back_to_the_snapshot_time(synthetic_run):
    import pyvista as pv

    run = read_run(synthetic_run)
    final = pv.PolyData(np.array([[0.004, 0.0, 0.01], [0.0, 0.004, 0.02]]))
    params = run["case"]["attrs"]
    omega = params["workpiece.speed"] / params["workpiece.path_radius"]  # rad/s
    earlier = _rod_at(run, final, run["attrs"]["simulated_time"] - 0.1)
    angle = -omega * 0.1
    np.testing.assert_allclose(earlier.points[0], [0.004 * math.cos(angle), 0.004 * math.sin(angle), 0.01], atol=1e-12)
    np.testing.assert_allclose(earlier.points[:, 2], [0.01, 0.02])
    np.testing.assert_allclose(_rod_at(run, final, run["attrs"]["simulated_time"]).points, final.points)


def test_analyze_writes_both_pngs(synthetic_run, capsys):
    outputs = analyze_run(synthetic_run)
    assert {"forces", "network"} <= set(outputs)  # and the contact-chain pictures (tests/kinds/drag_finishing/test_contact_chains.py)
    for path in outputs.values():
        _assert_not_blank(_image(path))
    assert "paper, simulated" in capsys.readouterr().out
