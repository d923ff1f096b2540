"""A PTT medium beside a Johnson-Cook solid (engine eq. FS1', fluid_solid.h): the medium's whole stress, not its
pressure alone, acts across the interface. tests/kinds/sph_flow/data/sph_ptt_couette_on_layer.toml shears a one-mode
PTT medium (the polymer nine tenths of the shear stress) between a moving plate and an elastic layer.

Measured (0.04 s, 4 000 steps, 1 s): the medium's profile is linear at 0.958 of the nominal rate and reaches zero
0.04 U beyond the interface row (a Newtonian medium of the same viscosity: 0.964 and 0.036, the no-slip plane of
the solid's particles); the polymer's shear stress within 0.1 % of the closed form at the measured rate, and the
layer carries the medium's whole shear stress within 0.3 %. With the pressure alone across the interface (eq. FS1)
the polymer's stress has nothing to push on at the solid: the medium slips over it at 0.32 U."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from paths import REPO

from orchestrator.case import load_case
from orchestrator.errors import CaseError
from orchestrator.kinds.sph_flow.checks_base import frames_of
from orchestrator.reference.viscoelastic_flows import ptt_steady_shear
from orchestrator.runh5 import read_run

CASE = REPO / "tests/kinds/sph_flow/data/sph_ptt_couette_on_layer.toml"
DX, PLATE = 1e-4, 1.6e-3  # m, m/s
INTERFACE, TOP = 4e-4, 2.0e-3  # m: the layer's top and the plate's face
SOLVENT, LAMBDA, ETA_P, EPSILON = 0.1, 2e-3, 0.9, 0.1  # Pa s, s, Pa s, -


@pytest.mark.sph
def test_a_ptt_medium_shears_an_elastic_layer_with_its_whole_stress(tmp_path):
    out = tmp_path / "run"
    done = subprocess.run([sys.executable, "-m", "orchestrator", "run", str(CASE), "--out", str(out),
                           "--no-progress"], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    _, last = frames_of(read_run(out))[-1]
    x, v = np.asarray(last["positions"]), np.asarray(last["velocities"])
    material, kind = np.asarray(last["material"]), np.asarray(last["kind"])
    medium, layer = (material == 0) & (kind == 0), (material == 1) & (kind == 0)
    z, u = x[medium, 1], v[medium, 0]
    bulk = (z > INTERFACE + 2 * DX) & (z < TOP - 2 * DX)
    rate, offset = np.polyfit(z[bulk], u[bulk], 1)
    # the profile is a line to the plate, with the no-slip plane of the solid's particles (Newtonian: 0.036 U)
    assert abs(rate * (TOP - INTERFACE) / PLATE - 0.96) < 0.01
    assert 0.0 < (rate * INTERFACE + offset) / PLATE < 0.06
    polymer = np.asarray(last["mode_stress"])[medium][bulk, 0, 0, 1].mean()
    closed = float(ptt_steady_shear(rate, LAMBDA, ETA_P, EPSILON).shear_stress)
    assert polymer == pytest.approx(closed, rel=0.005)
    # the layer's mean shear stress is the medium's, solvent and polymer
    assert np.asarray(last["stress"])[layer, 0, 1].mean() == pytest.approx(SOLVENT * rate + closed, rel=0.01)


def test_a_ptt_medium_beside_a_solid_needs_the_morris_solvent(tmp_path):
    text = CASE.read_text().replace('terms = ["morris_viscosity"]', "terms = []")
    path = tmp_path / "case.toml"
    path.write_text(text.replace("solvent_viscosity = 0.1       # Pa s, the Morris term\n", ""))
    with pytest.raises(CaseError) as error:
        load_case(path)
    assert "is a ptt medium beside the johnson_cook material 'layer': physics.terms needs 'morris_viscosity'" in \
        str(error.value)


def test_two_fluids_beside_a_ptt_medium_and_a_solid_are_named(tmp_path):
    extra = '\n[[materials]]\nname = "oil"\nmodel = "newtonian"\ndensity = 900.0\nviscosity = 1e-4\n'
    path = tmp_path / "case.toml"
    path.write_text(CASE.read_text().replace("[physics]", extra + "\n[physics]"))
    with pytest.raises(CaseError) as error:
        load_case(path)
    assert "needs it to be the only fluid [[materials]] table (here also 'oil')" in str(error.value)
