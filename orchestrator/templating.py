"""Jinja rendering with StrictUndefined: a template asking for a missing value fails at render time.

Text from a case reaches an engine's input only through a filter that keeps it what it is in that language:
``pystr`` (a Python string literal, for the Yade scripts), ``comment`` (one line of a LIGGGHTS ``#`` comment)
and Jinja's ``tojson`` (JSON). HTML templates (``*.html.j2``) are autoescaped; deliberate HTML is marked
``|safe`` in the template.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

TEMPLATE_ROOT_CANDIDATES = (
    Path(__file__).resolve().parent / "templates",  # installed wheel
    Path(__file__).resolve().parent.parent / "templates",  # source checkout / editable install
)


def template_root() -> Path:
    """Directory holding the shared templates (templates/report); a kind's engine templates are in its folder."""
    for candidate in TEMPLATE_ROOT_CANDIDATES:
        if candidate.is_dir():
            return candidate
    raise FileNotFoundError("the orchestrator's templates directory is missing; reinstall the package")


def python_string(value) -> str:
    """A double-quoted, ASCII-only Python string literal whose value is str(value) (for Yade's scripts).

    Quotes, backslashes, control characters and everything beyond ASCII are escaped, so the literal is one
    token on one line whatever the text holds; for plain names it is the same text as JSON's.
    """
    text = json.dumps(str(value), ensure_ascii=False)  # escapes " \\ and the characters below U+0020
    return "".join(c if " " <= c < "\x7f" else (f"\\u{ord(c):04x}" if ord(c) <= 0xFFFF else f"\\U{ord(c):08x}")
                   for c in text)


def comment_text(value) -> str:
    """str(value) made safe inside a one-line '#' comment of a LIGGGHTS deck: every character that is not
    printable ASCII becomes '?' (a newline would end the comment and start a command) and '&' becomes '+'
    (a line ending in '&' continues into the next, which would then be commented out)."""
    return "".join(c if " " <= c < "\x7f" and c != "&" else ("+" if c == "&" else "?") for c in str(value))


def _autoescape(name: str | None) -> bool:
    return bool(name) and (name.endswith(".html.j2") or name.endswith(".html"))


def render(template, context: dict) -> str:
    """Render a template with the given context (StrictUndefined; HTML templates autoescaped).

    template: an absolute Path (a kind's template beside its adapter) or a path relative to templates/ (report).
    """
    import jinja2

    path = Path(template)
    root, relative = (path.parent, path.name) if path.is_absolute() else (template_root(), str(template))
    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(root)),
        undefined=jinja2.StrictUndefined,
        keep_trailing_newline=True,
        trim_blocks=True,
        lstrip_blocks=True,
        autoescape=_autoescape,
    )
    env.filters["pystr"] = python_string
    env.filters["comment"] = comment_text
    return env.get_template(relative).render(**context)


def files_hash(paths) -> str:
    """sha256 over the given files' bytes, hex."""
    digest = hashlib.sha256()
    for path in paths:
        digest.update(Path(path).read_bytes())
    return digest.hexdigest()
