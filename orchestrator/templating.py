"""Jinja rendering with StrictUndefined: a template asking for a missing value fails at render time."""

from __future__ import annotations

import hashlib
from pathlib import Path

TEMPLATE_ROOT_CANDIDATES = (
    Path(__file__).resolve().parent / "templates",  # installed wheel
    Path(__file__).resolve().parent.parent / "templates",  # source checkout / editable install
)


def template_root() -> Path:
    """Directory holding templates/{yade,liggghts,sph}."""
    for candidate in TEMPLATE_ROOT_CANDIDATES:
        if candidate.is_dir():
            return candidate
    raise FileNotFoundError("the orchestrator's templates directory is missing; reinstall the package")


def render(relative: str, context: dict) -> str:
    """Render templates/<relative> with the given context (StrictUndefined)."""
    import jinja2

    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(template_root())),
        undefined=jinja2.StrictUndefined,
        keep_trailing_newline=True,
        trim_blocks=True,
        lstrip_blocks=True,
    )
    return env.get_template(relative).render(**context)


def files_hash(paths) -> str:
    """sha256 over the given files' bytes, hex."""
    digest = hashlib.sha256()
    for path in paths:
        digest.update(Path(path).read_bytes())
    return digest.hexdigest()
