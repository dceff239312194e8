"""Explicit multimaterial material point method (MPM) with imperfect interfaces.

``mpm.solve(case, **options) -> interfaces.Result`` runs a Case to its quasi-static
state (000, 002 Sec 2.4, 004 Sec 3.2); ``mpm.write_vtk_series`` writes particle frames.
Data layout shared by the core and the multimaterial node kernels: mpm/LAYOUT.md.
"""
from interfaces.numba_cache import use_project_cache as _use_project_cache

_use_project_cache(__path__[0])  # before any kernel module is imported: cache out of the package

from .solver import solve, supports  # noqa: E402
from .vtk import write_vtk_series  # noqa: E402

__all__ = ["solve", "supports", "write_vtk_series"]
