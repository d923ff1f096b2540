"""Package discovery by pattern: every package under orchestrator/ (a new kind folder needs no edit), plus the two
folders that pyproject.toml's package-dir maps into it. Everything else is in pyproject.toml."""

from setuptools import find_packages, setup

#: Folders outside orchestrator/ that ship inside it (package-dir in pyproject.toml says where they live).
MAPPED = ["orchestrator.templates", "orchestrator.verification_cases"]

setup(packages=find_packages(include=["orchestrator", "orchestrator.*"]) + MAPPED)
