"""`orchestrator doctor`: which engines are installed, where, which version."""

from __future__ import annotations

from orchestrator.engines import engine_names, get_engine


def check_engines() -> list[dict]:
    """One row per known engine: engine, found, version, features (what the engine says of its build, e.g. the LAMMPS
    packages the adapters use; '' when it says nothing), path, hint (what to do when missing)."""
    rows = []
    for name in engine_names():
        profile = get_engine(name)
        found = profile.available()
        rows.append(
            {
                "engine": name,
                "found": found,
                "version": profile.version() if found else "",
                "features": profile.features() if found and hasattr(profile, "features") else "",
                "path": profile.where() if found else "",
                "hint": "" if found else profile.install_hint(),
            }
        )
    return rows
