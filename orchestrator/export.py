"""`orchestrator export RUN_DIR`: VTK files of a run for ParaView, written from
run.h5 with meshio (never from an engine's own dumps).

What is written into the output directory (default ``RUN_DIR/vtk``):

``particles_<k>.vtu``
    frame k (``/frames/<k>``): one vertex cell per particle at its centre
    (m); point data ``radius`` (m), ``velocity`` (m/s, 3 components) and any
    other per-particle array the frame holds, under its run.h5 name
    (SPH frames: ``density`` kg/m^3, ``pressure`` Pa, ``kind``, ``ids``; a 2D
    run's points and vectors get z = 0).
``particles.pvd``
    the frames as a time collection (timestep = the frame's simulation time, s).
``network_<k>.vtu``
    contact snapshot k (``/contacts/<k>``): one line cell per interaction from
    ``point1`` (centre of the first sphere) to ``point2`` (centre of the other
    sphere, or the contact point on a facet), m. Cell data: ``normal_force``
    (N, > 0 in compression), ``tangential_force`` (N, magnitude),
    ``normal_force_vector`` and ``tangential_force_vector`` (N, 3 components),
    ``body2_role`` (0 ball, 1 bowl facet, 2 rod facet), ``id1``, ``id2``.
``network.pvd``
    the contact snapshots as a time collection (simulation time, s).
``mesh_<name>.vtu``
    mesh ``/meshes/<name>``: triangles on its vertices (m; segments for a 2D SPH wall); every per-face
    array of the mesh as cell data (e.g. the rod's ``contact_intensity``, N s,
    and ``contact_count``, -).

Only files are written; run.h5 is opened read-only.
"""

from __future__ import annotations

from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from orchestrator.errors import OrchestratorError, ReadError
from orchestrator.humanize import os_problem
from orchestrator.outputs import claim_folder, write_text
from orchestrator.runh5 import RUN_FILE, normal_force_of, read_run

#: run.h5 frame names -> the singular names used as VTK point data.
_POINT_NAMES = {"radii": "radius", "velocities": "velocity", "densities": "density", "pressures": "pressure"}
#: Contact arrays that are geometry or handled explicitly (not copied as cell data).
_NETWORK_SPECIAL = {"point1", "point2", "branch", "normal_force", "normal_force_vector", "tangential_force"}


def export_vtk(run_dir, out_dir=None) -> list[Path]:
    """Write the VTK files of a run (see the module docstring); returns their paths in writing order.

    run_dir: a directory written by ``orchestrator run`` (or the path of its run.h5).
    out_dir: where to write; created if missing; default ``run_dir/vtk``.
    Raises ReadError when run_dir holds no readable run.h5.
    """
    run_dir = Path(run_dir)
    h5_path = run_dir if run_dir.is_file() else run_dir / RUN_FILE
    if not h5_path.is_file():
        raise ReadError(
            f"no {RUN_FILE} in {run_dir}: export needs a run directory written by 'orchestrator run' "
            f"(e.g. orchestrator run CASE --out {run_dir})"
        )
    run = read_run(h5_path)
    if "case" not in run or "status" not in run.get("attrs", {}):
        raise ReadError(f"{h5_path} has no /case group or status: it was not written by 'orchestrator run' "
                        "(or is damaged); export needs a run directory written by 'orchestrator run'")
    out = claim_folder(Path(out_dir) if out_dir is not None else h5_path.parent / "vtk", "--out", "export")
    try:
        return _write_all(run, out)
    except OSError as exc:
        raise OrchestratorError(f"cannot write the VTK files into {out}: {os_problem(exc)}") from None


def _write_all(run: dict, out: Path) -> list[Path]:
    """Every VTK file of a run read by read_run, into the folder out; their paths in writing order."""
    written: list[Path] = []
    for group_name, stem, to_mesh in (("frames", "particles", _particles_mesh), ("contacts", "network", _network_mesh)):
        series = []
        for k, group in _numbered(run.get(group_name, {})):
            path = out / f"{stem}_{k}.vtu"
            to_mesh(group, k).write(path)
            written.append(path)
            series.append((float(group["attrs"].get("time", k)), path.name))
        if series:
            written.append(_write_pvd(out / f"{stem}.pvd", series))

    for name, group in sorted((n, g) for n, g in run.get("meshes", {}).items() if n != "attrs"):
        path = out / f"mesh_{name}.vtu"
        _surface_mesh(group, name).write(path)
        written.append(path)
    return written


