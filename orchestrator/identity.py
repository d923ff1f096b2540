"""A run's identity: what decides whether a finished run can stand for a planned one.

identity = sha256 of the resolved case, the engine, its version, its MPI rank count and the bytes of every file
the engine reads (the rendered deck or script and its data files: particles, meshes), each under its name. The
input files are rendered into a scratch folder exactly as a run writes them, so a change to the Python that fills
a template (a context function, a unit conversion, a damping mapping) changes the identity as surely as a change
to the template itself, and a study reruns the runs it affects.
"""

from __future__ import annotations

import hashlib
import json
import tempfile
from pathlib import Path


def input_digest(bound_adapter, scene) -> str:
    """sha256 (hex) over the engine input files bound_adapter.write_input writes for scene, by relative path.

    bound_adapter: a kinds.BoundAdapter (an adapter bound to its engine's profile)."""
    digest = hashlib.sha256()
    with tempfile.TemporaryDirectory(prefix="orchestrator-identity-") as tmp:
        root = Path(tmp)
        bound_adapter.write_input(scene, root)
        for path in sorted(p for p in root.rglob("*") if p.is_file()):
            name = path.relative_to(root).as_posix().encode()
            digest.update(len(name).to_bytes(4, "little") + name)
            data = path.read_bytes()
            digest.update(len(data).to_bytes(8, "little") + data)
    return digest.hexdigest()


def run_identity(loaded, engine: str, engine_version: str, bound_adapter, scene) -> str:
    """The run id (sha256 hex) of a LoadedCase on an engine (see the module docstring)."""
    identity = {
        "case": loaded.resolved,
        "engine": engine,
        "engine_version": engine_version,
        "mpi_ranks": int(getattr(bound_adapter.profile, "mpi_ranks", 1)),
        "inputs": input_digest(bound_adapter, scene),
    }
    return hashlib.sha256(json.dumps(identity, sort_keys=True, default=str).encode()).hexdigest()
