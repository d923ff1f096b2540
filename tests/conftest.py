"""Shared test fixtures (a small synthetic run.h5, no engine needed) and the engine markers.

A test marked ``@pytest.mark.yade``, ``liggghts``, ``sph`` or ``lammps`` needs that engine and is skipped, with the
engine's install hint as the reason, where it is missing (ENGINE_MARKERS; the one place that decides it).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

DATA = Path(__file__).parent / "data"
#: Test markers that name an engine the test needs.
ENGINE_MARKERS = ("yade", "liggghts", "sph", "lammps")


def pytest_collection_modifyitems(config, items):
    """Skip the tests marked with an engine that is not installed here (reason: the engine's install hint)."""
    from orchestrator.engines import get_engine

    missing = {}
    for name in ENGINE_MARKERS:
        engine = get_engine(name)
        if not engine.available():
            missing[name] = pytest.mark.skip(reason=f"{engine.label} is not installed: {engine.install_hint()}")
    for item in items:
        for name, skip in missing.items():
            if item.get_closest_marker(name) is not None:
                item.add_marker(skip)

@pytest.fixture(scope="session")
def tiny_bowl():
    """The tiny drag-finishing bowl (tests/data/tiny_bowl.toml) as a case model; models are immutable, so one
    instance serves the whole session."""
    from orchestrator.case import load_case
    from paths import TINY_BOWL

    return load_case(TINY_BOWL).model


@pytest.fixture(scope="session")
def tiny_bowl_scene(tiny_bowl):
    """The tiny bowl's built scene (packed media cloud, bowl and rod meshes); tests read it, none writes to it."""
    from orchestrator.kinds import build_scene

    scene = build_scene(tiny_bowl)
    for value in (scene.positions, scene.radii):
        value.flags.writeable = False  # a test that writes to the shared cloud fails at once
    return scene


#: What the synthetic run holds (tests compare exported files against these).
PROCESS_START = 0.3  # s
SIM_END = 0.6  # s
N_PARTICLES = 30
FRAME_TIMES = (0.2, 0.45, SIM_END)  # s
N_CONTACTS = 14
SNAPSHOT_TIME = 0.45  # s


def build_synthetic_run(run_dir: Path, seed: int = 3) -> Path:
    """Write run_dir/run.h5 shaped like a drag-finishing Yade run; returns the run directory.

    Series every 5 ms over 0.6 s (phases 0-3, process from 0.3 s) with
    F_n ~ -2 N and F_t ~ 0.5 N; three frames of 30 balls; one contact
    snapshot of 14 interactions (balls, bowl and rod facets; two with
    normal force <= 0); a bowl and a rod mesh (rod with per-face fields).
    The case is tests/data/tiny_bowl.toml with a 0.3 s process.
    """
    import trimesh

    from orchestrator.kinds.drag_finishing.analysis import measure_drag_finishing
    from orchestrator.engines.base import Result, Series
    from orchestrator.case import load_case
    from orchestrator.runh5 import RUN_FILE, write_run

    rng = np.random.default_rng(seed)
    run_dir = Path(run_dir)
    run_dir.mkdir(parents=True, exist_ok=True)
    loaded = load_case(
        DATA / "tiny_bowl.toml",
        overrides=[
            "process.duration=0.3",
            "analysis.transient_time=0.05",
            "output.network_times=[0.15]",
            'reference=[{label="paper, simulated", fn_mean=-1.99, fn_std=0.63},'
            ' {label="paper, measured", fn_mean=-2.4, fn_std=0.3}]',
        ],
    )

    time = np.arange(1, 121) * 0.005
    phase = np.select([time < 0.2, time < 0.25, time < PROCESS_START], [0, 1, 2], 3).astype(np.int8)
    tp = time - PROCESS_START
    force = np.full((len(time), 3), np.nan)
    proc = phase == 3
    force[proc, 0] = -2.0 + 0.4 * np.sin(2 * np.pi * 12 * tp[proc]) + 0.1 * rng.standard_normal(proc.sum())
    force[proc, 1] = 0.5 + 0.2 * np.cos(2 * np.pi * 7 * tp[proc])
    force[proc, 2] = 0.1
    force[proc & (tp < 0.05), :2] *= np.linspace(0, 1, int((proc & (tp < 0.05)).sum()))[:, None]

    result = Result(status="ok", time=time)
    result.attrs.update(n_steps=12000, dt=5e-5, simulated_time=SIM_END, process_start_time=PROCESS_START,
                        bed_height=0.018, settled=True)
    result.series = {
        "phase": Series(phase, "-", "0 settle, 1 insert, 2 relax, 3 process"),
        "workpiece_force": Series(force, "N", "[normal, tangential, vertical]"),
        "kinetic_energy": Series(np.abs(rng.standard_normal(len(time))) * 1e-5, "J"),
    }

    radii = 3.27e-3 + 0.15e-3 * rng.standard_normal(N_PARTICLES)
    for t in FRAME_TIMES:
        angle = rng.uniform(0, 2 * np.pi, N_PARTICLES)
        rho = rng.uniform(0, 0.011, N_PARTICLES)
        positions = np.column_stack([rho * np.cos(angle), rho * np.sin(angle), rng.uniform(0.003, 0.018, N_PARTICLES)])
        result.frames.append((t, {"positions": positions, "velocities": rng.standard_normal((N_PARTICLES, 3)) * 0.01,
                                  "radii": radii.copy()}))

    positions = result.frames[1][1]["positions"]
    id1 = rng.integers(0, N_PARTICLES, N_CONTACTS)
    role = np.array([0] * 8 + [1] * 4 + [2] * 2, dtype=np.int8)
    other_ball = (id1 + 1 + rng.integers(0, N_PARTICLES - 1, N_CONTACTS)) % N_PARTICLES
    id2 = np.where(role == 0, other_ball, 100 + np.arange(N_CONTACTS))
    p1 = positions[id1]
    p2 = np.where((role == 0)[:, None], positions[id2 % N_PARTICLES], p1 + [0.0, 0.0, -3.2e-3])
    normal_force = np.linspace(0.05, 1.2, N_CONTACTS)
    normal_force[3], normal_force[9] = -0.01, 0.0  # tensile and empty interactions: not drawn
    unit = (p2 - p1) / np.linalg.norm(p2 - p1, axis=1)[:, None]
    tangential = rng.standard_normal((N_CONTACTS, 3)) * 0.05
    result.contacts.append((SNAPSHOT_TIME, {
        "id1": id1, "id2": id2, "normal_force": normal_force, "normal_force_vector": normal_force[:, None] * unit,
        "tangential_force": tangential, "branch": p2 - p1, "point1": p1, "point2": p2, "body2_role": role,
        "process_time": np.float64(SNAPSHOT_TIME - PROCESS_START),
    }))

    bowl = trimesh.creation.cylinder(radius=0.015, height=0.05, sections=24)
    bowl.apply_translation([0, 0, 0.025])
    rod = trimesh.creation.cylinder(radius=0.0025, height=0.03, sections=8)
    rod.apply_translation([0.004, 0, 0.012 + 0.015])
    n_rod = len(rod.faces)
    result.meshes = {
        "bowl": {"vertices": np.asarray(bowl.vertices), "faces": np.asarray(bowl.faces)},
        "rod": {"vertices": np.asarray(rod.vertices), "faces": np.asarray(rod.faces),
                "contact_intensity": np.linspace(0.0, 0.02, n_rod), "contact_count": np.arange(n_rod, dtype=np.int64)},
    }
    result.measured = measure_drag_finishing(loaded.model, result)
    root = {"engine": "synthetic", "engine_version": "0.0", "case_name": loaded.name, "case_kind": loaded.kind,
            "case_hash": loaded.hash, "n_particles": N_PARTICLES, "wall_time_s": 1.5}
    write_run(run_dir / RUN_FILE, result, root, loaded.toml_text, loaded.resolved, "synthetic log")
    return run_dir


@pytest.fixture
def synthetic_run(tmp_path) -> Path:
    """A fresh run directory with a synthetic drag-finishing run.h5 (see build_synthetic_run)."""
    return build_synthetic_run(tmp_path / "run")
