"""Numbers for people: durations in the unit that reads best."""


def duration(seconds: float) -> str:
    """A wall time in s, min, h, days or years, e.g. '20.3 h'."""
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    if seconds < 3 * 86400:
        return f"{seconds / 3600:.1f} h"
    if seconds < 3 * 365 * 86400:
        return f"{seconds / 86400:.1f} days"
    return f"{seconds / (365 * 86400):.0f} years"
