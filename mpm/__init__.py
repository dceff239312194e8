"""Explicit multimaterial material point method (MPM) with imperfect interfaces.

``mpm.solve(case, **options) -> interfaces.Result`` runs a Case to its quasi-static
state (000, 002 Sec 2.4, 004 Sec 3.2); ``mpm.write_vtk_series`` writes particle frames.
Data layout shared by the core and the multimaterial node kernels: mpm/LAYOUT.md.
"""
from interfaces.numba_cache import drop_stale_cache as _drop_stale_cache

_drop_stale_cache(__path__[0])  # before any kernel module is imported

from .solver import solve  # noqa: E402
from .vtk import write_vtk_series  # noqa: E402

__all__ = ["solve", "write_vtk_series"]
