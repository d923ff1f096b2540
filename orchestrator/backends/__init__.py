"""Engine backends, registered by name and imported lazily.

Each backend module holds a template (the engine's file formats:
``write_input``, ``command``, ``read_output``) and a profile (the machine:
executable, version, threads, environment), as in ASE's calculators.
"""

from __future__ import annotations

import importlib

from ..errors import OrchestratorError

_REGISTRY = {
    "yade": ("orchestrator.backends.yade", "YadeBackend"),
    "reference": ("orchestrator.backends.reference", "ReferenceBackend"),
    "liggghts": ("orchestrator.backends.liggghts", "LiggghtsBackend"),
    "sph": ("orchestrator.backends.sph", "SphBackend"),
}


def engine_names() -> list[str]:
    """Names of every engine the orchestrator knows (installed or not)."""
    return sorted(_REGISTRY)


def get_backend(name: str, **profile_options):
    """An instance of the backend registered under name (raises OrchestratorError if unknown)."""
    if name not in _REGISTRY:
        raise OrchestratorError(f"unknown engine {name!r}; allowed: {', '.join(engine_names())}")
    module, cls = _REGISTRY[name]
    return getattr(importlib.import_module(module), cls)(**profile_options)


def engines_for_kind(kind: str) -> list[str]:
    """Names of the engines whose backend runs cases of this kind (its class attribute case_kinds)."""
    names = []
    for name, (module, cls) in sorted(_REGISTRY.items()):
        kinds = getattr(getattr(importlib.import_module(module), cls), "case_kinds", ())
        if kind in kinds:
            names.append(name)
    return names
