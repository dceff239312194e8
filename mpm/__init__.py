"""Explicit multimaterial material point method (MPM) with imperfect interfaces.

``mpm.solve(case, **options) -> interfaces.Result`` runs a Case to its quasi-static
state (000, 002 Sec 2.4, 004 Sec 3.2); ``mpm.write_vtk_series`` writes particle frames.
Data layout shared by the core and the multimaterial node kernels: mpm/LAYOUT.md.
"""
from .solver import solve
from .vtk import write_vtk_series

__all__ = ["solve", "write_vtk_series"]
