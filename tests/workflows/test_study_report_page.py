"""The study report as a user sees it: its figures' labels (measured with matplotlib's renderer), and the page
rendered by a real headless Chromium (screenshot and DOM) from a synthetic study folder, no engine needed."""

from __future__ import annotations

import csv
import itertools
import json
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from conftest import build_synthetic_run
from orchestrator.study.report import speed_error_figure, write_study_report

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
needs_chromium = pytest.mark.skipif(CHROMIUM is None, reason="Chromium is not installed (apt-get install -y chromium); "
                                    "the report page is checked in a real headless browser")
#: A path of this machine, as it would leak into a page: a root folder of a Unix file system and one more part.
ABSOLUTE_PATH = re.compile(r"(?<![\w.:/])/(?:tmp|home|root|work|usr|var|mnt|opt|srv)/\w")


def label_boxes(fig):
    """The window boxes (pixels) of the figure's point labels, per axes: {axes: [Bbox, ...]}."""
    from matplotlib.text import Annotation, Text

    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    boxes = {}
    for ax in fig.axes:
        notes = [t for t in ax.texts if isinstance(t, Annotation)]
        boxes[ax] = [Text.get_window_extent(t, renderer) for t in notes]
    return boxes


def assert_labels_clear(fig, expected: int):
    """Every point label lies inside its axes and overlaps no other label; at least `expected` in all."""
    total = 0
    for ax, boxes in label_boxes(fig).items():
        frame = ax.get_window_extent()
        for box in boxes:
            assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1, \
                (box, frame)
        for a, b in itertools.combinations(boxes, 2):
            assert not a.overlaps(b), (a, b)
        total += len(boxes)
    assert total >= expected


def crowded_points(n=14, seed=2):
    """Wall times (s) within a factor of 1.6 and errors within a factor of 3: labels must move to fit."""
    rng = np.random.default_rng(seed)
    walls = list(10 * np.exp(rng.uniform(0, 0.5, n)))
    errors = list(0.05 * np.exp(rng.uniform(0, 1.1, n)))
    return walls, errors


def test_speed_error_labels_stay_inside_and_apart():
    from orchestrator.study.report import pareto_front

    walls, errors = crowded_points()
    walls.append(40.0)
    errors.append(0.0)  # the reference run
    front = pareto_front(walls, errors)
    labels = [f"stiffness_scale = {10 ** -k:g}, seed = {k}" for k in range(len(walls))]
    fig = speed_error_figure(walls, errors, front, labels, [f"#{k + 1}" for k in range(len(walls))], "fn_mean", 0.05)
    assert_labels_clear(fig, expected=10)
    ax = fig.axes[0]
    smallest = min(e for e in errors if e > 0)
    # the reference (error 0) is no point of the log axis, and the Pareto line does not drop to it
    points = np.vstack([c.get_offsets() for c in ax.collections])
    assert points[:, 1].min() == pytest.approx(smallest, rel=1e-12)
    front_line = [line for line in ax.get_lines() if line.get_label() == "Pareto front"][0]
    assert min(front_line.get_ydata()) >= smallest * (1 - 1e-12)
    assert max(front_line.get_xdata()) == pytest.approx(40.0, rel=1e-12)  # it runs level to the reference's line
    assert ax.get_ylim()[0] > smallest / 10
    marks = [line for line in ax.get_lines() if "error 0" in line.get_label()]
    assert len(marks) == 1 and marks[0].get_xdata()[0] == pytest.approx(40.0)
    # plain tick numbers, no "8 x 10^0"
    ticks = [t.get_text() for axis in (ax.xaxis, ax.yaxis) for minor in (False, True)
             for t in axis.get_ticklabels(minor=minor) if t.get_text()]
    assert ticks and not any("$" in t or "10^" in t or "times" in t for t in ticks), ticks
    assert all(float(t) > 0 for t in ticks)


def test_drag_finishing_quantity_panels_keep_labels_apart():
    from orchestrator.kinds.drag_finishing.study_pictures import quantities_figure

    walls, errors = crowded_points(n=12, seed=5)
    rows = [{"run_id": f"{k:064d}", "engine": "yade", "status": "ok", "param:numerics.stiffness_scale": 10 ** -k,
             "param:case.seed": k, "wall_time_s": w, "fn_mean": -2 * (1 + e), "fn_sem": 0.05, "fn_std": 0.3 + e,
             "contact_fn_max": 1 + e, "contact_fn_p99": 0.2 + e} for k, (w, e) in enumerate(zip(walls, errors))]
    fig = quantities_figure(rows)
    assert len(fig.axes) == 4
    assert_labels_clear(fig, expected=4 * 6)


