"""run.h5: one HDF5 file per run, written by the parent process only,
atomically (a temporary name, then rename). Layout in DESIGN.md."""

from __future__ import annotations

import io
import json
import tomllib
from pathlib import Path

import numpy as np

from orchestrator.case.loader import format_validation_error
from orchestrator.engines.base import Result
from orchestrator.errors import OrchestratorError, ReadError
from orchestrator.humanize import byte_size
from orchestrator.outputs import RUN_FILE, WriteError, atomic, free_bytes, write_bytes
from orchestrator.kinds import get_kind


#: run.h5 files up to this size (bytes, estimated from the arrays) are built in memory and written in one piece,
#: so that a full disk is one clean OSError of a plain write rather than a failure inside libhdf5.
IN_MEMORY_LIMIT = 1 << 30


def write_run(path: Path, result: Result, root_attrs: dict, case_toml: str, case_params: dict, log_tail: str) -> Path:
    """Write run.h5 at path through the output policy (outputs.atomic: a temporary name, then rename); returns
    path. Raises outputs.WriteError (nothing half-written stays) when the device lacks the space the arrays need
    or the write fails."""
    import h5py

    path = Path(path)
    need = int(1.05 * _estimated_bytes(result)) + len(case_toml) + len(log_tail) + (64 << 10)
    free = free_bytes(path.parent)
    if free is not None and free < need:
        raise WriteError(f"cannot write {path}: about {byte_size(need)} needed, {byte_size(free)} free on its device")
    if need <= IN_MEMORY_LIMIT:
        buffer = io.BytesIO()
        with h5py.File(buffer, "w") as h5:
            _fill(h5, result, root_attrs, case_toml, case_params, log_tail)
        return write_bytes(path, buffer.getvalue(), RUN_FILE, own_run_file=True)
    with atomic(path, RUN_FILE, own_run_file=True) as tmp, h5py.File(tmp, "w") as h5:
        _fill(h5, result, root_attrs, case_toml, case_params, log_tail)
    return path


def _estimated_bytes(result: Result) -> int:
    """Bytes of the arrays a Result holds (what run.h5 stores, before HDF5's own overhead)."""
    total = 0 if result.time is None else np.asarray(result.time).nbytes
    total += sum(np.asarray(item.values).nbytes for item in result.series.values())
    total += sum(np.asarray(item.values).nbytes for item in result.events.values())
    for entries in (result.frames, result.contacts):
        total += sum(np.asarray(a).nbytes for _, arrays in entries for a in arrays.values())
    total += sum(np.asarray(a).nbytes for arrays in result.meshes.values() for a in arrays.values())
    return int(total)


def _fill(h5, result: Result, root_attrs: dict, case_toml: str, case_params: dict, log_tail: str) -> None:
    """Write a run's groups and attributes into an open HDF5 file (layout in DESIGN.md)."""
    for key, value in {**root_attrs, **result.attrs}.items():
        h5.attrs[key] = _attr(value)
    h5.attrs["status"] = result.status
    h5.attrs["message"] = result.message
    case = h5.create_group("case")
    case.attrs["toml"] = case_toml
    _write_params(case, case_params)
    series = h5.create_group("series")
    if result.time is not None:
        series.create_dataset("time", data=result.time).attrs["units"] = "s"
    for name, item in result.series.items():
        ds = series.create_dataset(name, data=item.values)
        ds.attrs["units"] = item.units
        if item.description:
            ds.attrs["description"] = item.description
    for group_name, entries in (("frames", result.frames), ("contacts", result.contacts)):
        group = h5.create_group(group_name)
        for k, (time_s, arrays) in enumerate(entries):
            sub = group.create_group(str(k))
            sub.attrs["time"] = time_s
            for name, array in arrays.items():
                if np.ndim(array) == 0:
                    sub.attrs[name] = array
                else:
                    sub.create_dataset(name, data=array)
    if result.events:
        events = h5.create_group("events")
        for name, item in result.events.items():
            events.create_dataset(name, data=item.values).attrs["units"] = item.units
    meshes = h5.create_group("meshes")
    for name, arrays in result.meshes.items():
        sub = meshes.create_group(name)
        for key, array in arrays.items():
            sub.create_dataset(key, data=array)
    measured = h5.create_group("measured")
    for key, value in result.measured.items():
        measured.attrs[key] = _attr(value)
    h5.create_dataset("log", data=log_tail)


