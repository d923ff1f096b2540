"""`orchestrator doctor`: which engines are installed, where, which version."""

from __future__ import annotations


def check_engines() -> list[dict]:
    """One row per known engine: engine, found, version, path, hint (what to do when missing)."""
    from .backends import engine_names, get_backend

    rows = []
    for name in engine_names():
        backend = get_backend(name)
        found = backend.available()
        rows.append(
            {
                "engine": name,
                "found": found,
                "version": backend.version() if found else "",
                "path": backend.where() if found else "",
                "hint": "" if found else backend.install_hint(),
            }
        )
    return rows
