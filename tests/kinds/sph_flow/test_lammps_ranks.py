"""One sph_flow case on LAMMPS on 1 and on 2 MPI ranks: the same answers, a different run identity.

The Poiseuille start-up of Morris et al. 1997 (cases/verification), cut to 0.2 s (about 1 s of LAMMPS per run;
profiles at 0.02, 0.04, 0.1 and 0.2 s). Two ranks split the channel into two subdomains, so each particle's force
sums its neighbours in another order and the runs are not bitwise equal; measured, every fluid particle's velocity
differs by about 1e-20 m/s (4e-16 of the 2.5e-5 m/s peak) after 0.2 s. The test asks the verification rows
(kinds/sph_flow/checks.py) to agree within the case's tolerance (0.02 of the peak) and every velocity within 1e-9 of
the peak, a bound that holds only when the two runs differ by rounding.
"""

from __future__ import annotations

import numpy as np
import pytest
from paths import VERIFICATION

from orchestrator.case import load_case
from orchestrator.identity import run_identity
from orchestrator.kinds import bind, build_scene

CASE = VERIFICATION / "sph_poiseuille_morris1997.toml"
SHORT = ["simulation.duration=0.2"]
#: The steady peak speed F L^2 / (8 nu) of the case, m/s: the scale of its u_profile rows.
PEAK = 2.5e-5


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """{ranks: (run.h5 as read_run gives it, verification rows)} for 1 and 2 ranks, run back to back."""
    from orchestrator.kinds.sph_flow.checks import check_run
    from orchestrator.run import run_case
    from orchestrator.runh5 import read_run

    loaded = load_case(CASE, overrides=SHORT)
    out = {}
    for ranks in (1, 2):
        run_dir = tmp_path_factory.mktemp(f"ranks{ranks}")
        summary = run_case(loaded, engine="lammps", out_dir=run_dir, progress=False, force=True, mpi_ranks=ranks)
        assert summary.status == "ok", summary.message
        run = read_run(run_dir)
        rows, _ = check_run(loaded.model, "lammps", run)
        out[ranks] = (run, rows)
    return out


@pytest.mark.lammps
def test_two_ranks_measure_what_one_rank_measures(runs):
    (one, rows_1), (two, rows_2) = runs[1], runs[2]
    assert "-n 2" in str(two["attrs"]["command"]) and "-n 2" not in str(one["attrs"]["command"])
    assert [r["quantity"] for r in rows_1] == [r["quantity"] for r in rows_2]
    assert len(rows_1) == 4  # profiles at 0.02, 0.04, 0.1 s and the end, 0.2 s
    tolerance = rows_1[0]["tolerance"]
    assert tolerance == 0.02
    for a, b in zip(rows_1, rows_2):
        assert abs(a["value"] - b["value"]) / PEAK < tolerance, a["quantity"]
        assert abs(a["rel_error"] - b["rel_error"]) < tolerance, a["quantity"]
        assert abs(a["rel_error"] - b["rel_error"]) < 1e-9, a["quantity"]


@pytest.mark.lammps
def test_every_particle_moves_alike_on_two_ranks(runs):
    from orchestrator.kinds.sph_flow.checks_base import frames_of

    frames_1, frames_2 = frames_of(runs[1][0]), frames_of(runs[2][0])
    assert len(frames_1) == len(frames_2) == 11  # t = 0, 0.02, ..., 0.2 s
    for (t1, a), (t2, b) in zip(frames_1, frames_2):
        assert t1 == pytest.approx(t2, rel=1e-12)
        np.testing.assert_array_equal(a["ids"], b["ids"])
        difference = np.max(np.abs(np.asarray(a["velocities"]) - np.asarray(b["velocities"]))) / PEAK
        assert difference < 1e-9, f"t = {t1:.3g} s: {difference:.3g} of the peak"
        np.testing.assert_allclose(b["positions"], a["positions"], rtol=0, atol=1e-9 * 2.5e-5)  # of dx


def test_the_rank_count_is_part_of_the_run_identity():
    loaded = load_case(CASE, overrides=SHORT)
    scene = build_scene(loaded.model)

    def identity(ranks: int) -> str:
        return run_identity(loaded, "lammps", "22 Jul 2025", bind("sph_flow", "lammps", scene, mpi_ranks=ranks), scene)

    assert identity(1) != identity(2)
    assert identity(2) == identity(2)  # the same inputs on the same ranks: the same run


@pytest.mark.lammps
def test_a_study_gives_each_run_its_ranks(tmp_path):
    """[study] mpi_ranks = 2: each run starts under the MPI launcher with 2 ranks, and its identity (its folder)
    differs from the same point's on the engine's default of 1 rank."""
    import h5py

    from orchestrator.study import Study

    point = [{"simulation.duration": 0.04}]
    two = Study(CASE, point, engines=("lammps",), out_dir=tmp_path / "two", mpi_ranks=2)
    one = Study(CASE, point, engines=("lammps",), out_dir=tmp_path / "one")
    assert [r.mpi_ranks for r in two.plan()] == [2] and [r.mpi_ranks for r in one.plan()] == [1]
    assert two.plan()[0].run_id != one.plan()[0].run_id
    rows = two.run(progress=False, max_workers=1)
    assert [row["status"] for row in rows] == ["ok"], rows
    with h5py.File(two.plan()[0].run_dir / "run.h5", "r") as h5:
        assert " -n 2 " in str(h5.attrs["command"])


def test_a_study_refuses_ranks_for_an_engine_without_mpi(tmp_path):
    from orchestrator.errors import OrchestratorError
    from orchestrator.study import Study

    study = Study(CASE, [{"simulation.duration": 0.04}], engines=("sph",), out_dir=tmp_path / "s", mpi_ranks=2)
    with pytest.raises(OrchestratorError, match=r"study.mpi_ranks = 2: the sph engine does not run under MPI"):
        study.plan()
