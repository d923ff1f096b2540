"""The small typed family of errors the orchestrator raises.

Every error carries a message meant for a user: it names the problem and,
where there is one, what to do about it. The CLI prints ``error: <message>``
and exits non-zero; it never shows a traceback for these.
"""


class OrchestratorError(Exception):
    """Base class: a problem the user can act on."""

    exit_code = 2
    summary = None  # the RunSummary of a run that ended badly, when there is one

    def with_summary(self, summary):
        """Attach the summary of the run this error ended (for --json output)."""
        self.summary = summary
        return self


class CaseError(OrchestratorError):
    """The case file is unreadable or invalid (names key, value, what is allowed)."""


class EngineNotFound(OrchestratorError):
    """The requested engine is not installed or not on PATH."""

    exit_code = 3


class EngineFailed(OrchestratorError):
    """The engine rejected its input, crashed or ended without its outputs."""

    exit_code = 4


class EngineTimeout(OrchestratorError):
    """The engine ran past the allowed wall time and was stopped."""

    exit_code = 5


class ReadError(OrchestratorError):
    """An engine output or a run.h5 could not be read."""

    exit_code = 6


class EngineUnstable(OrchestratorError):
    """The run blew up numerically (NaN, energy growth, particles leaving the domain)."""

    exit_code = 7
