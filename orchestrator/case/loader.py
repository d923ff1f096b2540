"""From a TOML file (plus a preset and --set overrides) to a validated Case.

Every failure becomes a CaseError whose message names the key, the bad value
and what is allowed; no pydantic or TOML traceback reaches the user.
"""

from __future__ import annotations

import copy
import hashlib
import json
import stat
import tomllib
import types
import typing
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ValidationError

from orchestrator.errors import CaseError, OrchestratorError
from orchestrator.kinds import get_kind, kind_names

#: Largest case or study file read, bytes (the shipped ones are a few kB).
MAX_TOML_BYTES = 16 * 1024 * 1024


@dataclass(frozen=True)
class LoadedCase:
    """A validated case with where it came from and its resolved TOML text."""

    model: Any
    source: Path
    preset: str | None
    resolved: dict
    toml_text: str

    @property
    def name(self) -> str:
        """case.name."""
        return self.model.case.name

    @property
    def kind(self) -> str:
        """case.kind, e.g. 'drag_finishing'."""
        return self.model.case.kind

    @property
    def hash(self) -> str:
        """sha256 of the resolved parameters (sorted JSON), hex."""
        blob = json.dumps(self.resolved, sort_keys=True, default=str).encode()
        return hashlib.sha256(blob).hexdigest()


def parse_override(text: str) -> tuple[list[str], Any]:
    """Split ``a.b.c=VALUE``; VALUE is read as a TOML value, else as a plain string."""
    if "=" not in text:
        raise CaseError(f"--set {text!r}: expected KEY=VALUE, e.g. --set media.count=200")
    key, raw = text.split("=", 1)
    key = key.strip()
    if not key or any(not part for part in key.split(".")):
        raise CaseError(f"--set {text!r}: the key {key!r} is empty or has an empty part; e.g. media.count")
    try:
        value = tomllib.loads(f"v = {raw}")["v"]
    except tomllib.TOMLDecodeError:
        value = raw
    except RecursionError:
        raise CaseError(f"--set {key}: the value is nested too deeply (arrays in arrays, beyond what the TOML "
                        "reader can follow); a case value needs at most a few levels") from None
    return key.split("."), value


def _set_path(data: dict, path: list[str], value: Any, origin: str) -> None:
    """Set data[a][b]... = value; a numeric part indexes an array of tables (contacts.0.restitution)."""
    node = data
    for i, part in enumerate(path[:-1]):
        if isinstance(node, list):
            child = node[_index(node, part, path[: i + 1], origin)]
        else:
            child = node.get(part)
            if child is None:
                child = node[part] = {}
        if isinstance(child, list) and not path[i + 1].isdigit():
            raise CaseError(f"{origin}: {'.'.join(path)}: {path[i + 1]!r} is not an index of "
                            f"{'.'.join(path[: i + 1])}, an array of {len(child)} entries; allowed indices: "
                            f"{_allowed_indices(child)}" + (" (negative indices are not allowed)"
                                                             if path[i + 1].lstrip("-").isdigit() else ""))
        if not isinstance(child, (dict, list)):
            raise CaseError(f"{origin}: {'.'.join(path[: i + 1])} is a value, not a table; cannot set {'.'.join(path)}")
        node = child
    if isinstance(node, list):
        node[_index(node, path[-1], path, origin)] = value
    else:
        node[path[-1]] = value


def _index(items: list, part: str, path: list[str], origin: str) -> int:
    if not part.isdigit() or int(part) >= len(items):
        negative = " (negative indices are not allowed)" if part.lstrip("-").isdigit() and part.startswith("-") else ""
        raise CaseError(f"{origin}: {'.'.join(path)}: {'.'.join(path[:-1])} has {len(items)} entries; "
                        f"allowed indices: {_allowed_indices(items)}{negative}")
    return int(part)


def _allowed_indices(items: list) -> str:
    return f"0 to {len(items) - 1}" if items else "none (the array is empty)"


