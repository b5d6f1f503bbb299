"""cloth-tui: a cloth simulator that runs in a terminal."""

__version__ = "0.1.0"
