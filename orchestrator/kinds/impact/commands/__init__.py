"""The commands the impact kind contributes to the command line (Kind.commands): `calibrate restitution`, e_n
fitted to a sphere drop."""
