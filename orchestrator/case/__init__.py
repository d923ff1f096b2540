"""Case files: TOML in, validated immutable models (SI units) out."""

from .loader import CASE_KINDS, LoadedCase, load_case, parse_override

__all__ = ["CASE_KINDS", "LoadedCase", "load_case", "parse_override"]