def _merge(base: dict, patch: dict, origin: str, prefix: tuple[str, ...] = ()) -> None:
    for key, value in patch.items():
        if isinstance(value, dict) and isinstance(base.get(key), dict):
            _merge(base[key], value, origin, prefix + (key,))
        else:
            _set_path(base, [key], copy.deepcopy(value), origin)


def _model_at(root: type[BaseModel], loc: tuple) -> type[BaseModel] | None:
    """The pydantic model class that holds the field at loc[-1], if any."""
    model: Any = root
    for part in loc[:-1]:
        if isinstance(model, type) and issubclass(model, BaseModel):
            if part not in model.model_fields:
                return None
            model = model.model_fields[part].annotation
            if typing.get_origin(model) in (typing.Union, types.UnionType):
                model = _unwrap(model)  # Optional[Model]: the next part is one of its fields
        else:
            # A container (dict of models, tuple of models): part is a key or an index.
            model = _unwrap(model)
    model = _unwrap(model)
    return model if isinstance(model, type) and issubclass(model, BaseModel) else None


def _unwrap(annotation: Any) -> Any:
    args = typing.get_args(annotation)
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for arg in args:
        found = _unwrap(arg)
        if isinstance(found, type) and issubclass(found, BaseModel):
            return found
    return annotation


def _key(loc: tuple) -> str:
    out = ""
    for part in loc:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out


def format_validation_error(error: ValidationError, root: type[BaseModel]) -> str:
    """One line per problem: 'key = value: what is wrong; allowed: ...'."""
    lines = []
    items = error.errors()
    failed = [tuple(i["loc"]) for i in items]
    for item in items:
        loc = tuple(p for p in item["loc"] if not (isinstance(p, str) and p.startswith("function-")))
        if item["type"] == "too_short" and any(f[:len(item["loc"])] == tuple(item["loc"]) and len(f) > len(loc)
                                               for f in failed):
            continue  # an array whose entries failed also counts as too short: the entries' lines say it
        msg = item["msg"].removeprefix("Value error, ").removeprefix("Assertion failed, ")
        key = _key(loc)
        if item["type"] == "extra_forbidden":
            holder = _model_at(root, loc)
            allowed = ", ".join(holder.model_fields) if holder else "see the documented keys"
            lines.append(f"{key}: unknown key; allowed here: {allowed}")
        elif item["type"] == "missing":
            lines.append(f"{key}: required key is missing")
        elif item["type"] == "finite_number":
            lines.append(f"{key} = {item.get('input')!r}: expected a finite number; inf and nan are not allowed")
        elif item["type"] in ("path_type", "path_parsing"):
            lines.append(f"{key} = {item.get('input')!r}: expected a file path as text, e.g. \"rod.stl\"")
        elif not loc:
            lines.append(msg)
        else:
            value = item.get("input")
            shown = repr(value) if not isinstance(value, dict) else "{...}"
            if len(shown) > 60:
                shown = shown[:57] + "..."
            lines.append(f"{key} = {shown}: {msg}")
    return "\n".join(lines)


def _validate(data: dict, base_dir: Path, where: str):
    meta = data.get("case")
    if meta is None:
        raise CaseError(f"{where}: the [case] table is missing; it needs at least kind and name")
    if not isinstance(meta, dict):
        raise CaseError(f"{where}: case = {meta!r} is a value, not a table; write a [case] table with kind and name")
    kind = meta.get("kind")
    allowed = ", ".join(kind_names())
    if kind is None:
        raise CaseError(f"{where}: case.kind: required key is missing; allowed: {allowed}")
    if not isinstance(kind, str) or kind not in kind_names():
        raise CaseError(f"{where}: case.kind = {kind!r} is not known; allowed: {allowed}")
    model_cls = get_kind(kind).case_model.load()
    try:
        return model_cls.model_validate(data, context={"base_dir": str(base_dir)})
    except ValidationError as exc:
        raise CaseError(f"{where}: invalid case\n" + format_validation_error(exc, model_cls)) from None


