"""The commands the ejector_drill kind contributes to the command line (Kind.commands)."""
