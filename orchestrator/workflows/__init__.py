"""Workflows over many runs: verification suites, engine comparison, calibration, time-step sweep, benchmarks."""
