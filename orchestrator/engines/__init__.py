"""Engines as programs (profiles), registered by name and imported lazily: where each is, its version, its command
line, threads and MPI ranks, its environment, how to install it. What an engine does with a kind's case is the
kind's adapter's business (orchestrator.kinds)."""

from __future__ import annotations

import importlib

from orchestrator.errors import OrchestratorError

_REGISTRY = {
    "yade": ("orchestrator.engines.yade", "Yade"),
    "reference": ("orchestrator.engines.reference", "Reference"),
    "liggghts": ("orchestrator.engines.liggghts", "Liggghts"),
    "sph": ("orchestrator.engines.sph", "Sph"),
    "lammps": ("orchestrator.engines.lammps", "Lammps"),
}


def engine_names() -> list[str]:
    """Names of every engine the orchestrator knows (installed or not)."""
    return sorted(_REGISTRY)


def get_engine(name: str, **profile):
    """The engine (profile) registered under name with the given options (threads, mpi_ranks, executable).

    Raises OrchestratorError for an unknown name or an option the engine does not take (e.g. MPI ranks for yade).
    """
    if name not in _REGISTRY:
        raise OrchestratorError(f"unknown engine {name!r}; allowed: {', '.join(engine_names())}")
    module, cls = _REGISTRY[name]
    engine_class = getattr(importlib.import_module(module), cls)
    try:
        return engine_class(**profile)
    except TypeError:
        if "mpi_ranks" in profile and profile["mpi_ranks"] is not None:
            raise OrchestratorError(f"--mpi {profile['mpi_ranks']}: the {name} engine does not run under MPI; "
                                    "liggghts and lammps do") from None
        raise
