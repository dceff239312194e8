"""Named cases, cross-method comparison and the ``imperfect`` command line."""
from .registry import build, names, parameters

__all__ = ["build", "names", "parameters"]
