"""The file formats LIGGGHTS-PUBLIC 3.8 reads (read_data files, ASCII STL) and writes (text dumps, fix print
tables, its log's ERROR lines), SI units."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from orchestrator.errors import ReadError


# ---- files LIGGGHTS reads ----
def write_stl_ascii(path: Path, vertices: np.ndarray, faces: np.ndarray, name: str) -> None:
    """An ASCII STL (LIGGGHTS 3.8 reads no binary STL) with full double precision, m."""
    vertices = np.asarray(vertices, dtype=float)
    lines = [f"solid {name}"]
    for face in np.asarray(faces, dtype=np.int64):
        a, b, c = vertices[face]
        normal = np.cross(b - a, c - a)
        size = np.linalg.norm(normal)
        normal = normal / size if size > 0 else normal
        lines.append(" facet normal %r %r %r" % tuple(float(v) for v in normal))
        lines.append("  outer loop")
        lines.extend("   vertex %r %r %r" % tuple(float(v) for v in corner) for corner in (a, b, c))
        lines.append("  endloop")
        lines.append(" endfacet")
    lines.append(f"endsolid {name}")
    Path(path).write_text("\n".join(lines) + "\n")


def write_data_file(path: Path, box: np.ndarray, n_types: int, types: np.ndarray, radii: np.ndarray,
                    densities: np.ndarray, positions: np.ndarray, velocities: np.ndarray | None = None,
                    angular_velocities: np.ndarray | None = None) -> None:
    """A read_data file of granular atoms (ids from 1 in the scene's order); box (3, 2) m; SI units."""
    out = ["LIGGGHTS data file written by orchestrator (SI units)", "", f"{len(radii)} atoms",
           f"{n_types} atom types", ""]
    out += [f"{float(box[k, 0])!r} {float(box[k, 1])!r} {axis}lo {axis}hi" for k, axis in enumerate("xyz")]
    out += ["", "Atoms", ""]
    out += [f"{i + 1} {int(t)} {2.0 * float(r)!r} {float(rho)!r} {float(p[0])!r} {float(p[1])!r} {float(p[2])!r}"
            for i, (t, r, rho, p) in enumerate(zip(types, radii, densities, positions))]
    if velocities is not None:
        spins = np.zeros_like(velocities) if angular_velocities is None else angular_velocities
        out += ["", "Velocities", ""]
        out += [f"{i + 1} " + " ".join(repr(float(v)) for v in (*vel, *spin))
                for i, (vel, spin) in enumerate(zip(velocities, spins))]
    Path(path).write_text("\n".join(out) + "\n")


# ---- files LIGGGHTS writes ----
def read_dump(path: Path) -> list[tuple[int, list[str], np.ndarray]]:
    """A LAMMPS text dump (custom or local) as [(step, column names, rows (n, k))]; a cut-off last
    snapshot is dropped."""
    if not Path(path).is_file():
        return []
    snapshots = []
    text = Path(path).read_text()
    for block in text.split("ITEM: TIMESTEP\n")[1:]:
        lines = block.split("\n")
        try:
            step = int(lines[0])
            count = int(lines[2])
            header = next(k for k, line in enumerate(lines) if line.startswith("ITEM: ATOMS")
                          or line.startswith("ITEM: ENTRIES"))
        except (ValueError, IndexError, StopIteration):
            break
        columns = lines[header].split()[2:]
        body = lines[header + 1: header + 1 + count]
        if len(body) < count or (count and len(body[-1].split()) != len(columns)):
            break
        rows = np.array(" ".join(body).split(), dtype=float).reshape(count, len(columns)) if count else \
            np.zeros((0, len(columns)))
        snapshots.append((step, columns, rows))
    return snapshots


def read_table(path: Path, key: str | None = None) -> dict[str, np.ndarray]:
    """A whitespace table with a '# name name ...' title line (fix print output) as name -> column; rows
    cut off or not numeric are dropped, and with a key column only the first row of each key value is kept."""
    path = Path(path)
    if not path.is_file():
        return {}
    lines = path.read_text().splitlines()
    if not lines or not lines[0].startswith("#"):
        raise ReadError(f"{path} has no '# column ...' title line")
    names = lines[0][1:].split()
    rows = []
    for line in lines[1:]:
        parts = line.split()
        if len(parts) != len(names):
            continue
        try:
            rows.append([float(p) for p in parts])
        except ValueError:
            continue
    data = np.array(rows, dtype=float).reshape(-1, len(names))
    if key is not None and len(data):  # a row written twice at one step (a record at a phase change) counts once
        _, first = np.unique(data[:, names.index(key)], return_index=True)
        data = data[np.sort(first)]
    return {name: data[:, i] for i, name in enumerate(names)}


def engine_error(log_text: str) -> str:
    """The first 'ERROR' line of a LIGGGHTS log, without the source location ('' if none)."""
    for line in log_text.splitlines():
        if line.startswith("ERROR") or "ERROR on proc" in line:
            return re.sub(r"\s*\(\S+:\d+\)\s*$", "", line.split(":", 1)[1].strip() if ":" in line else line)
    return ""