def _numbered(groups: dict):
    """(k, group) of the numbered subgroups /frames/<k> or /contacts/<k>, in numeric order."""
    items = [(int(key), value) for key, value in groups.items() if key != "attrs" and key.isdigit()]
    return sorted(items, key=lambda item: item[0])


def _particles_mesh(frame: dict, k: int):
    """Frame k as vertex cells at the particle centres (m) with per-particle point data."""
    import meshio

    if "positions" not in frame:
        raise ReadError(f"run.h5 /frames/{k} has no positions")
    positions = _in_3d(frame["positions"])
    n = len(positions)
    two_d = np.ndim(frame["positions"]) == 2 and np.shape(frame["positions"])[1] == 2
    point_data = {}
    for key, value in frame.items():
        if key in ("attrs", "positions"):
            continue
        array = np.asarray(value)
        if array.ndim >= 1 and array.shape[0] == n and array.ndim <= 2:
            point_data[_POINT_NAMES.get(key, key)] = _in_3d(array) if two_d and array.ndim == 2 else array
    cells = [("vertex", np.arange(n, dtype=np.int64).reshape(-1, 1))]
    return meshio.Mesh(positions, cells, point_data=point_data)


def _network_mesh(snapshot: dict, k: int):
    """Contact snapshot k as line cells point1 -> point2 (m) with per-interaction cell data."""
    import meshio

    if "point1" not in snapshot or "point2" not in snapshot:
        raise ReadError(f"run.h5 /contacts/{k} has no point1/point2 (the contact endpoints)")
    p1 = np.asarray(snapshot["point1"], dtype=float).reshape(-1, 3)
    p2 = np.asarray(snapshot["point2"], dtype=float).reshape(-1, 3)
    n = len(p1)
    fn, fn_vec = normal_force_of(snapshot)
    ft_vec = np.asarray(snapshot.get("tangential_force", np.zeros((n, 3))), dtype=float).reshape(-1, 3)
    cell_data = {
        "normal_force": [fn],
        "tangential_force": [np.linalg.norm(ft_vec, axis=1)],
        "normal_force_vector": [fn_vec],
        "tangential_force_vector": [ft_vec],
    }
    for key, value in snapshot.items():
        if key == "attrs" or key in _NETWORK_SPECIAL:
            continue
        array = np.asarray(value)
        if array.ndim in (1, 2) and array.shape[0] == n:
            cell_data[key] = [array]
    lines = np.column_stack([np.arange(n), np.arange(n, 2 * n)]).astype(np.int64)
    return meshio.Mesh(np.vstack([p1, p2]), [("line", lines)], cell_data=cell_data)


def _surface_mesh(group: dict, name: str):
    """Mesh `name` as triangles (vertices in m) with its per-face arrays as cell data."""
    import meshio

    if "vertices" not in group or "faces" not in group:
        raise ReadError(f"run.h5 /meshes/{name} has no vertices/faces")
    vertices = _in_3d(group["vertices"])
    faces = np.asarray(group["faces"], dtype=np.int64)
    cell_type = "line" if faces.ndim == 2 and faces.shape[1] == 2 else "triangle"  # 2D walls are segments
    faces = faces.reshape(-1, 2 if cell_type == "line" else 3)
    cell_data = {}
    for key, value in group.items():
        if key in ("attrs", "vertices", "faces"):
            continue
        array = np.asarray(value)
        if array.ndim in (1, 2) and array.shape[0] == len(faces):
            cell_data[key] = [array]
    return meshio.Mesh(vertices, [(cell_type, faces)], cell_data=cell_data)


def _in_3d(points) -> np.ndarray:
    """Points or vectors (n, 3), or (n, 2) of a 2D run padded with z = 0, as (n, 3) floats."""
    array = np.asarray(points, dtype=float)
    if array.ndim == 2 and array.shape[1] == 2:
        return np.column_stack([array, np.zeros(len(array))])
    return array.reshape(-1, 3)


def _write_pvd(path: Path, entries: list[tuple[float, str]]) -> Path:
    """A ParaView collection: one DataSet per (time s, file name relative to the .pvd)."""
    lines = ['<?xml version="1.0"?>',
             '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
             "  <Collection>"]
    for time_s, name in sorted(entries):
        lines.append(f'    <DataSet timestep="{time_s!r}" group="" part="0" file={quoteattr(name)}/>')
    lines += ["  </Collection>", "</VTKFile>", ""]
    return write_text(path, "\n".join(lines), "--out")
