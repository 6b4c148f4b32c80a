"""Collect doctests from the package but never run the command-line entry module."""

collect_ignore = ["sktiction/__main__.py"]