def write_study_folder(folder: Path, with_run: bool) -> Path:
    """A study folder as `orchestrator study` leaves it: study.json (its name differs from the folder's) and
    index.csv of a stiffness sweep; with_run: the finest run's directory holds a synthetic run.h5."""
    folder.mkdir(parents=True)
    (folder / "study.json").write_text(json.dumps({"name": "stiffness_sweep", "kind": "drag_finishing",
                                                   "description": "four stiffness factors, two seeds"}))
    rows = []
    for k, (scale, seed) in enumerate(itertools.product((1.0, 0.1, 0.01, 0.001), (7, 8))):
        run_dir = folder / f"yade-{k:012d}"
        rows.append({"run_id": f"{k:064d}", "engine": "yade", "run_dir": str(run_dir),
                     "param:numerics.stiffness_scale": scale, "param:case.seed": seed,
                     "status": "failed" if k == 7 else "ok", "wall_time_s": 1000 * scale ** 0.5 + seed,
                     "dt": 1e-7 / scale ** 0.5,
                     "fn_mean": "" if k == 7 else -2.0 * (1 + 0.3 * (1 - scale ** 0.25)) - 0.01 * seed,
                     "fn_sem": 0.02, "fn_std": 0.3})
    with open(folder / "index.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    if with_run:
        build_synthetic_run(folder / "yade-000000000000")
    return folder


def chromium(*args: str, tmp_path: Path) -> subprocess.CompletedProcess:
    """Run headless Chromium (as the test user, even root) with a fresh profile; returns the finished process."""
    profile = tmp_path / "chromium-profile"
    profile.mkdir(exist_ok=True)
    command = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
               "--disable-background-networking", "--disable-component-update", "--disable-sync",
               f"--user-data-dir={profile}", *args]
    return subprocess.run(command, capture_output=True, text=True, timeout=180, cwd=tmp_path)


def test_page_names_the_study_and_no_path_of_this_machine(tmp_path):
    folder = write_study_folder(tmp_path / "some_folder", with_run=False)
    html = write_study_report(folder).read_text()
    assert "<title>Study stiffness_sweep</title>" in html and "<h1>Study stiffness_sweep</h1>" in html
    assert "some_folder" not in html
    assert "from index.csv." in html
    assert str(tmp_path) not in html and not ABSOLUTE_PATH.search(html), ABSOLUTE_PATH.search(html)
    assert "Error 0 (#2)" in html  # the reference run, named beside the figure instead of drawn at a fake error
    # the same stiffness with the other seed is within 0.5 % and about as slow: no "1 x faster"
    assert "#1, numerics.stiffness_scale = 1.0, case.seed = 7 on yade" in html
    assert "(the reference run took 1008.0 s)" in html


@needs_chromium
def test_report_page_in_headless_chromium(tmp_path):
    from PIL import Image

    folder = write_study_folder(tmp_path / "study", with_run=True)
    page = write_study_report(folder)
    html = page.read_text()
    assert not ABSOLUTE_PATH.search(html) and str(tmp_path) not in html
    url = page.resolve().as_uri()

    shot = tmp_path / "page.png"
    done = chromium("--window-size=1280,2600", "--hide-scrollbars", f"--screenshot={shot}", url, tmp_path=tmp_path)
    assert shot.is_file(), done.stderr[-2000:]
    pixels = np.asarray(Image.open(shot).convert("L"), dtype=float)
    assert pixels.shape == (2600, 1280)
    # rendered, not blank: dark text and plot lines over a good part of the page, on a white background
    ink = pixels < 128
    assert 0.01 < ink.mean() < 0.5
    assert ink.any(axis=1).mean() > 0.3  # ink on many lines of the page, not one stray mark

    dom = chromium("--dump-dom", url, tmp_path=tmp_path).stdout
    assert "<h1>Study stiffness_sweep</h1>" in dom
    assert not ABSOLUTE_PATH.search(dom)
    images = re.findall(r'<img alt="([^"]*)" src="data:image/png;base64,', dom)
    # speed against error, the kind's quantities against wall time, and the force plot of the one stored run
    assert images[0] == "wall time against error" and "Measured quantities against wall time" in images
    assert any(alt.startswith("Run #1:") for alt in images) and len(images) == 3
    assert dom.count("<tr") == 1 + 8 and dom.count('class="failed"') == 1
