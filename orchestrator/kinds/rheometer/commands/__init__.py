"""The commands the rheometer kind contributes to the command line (Kind.commands): `rheometry`, a frequency
sweep, and `calibrate maxwell`, the modes fitted to measured moduli."""
