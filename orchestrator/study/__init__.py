"""Studies: sweeps of a case over parameters and engines, cached and resumable."""

from orchestrator.study.core import Study, grid, read_index, zipped

__all__ = ["Study", "grid", "read_index", "zipped"]
