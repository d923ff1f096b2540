"""What the solid kinds' LAMMPS MACHDYN adapters share (the Taylor bar's and the crater's): the frame dump's
columns and its reader, one record as the sph reader's frame arrays, and the adapter itself (one deck rendered
from the kind's template and one data file; what MACHDYN lacks refused before anything is written). The
mapping of the material onto MACHDYN is machdyn.py's."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from orchestrator.engines.liggghts_files import read_dump
from orchestrator.errors import OrchestratorError
from orchestrator.kinds.base import Adapter
from orchestrator.kinds.sph_flow.machdyn import refusal, run_steps, solid_material
from orchestrator.templating import render

#: The frame dump, written by the decks of both kinds.
DUMP = "output/frames.dump"
#: Columns of the dump, in the decks' order.
DUMP_COLUMNS = ("id", "x", "y", "z", "vx", "vy", "vz", "c_plastic_strain", "c_energy")


_LOOP = re.compile(r"Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms")


def loop_times(log: str) -> dict[str, float]:
    """engine_wall_time_s (s) and particle_steps_per_s (1/s) of the last "Loop time" line of a LAMMPS log ({}
    without one)."""
    loops = _LOOP.findall(log)
    if not loops:
        return {}
    wall, _, done, atoms = loops[-1]
    out = {"engine_wall_time_s": float(wall)}
    if float(wall) > 0:
        out["particle_steps_per_s"] = int(done) * int(atoms) / float(wall)
    return out


def read_frames(path: Path) -> list[tuple[int, np.ndarray]]:
    """(step, rows (n, 9) in DUMP_COLUMNS order) of every complete record of the dump ([] without one); records
    after one with other columns are dropped."""
    records = []
    for step, columns, rows in read_dump(path):
        if columns != list(DUMP_COLUMNS):
            break
        records.append((step, rows))
    return records


def frame_arrays(rows: np.ndarray, masses, kind=None) -> dict[str, np.ndarray]:
    """One record as the sph reader's frame arrays: ids (from 0), positions m, velocities m/s, plastic_strain and
    internal_energy J/kg (MACHDYN's per-particle energy over its mass). masses: kg, one for all or one per
    particle in input order; kind: the scene's (0 moving, 1 held), copied into the frame when given."""
    rows = rows[np.argsort(rows[:, 0])]
    frame = {"ids": rows[:, 0].astype(np.int64) - 1, "positions": rows[:, 1:4].copy(),
             "velocities": rows[:, 4:7].copy(), "plastic_strain": rows[:, 7].copy(),
             "internal_energy": rows[:, 8] / masses}
    if kind is not None:
        frame["kind"] = np.asarray(kind, dtype=np.int8).copy()
    return frame


class MachdynAdapter(Adapter):
    """A solid kind on LAMMPS MACHDYN: the kind's deck (templates[0]) and data file. A kind sets `label` (its name
    in messages), the equations of state it maps (`eos`), whether an elastic solid may run (`elastic`), the file
    names, and defines the three methods of its scene that this class calls: write_data(scene, path),
    context(scene) -> the template's variables, read(workdir, scene, steps) -> Result."""

    engine = "lammps"
    label = "solid"
    eos: tuple[str, ...] = ("linear",)
    elastic = False
    deck_file = "lammps.in"
    data_file = "solid.data"

    def steps(self, scene) -> tuple[int, float, int]:
        """(planned steps, dt s, steps per frame) of the run (machdyn.run_steps)."""
        return run_steps(scene)

    def check_scene(self, profile, scene) -> None:
        """OrchestratorError naming what MACHDYN lacks for this solid (exit 2 at the command line)."""
        reason = refusal(solid_material(scene).solid, eos=self.eos, elastic=self.elastic)
        if reason:
            raise OrchestratorError(f"LAMMPS MACHDYN cannot run this {self.label}: {reason}; run it with --engine sph")

    def write_input(self, profile, scene, workdir: Path) -> None:
        workdir = Path(workdir)
        (workdir / "output").mkdir(exist_ok=True)
        self.write_data(scene, workdir / self.data_file)
        (workdir / self.deck_file).write_text(render(self.templates[0], self.context(scene)))

    def command(self, profile, scene, workdir: Path) -> tuple[list[str], dict[str, str]]:
        return profile.command(self.deck_file)

    def read_output(self, profile, scene, workdir: Path):
        return self.read(Path(workdir), scene, self.steps(scene))

    def planned_steps(self, profile, scene) -> int:
        return self.steps(scene)[0]
