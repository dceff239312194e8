"""Continuum-kinematics-inspired peridynamics (CPD), implicit, with the kinematically
coupled overlap interface of 003 (Laurien, Javili, Steinmann 2022).

Model (see the module docstrings for the equations):

* ``kernels``: energies of 003 Eq 7, 10 over one-neighbour pairs, two-neighbour triples
  (2D and 3D) and three-neighbour quadruples (3D) with the counting factors 1/2, 1/3, 1/4;
  residual and tangent are the exact gradient and Hessian (numba, cache=True). The printed
  Eq 16-18 / Appendix A are garbled (ERRATA 11) and not used.
* ``assembly``: cKDTree horizons per material, a fixed block-CSR sparsity pattern built once,
  values refilled every Newton iteration.
* ``discretization``: one uniform grid (vertex-centred by default), boundary layers of depth
  delta outside every side with prescribed displacement (003 Sec 4.1), and the overlap band
  of total width l_ov (default delta) centred on the interface whose points belong to both
  materials and share their DOFs (003 Sec 3).
* ``parameters``: (C1, C2, C3, delta) <-> (lambda, mu) / (E, nu) (ERRATA 12, 003 Eq 25),
  lattice check and optional lattice calibration.
* ``interface``: the compliant overlap for finite Dn, Dt (beyond 003): the band's points
  keep separate A and B nodes tied by springs of stiffness (V_p / w)(Dn n n^T + Dt (I - n n^T)),
  w = band volume / interface measure, so a uniform jump stores exactly the law's energy;
  perfect directions are identified DOFs (``docs/cpd_interface.md``). Other laws are refused.
* ``newton``: load steps, Newton-Raphson on the free-DOF residual normalised by its first
  value in each step (003 Table 3, tol 1e-11), line search, step bisection, SolverError;
  linear solves by ``interfaces.sparse.DirectSolver`` (PARDISO or SuperLU, chosen at run
  time, named in ``diagnostics["linear_solver"]["solver"]``) with the symbolic analysis reused:
  float32 Cholesky factors of the positive definite tangent refined by CG, LDL^T from the
  first indefinite one (``["factorization"]``, ``["cholesky_fallbacks"]``), double precision
  when CG fails with float32 factors (``["precision_fallbacks"]``). In 2D under load
  control the factors are, by default (option ``preconditioner = "pairs"``), those of the
  pair part of the tangent (``preconditioner``: a quarter of the stencil, a third of the
  factorisation), preconditioning CG on the exact tangent to the inexact-Newton forcing
  term; ``"tangent"`` factorises the tangent itself.

Public surface: :func:`solve` (Case -> Result) and the parameter conversions.
Units: mm, N, MPa; 2D quantities are per unit thickness times ``case.thickness``.
"""
from interfaces.numba_cache import use_project_cache as _use_project_cache

_use_project_cache(__path__[0])  # before any kernel module is imported: cache out of the package

from .parameters import (calibrate,  # noqa: E402 cpd_from_elastic, cpd_from_lame, elastic_from_cpd, lame_from_cpd,
                         lattice_ratios, nu2d_from_nu3d, nu3d_from_nu2d, poisson_2d)
from .interface import supports  # noqa: E402
from .solver import solve  # noqa: E402

__all__ = ["solve", "supports", "calibrate", "cpd_from_elastic", "cpd_from_lame", "elastic_from_cpd", "lame_from_cpd",
           "lattice_ratios", "nu2d_from_nu3d", "nu3d_from_nu2d", "poisson_2d"]
