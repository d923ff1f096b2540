"""Case files: TOML in, validated immutable models (SI units) out; each kind's model is in orchestrator/kinds."""

from orchestrator.case.loader import LoadedCase, load_case, parse_override

__all__ = ["LoadedCase", "load_case", "parse_override"]
