"""orchestrator: run particle simulations of machining and finishing processes
on established engines (Yade, LIGGGHTS, our SPH executable) and compare them
with built-in reference solvers.

The Python API mirrors the CLI::

    from orchestrator import load_case, run_case
    case = load_case("cases/drag_finishing_uhlmann2015.toml", preset="quick")
    result = run_case(case, engine="yade", out_dir="runs/demo")
"""

__version__ = "0.1.0"


def load_case(path, preset=None, overrides=()):
    """Read, override and validate a TOML case file into an immutable Case (SI units)."""
    from orchestrator.case import load_case as _load

    return _load(path, preset=preset, overrides=overrides)


def run_case(case, engine=None, out_dir=None, timeout_s=None, progress=True):
    """Run a validated Case on an engine; returns the RunSummary (see orchestrator.run)."""
    from orchestrator.run import run_case as _run

    return _run(case, engine=engine, out_dir=out_dir, timeout_s=timeout_s, progress=progress)
