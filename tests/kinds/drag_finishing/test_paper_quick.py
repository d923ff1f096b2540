"""The paper's drag-finishing setup, quick preset (about 6 minutes on one core): slow, deselected by default.

Run with: .venv/bin/python -m pytest -m slow tests/kinds/drag_finishing/test_paper_quick.py
"""

import subprocess
import sys

import numpy as np
import pytest

from orchestrator.runh5 import read_run
from paths import CASES

CASE = CASES / "drag_finishing_uhlmann2015.toml"

pytestmark = [
    pytest.mark.slow,
    pytest.mark.yade,
    pytest.mark.yade,
]


def test_quick_preset_reproduces_the_paper_force_band(tmp_path):
    out = tmp_path / "quick"
    proc = subprocess.run([sys.executable, "-m", "orchestrator", "run", str(CASE), "--preset", "quick",
                           "--out", str(out), "--no-progress"], capture_output=True, text=True, timeout=1800)
    assert proc.returncode == 0, proc.stderr
    run = read_run(out)
    assert run["attrs"]["status"] == "ok" and run["attrs"]["engine"] == "yade"
    measured = run["measured"]["attrs"]
    # paper: simulated -1.99 +- 0.63 N, measured -2.59 +- 0.66 N
    assert -4.0 < measured["fn_mean"] < -1.0
    assert 0.0 < measured["fn_std"] < 2.0
    assert measured["bed_height"] == pytest.approx(0.070, abs=0.004)
    net = run["contacts"]["0"]
    assert net["attrs"]["process_time"] == pytest.approx(1.5, abs=2e-3)
    assert len(net["normal_force"]) > 2000 and np.all(net["normal_force"] >= 0)
    assert run["meshes"]["rod"]["contact_intensity"].max() > 0
