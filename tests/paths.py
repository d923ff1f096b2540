"""Paths the tests share: the repository, its shipped cases, and the tests' own data and golden files. A test
module anywhere under tests/ imports them from here (pytest puts tests/ on sys.path: pyproject's pythonpath)."""

from __future__ import annotations

from pathlib import Path

TESTS = Path(__file__).resolve().parent
REPO = TESTS.parent
CASES = REPO / "cases"
VERIFICATION = CASES / "verification"
DATA = TESTS / "data"
GOLDEN = TESTS / "golden"
#: The small drag-finishing bowl most DEM tests run (a few hundred balls, seconds on Yade or LIGGGHTS).
TINY_BOWL = DATA / "tiny_bowl.toml"
