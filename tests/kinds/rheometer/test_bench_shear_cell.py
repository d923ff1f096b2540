"""`orchestrator bench sph`'s material-model rows: one Lees-Edwards shear cell of a Newtonian fluid and of PTT
fluids of 1 and 5 modes, the same particles and step (kinds/sph_flow/bench_scenes.py)."""

import pytest

from orchestrator.case import load_case
from orchestrator.case.loader import to_toml
from orchestrator.kinds import build_scene
from orchestrator.kinds.sph_flow.bench_scenes import SHEAR_CELL_MODELS, shear_cell_case
from orchestrator.workflows.bench_sph import BenchRow, format_report, run_bench, summary


@pytest.mark.parametrize("model", list(SHEAR_CELL_MODELS))
def test_the_shear_cells_differ_only_in_the_material(tmp_path, model):
    path = tmp_path / "case.toml"
    path.write_text(to_toml(shear_cell_case(10, 1, model)))
    case = load_case(path).model
    scene = build_scene(case)
    assert scene.n_particles == 10_000 and case.numerics.dt == pytest.approx(1.3e-4)
    assert case.lees_edwards.shear_rate == 1.0
    material = scene.materials[0]
    if model == "newtonian":
        assert material.mu == pytest.approx(10.0)  # the PTT fluids' zero-shear viscosity sum eta_i
    else:
        assert sum(eta for _, eta in material.modes) == pytest.approx(10.0)
        assert len(material.modes) == (1 if model == "ptt_1_mode" else 5)


def test_the_ptt_rows_are_compared_with_the_newtonian_one():
    def row(scene, rate):
        return BenchRow(scene, "sph 0.1.0", 1, 10_000, 10_000, 300, 20.0, 1.0, 1.0, rate, rate)

    rows = [row("bench_shear_cell_newtonian", 4e6), row("bench_shear_cell_ptt_1_mode", 2e6),
            row("bench_shear_cell_ptt_5_modes", 1e6)]
    s = summary(rows)
    assert s["shear_cell_ptt_1_mode_over_newtonian"] == pytest.approx(0.5)
    assert s["shear_cell_ptt_5_modes_over_newtonian"] == pytest.approx(0.25)
    assert "ptt 5 modes runs 0.25 x the particle-steps/s of the Newtonian fluid" in format_report(rows)


@pytest.mark.sph
def test_shear_cell_rows_run(tmp_path):
    rows = run_bench(tmp_path, steps_2d=1, steps_3d=1, threads=(1,), with_pysph=False, with_lammps=False,
                     steps_shear=20)
    cells = [r for r in rows if r.scene.startswith("bench_shear_cell")]
    assert [r.status for r in cells] == ["ok"] * 3 and all(r.steps == 20 for r in cells)
    assert all(r.particle_steps_per_s > 1e5 for r in cells)