def _attr(value):
    if value is None:
        return "none"
    if isinstance(value, (bool, np.bool_)):
        return np.bool_(value)
    return value


def _write_params(group, params: dict, prefix: str = "") -> None:
    """Flatten the resolved case into attributes 'a.b.c' (lists as arrays, tables of rows as JSON)."""

    for key, value in params.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            _write_params(group, value, name + ".")
        elif value is None:
            continue
        elif isinstance(value, (list, tuple)) and value and isinstance(value[0], (dict, list, str)):
            group.attrs[name] = json.dumps(value)
        elif isinstance(value, (list, tuple)):
            group.attrs[name] = np.asarray(value, dtype=float)
        else:
            group.attrs[name] = value


def read_run(path: Path) -> dict:
    """run.h5 as nested dicts of numpy arrays and attributes (for analysis, export and tests)."""
    import h5py

    path = Path(path)
    if path.is_dir():
        path = path / RUN_FILE
    if not path.is_file():
        raise ReadError(f"no run.h5 at {path}; give a run directory written by 'orchestrator run'")

    def load(node):
        out = {"attrs": {k: _plain(v) for k, v in node.attrs.items()}}
        for key, child in node.items():
            out[key] = load(child) if isinstance(child, h5py.Group) else child[()]
        return out

    try:
        with h5py.File(path, "r") as h5:
            return load(h5)
    except OSError as exc:
        raise ReadError(f"cannot read {path}: {exc}") from None


def stored_case(run: dict, path) -> object:
    """The validated case model stored in a run read by read_run (its /case group's TOML).

    Raises ReadError naming the file when run.h5 has no /case (not written by 'orchestrator run') or its case
    cannot be read or validated by this version; a case that no longer validates is named one line per problem,
    each naming its key (case.loader.format_validation_error).
    """

    from pydantic import ValidationError

    text = run.get("case", {}).get("attrs", {}).get("toml") if isinstance(run.get("case"), dict) else None
    if not isinstance(text, str):
        raise ReadError(f"{path}: run.h5 has no /case group with the case's TOML; it was not written by "
                        "'orchestrator run' (or is damaged)")
    try:
        data = tomllib.loads(text)
        model = get_kind(data["case"]["kind"]).case_model.load()
        return model.model_validate(data)
    except (tomllib.TOMLDecodeError, KeyError, TypeError, RecursionError, OrchestratorError):
        raise ReadError(f"{path}: the case stored in run.h5 (/case) is not a case this version knows") from None
    except ValidationError as exc:
        raise ReadError(f"{path}: the case stored in run.h5 no longer validates (it was written by another version "
                        f"of orchestrator):\n{format_validation_error(exc, model)}") from None


def _plain(value):
    if isinstance(value, bytes):
        return value.decode()
    if isinstance(value, np.generic):
        return value.item()
    return value


def normal_force_of(snapshot: dict) -> tuple[np.ndarray, np.ndarray]:
    """(scalar normal force (n,) N, > 0 compressive; normal force vector (n, 3) N) of a contact snapshot.

    Older run.h5 files stored only the vector under ``normal_force``; its
    magnitude then stands in for the scalar (sign unknown, taken compressive).
    """
    fn = np.asarray(snapshot.get("normal_force", np.zeros(0)), dtype=float)
    if fn.ndim == 2:
        return np.linalg.norm(fn, axis=1), fn
    n = len(fn)
    vec = np.asarray(snapshot.get("normal_force_vector", np.full((n, 3), np.nan)), dtype=float).reshape(-1, 3)
    return fn, vec