def to_toml(data: dict) -> str:
    """The resolved case as TOML text (stored in run.h5 and written beside the inputs)."""
    import tomli_w

    def plain(value):
        if isinstance(value, dict):
            return {k: plain(v) for k, v in value.items() if v is not None}
        if isinstance(value, (list, tuple)):
            return [plain(v) for v in value]
        if isinstance(value, Path):
            return str(value)
        return value

    return tomli_w.dumps(plain(data))


def read_toml_file(path: Path, what: str) -> dict:
    """A TOML file as a dict; CaseError for a missing, non-text or malformed file (`what` names it)."""

    try:
        info = path.stat()
    except (FileNotFoundError, NotADirectoryError):
        raise CaseError(f"{what} file not found: {path}") from None
    except OSError as exc:
        raise CaseError(f"cannot read the {what} file {path}: {exc.strerror or exc}") from None
    if stat.S_ISDIR(info.st_mode):
        raise CaseError(f"{what} file {path} is a directory; give a TOML file")
    if not stat.S_ISREG(info.st_mode):
        raise CaseError(f"{what} file {path} is not a regular file (a device, pipe or socket); give a TOML file")
    if info.st_size > MAX_TOML_BYTES:
        raise CaseError(f"{path}: {info.st_size} bytes is too large for a {what} file; allowed: at most "
                        f"{MAX_TOML_BYTES} bytes")
    try:
        return tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise CaseError(f"{path}: malformed TOML: {exc}") from None
    except UnicodeDecodeError:
        raise CaseError(f"{path}: not a text file (expected UTF-8 TOML)") from None
    except RecursionError:
        raise CaseError(f"{path}: the TOML is nested too deeply (arrays or tables in one another, beyond what the "
                        "TOML reader can follow); a case or study needs at most a few levels") from None
    except OSError as exc:
        raise CaseError(f"cannot read the {what} file {path}: {exc.strerror or exc}") from None


def load_case(path: str | Path, preset: str | None = None, overrides=()) -> LoadedCase:
    """Read a TOML case file, apply ``[presets.<preset>]`` then ``--set`` overrides, validate.

    Returns a LoadedCase whose ``model`` is immutable and in SI units.
    Raises CaseError naming the key, the bad value and what is allowed.
    """
    path = Path(path)
    raw = read_toml_file(path, "case")
    presets = raw.pop("presets", {})
    if not isinstance(presets, dict) or not all(isinstance(p, dict) for p in presets.values()):
        raise CaseError(f"{path}: [presets] must hold tables such as [presets.quick]")
    base_dir = path.parent.resolve()
    _validate(copy.deepcopy(raw), base_dir, str(path))
    for name, patch in presets.items():
        trial = copy.deepcopy(raw)
        _merge(trial, patch, f"preset {name!r}")
        _validate(trial, base_dir, f"{path}, preset {name!r}")
    data = copy.deepcopy(raw)
    if preset is not None:
        if preset not in presets:
            allowed = ", ".join(presets) or "(the file defines none)"
            raise CaseError(f"unknown preset {preset!r} for {path}; allowed: {allowed}")
        _merge(data, presets[preset], f"preset {preset!r}")
    for text in overrides:
        keys, value = parse_override(text)
        _set_path(data, keys, value, f"--set {text}")
    where = str(path) + (f", preset {preset!r}" if preset else "") + (" with --set" if overrides else "")
    model = _validate(data, base_dir, where)
    resolved = model.model_dump(mode="json")
    return LoadedCase(model=model, source=path.resolve(), preset=preset, resolved=resolved, toml_text=to_toml(resolved))


#: Where the package's own case folders lie: installed (orchestrator/<folder>_cases, see pyproject.toml's
#: package-dir) or in a source checkout (cases/<folder>).
_PACKAGE = Path(__file__).resolve().parent.parent


def shipped_cases(folder: str = "verification") -> Path:
    """The folder of case files shipped with the package, cases/<folder> (e.g. the verification scenes);
    OrchestratorError when it is missing."""
    for candidate in (_PACKAGE / f"{folder}_cases", _PACKAGE.parent / "cases" / folder):
        if candidate.is_dir():
            return candidate
    raise OrchestratorError(f"the shipped cases (cases/{folder}) are missing; reinstall the package")
