"""Rigid grains on the tensor path (eq. G1 in pair_loop.h's pair terms, grain_pairs.h's tensor_grain_reaction), which
a fluid beside Johnson-Cook solids takes: the same settling grain run on the scalar path (oil alone) and on the tensor
path (oil beside a declared solid material that no block uses, so the physics is the same) follows one trajectory."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from paths import REPO

from orchestrator.runh5 import read_run

pytestmark = pytest.mark.sph

OIL = REPO / "tests/kinds/sph_flow/data/sph_grain_in_oil.toml"
UNUSED_SOLID = (REPO / "tests/kinds/sph_flow/data/solid_layer_material.toml").read_text() + "[physics]"


def _grain_series(case, out):
    done = subprocess.run([sys.executable, "-m", "orchestrator", "run", str(case), "--out", str(out), "--no-progress"],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    series = read_run(out)["series"]
    return {key: np.asarray(series[f"grain_grain_{key}"]) for key in ("position", "velocity", "force")}


def test_a_settling_grain_moves_alike_on_the_scalar_and_the_tensor_path(tmp_path):
    text = OIL.read_text()
    assert text.count("[physics]") == 1
    tensor_case = tmp_path / "tensor.toml"
    tensor_case.write_text(text.replace("[physics]", UNUSED_SOLID))
    scalar, tensor = _grain_series(OIL, tmp_path / "scalar"), _grain_series(tensor_case, tmp_path / "tensor")
    # measured: the speed (26 mm/s at 0.05 s) 1e-5 apart at the end, 6e-4 of it at most over the run; the position
    # 2.2e-8 m; without the grain's reaction on the tensor path the grain would fall freely (0.5 m/s at 0.05 s)
    speed = scalar["velocity"][-1, 2]
    assert speed == pytest.approx(-0.026, rel=0.05)
    assert np.abs(tensor["velocity"] - scalar["velocity"]).max() < 2e-3 * abs(speed)
    assert np.abs(tensor["position"] - scalar["position"]).max() < 1e-7
    weight = np.abs(scalar["force"][-10:, 2]).mean()  # the fluid's force on the grain nearly carries its weight
    assert np.abs(tensor["force"][-10:, 2] - scalar["force"][-10:, 2]).max() < 1e-3 * weight
