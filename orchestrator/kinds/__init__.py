"""Process kinds, registered by name and imported lazily (as meshio's register_format, ASE's calculators).

A kind registers with one line below (or, for a kind outside the package, with ``register(name, module)``); its
module defines ``KIND`` (kinds.base.Kind). Nothing of a kind is imported until it is asked for.
"""

from __future__ import annotations

import importlib

from orchestrator.engines import get_engine
from orchestrator.errors import OrchestratorError
from orchestrator.kinds.base import Adapter, BoundAdapter, Kind

_REGISTRY: dict[str, str] = {}
_LOADED: dict[str, Kind] = {}


def register(name: str, module: str) -> None:
    """Register the kind `name`, defined as KIND in the importable module `module`."""
    _REGISTRY[name] = module
    _LOADED.pop(name, None)


register("afm_channel", "orchestrator.kinds.afm_channel")
register("cantilever_plate", "orchestrator.kinds.cantilever_plate")
register("crater", "orchestrator.kinds.crater")
register("drag_finishing", "orchestrator.kinds.drag_finishing")
register("ejector_drill", "orchestrator.kinds.ejector_drill")
register("ejector_feed", "orchestrator.kinds.ejector_feed")
register("impact", "orchestrator.kinds.impact")
register("rheometer", "orchestrator.kinds.rheometer")
register("scratch", "orchestrator.kinds.scratch")
register("sph_flow", "orchestrator.kinds.sph_flow")
register("taylor_bar", "orchestrator.kinds.taylor_bar")


def kind_names() -> list[str]:
    """Names of every registered kind, sorted."""
    return sorted(_REGISTRY)


def get_kind(name: str) -> Kind:
    """The Kind registered under name (OrchestratorError naming the known kinds otherwise)."""
    if name not in _REGISTRY:
        raise OrchestratorError(f"unknown case kind {name!r}; allowed: {', '.join(kind_names())}")
    if name not in _LOADED:
        _LOADED[name] = importlib.import_module(_REGISTRY[name]).KIND
    return _LOADED[name]


def kind_commands() -> dict:
    """{command name: kinds.base.Command} of every command the registered kinds contribute (Kind.commands), sorted
    by name; OrchestratorError when two kinds contribute the same name."""
    owners: dict[str, str] = {}
    for kind in kind_names():
        for name in get_kind(kind).commands:
            if name in owners:
                raise OrchestratorError(f"the kinds {owners[name]} and {kind} both contribute the command {name!r}")
            owners[name] = kind
    return {name: get_kind(owners[name]).command(name) for name in sorted(owners)}


def engines_for_kind(name: str) -> list[str]:
    """Names of the engines that run cases of this kind (the kind's adapters), sorted."""
    return get_kind(name).engines()


def kinds_for_engine(engine: str) -> list[str]:
    """Names of the kinds the engine runs, sorted."""
    return [name for name in kind_names() if engine in get_kind(name).adapters]


def build_scene(case):
    """The scene of a validated case model, built by its kind."""
    return get_kind(case.case.kind).build_scene(case)


def measure(case, result) -> dict[str, float]:
    """The case's measured quantities from a Result, by its kind (SI units; empty if the run has too little data)."""
    return get_kind(case.case.kind).measure(case, result)


def bind(kind: str, engine: str, scene=None, **options) -> BoundAdapter:
    """The adapter of engine (its registry name) for kind, bound to the engine's profile
    (engines.get_engine(engine, **options): threads, mpi_ranks, executable).

    Raises OrchestratorError when the engine does not run the kind (with the kind's reason when it has one: pass the
    scene) or the options do not apply to the engine.
    """

    adapter = get_kind(kind).adapter(engine, scene)
    return BoundAdapter(get_engine(engine, **options), adapter)


__all__ = ["Adapter", "BoundAdapter", "Kind", "bind", "build_scene", "measure", "engines_for_kind", "get_kind",
           "kind_commands", "kind_names", "kinds_for_engine", "register"]
