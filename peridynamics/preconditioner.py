"""The pair part of the CPD tangent, the preconditioner of the inexact Newton steps.

The tangent of 003 Eq 7 with the constants (C1, C2, C3) is the sum of the one-neighbour
(pair, psi1) part, whose stencil reaches delta, and the multi-neighbour (psi2, psi3)
parts, whose stencil reaches 2 delta (two neighbours of one central point). The pair part
alone is the tangent of the material with (C1, 0, 0): positive definite near the
reference state once the Dirichlet DOFs are removed (C1 > 0), spectrally close to the
whole tangent (both are elasticity operators: shear modulus mu, 003 Eq 25, and a bulk
part of the same sign), and a quarter as wide. Its float32 Cholesky factors precondition
conjugate gradients on the exact tangent (:class:`peridynamics.newton.TangentSolver`).

Measured at 100 x 100 points, delta = 3.01 h, set 3, one core, under load (19.6k free
DOFs): the pair tangent has 1.11M stored entries (the whole one 3.47M); evaluated in the
kernel pass of the whole tangent, straight into both free-DOF matrices, it adds 0.01 s
(0.12 s for both instead of 0.11 s for the tangent alone; 0.017 s in a pass of its own),
its float32 Cholesky takes 0.06-0.10 s (the whole tangent's 0.27-0.40 s) and its
triangular solve 3-8 ms; CG on the exact tangent with it reaches
1e-10 in 12 iterations, the forcing terms of the three Newton iterations (1e-3, 1e-4,
1e-6) in 2, 4 and 8; the Newton residual histories equal those of the tangent's own
factors to the forcing terms' accuracy (quadratic, 3 iterations). Whole-solve figures and
what else was tried: :mod:`peridynamics.newton`.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .assembly import CPDSystem, MaterialBlock, reduced_target
from .reduction import ReducedMatrix


def pair_preconditioner_applies(system: CPDSystem) -> bool:
    """True when the pair part is a positive definite approximation of the tangent: every
    material has C1 > 0 and multi-neighbour interactions (else the tangent is the pair part
    itself), in 2D (3D tangents of C3 < 0 materials may be indefinite, 003 Sec 4.5)."""
    return system.dim == 2 and all(b.C[0] > 0.0 for b in system.blocks) and any(b.multi for b in system.blocks)


class PairTangent:
    """K_ff of the pair (psi1) part of ``system``'s energy over the free independent DOFs
    ``free``: the same nodes, volumes, horizons, compliant-overlap springs and DOF map, the
    constants (C1, 0, 0). Assembled straight into K_ff where :func:`reduced_target` applies
    (through the full pattern and :class:`ReducedMatrix` otherwise); ``fused`` (or None) is
    the (target, buffer) that ``system.evaluate(pairs=...)`` takes to evaluate it in the
    pass of the whole tangent."""

    def __init__(self, system: CPDSystem, free: np.ndarray):
        blocks = [MaterialBlock(b.name, b.centers, b.nptr, b.nidx, np.array([b.C[0], 0.0, 0.0]))
                  for b in system.blocks]
        springs = system.springs.springs if system.springs is not None else None
        self.system = CPDSystem(system.X, system.vol, blocks, system.delta, springs)
        self.system.dofs = system.dofs               # the compliant overlap's ties
        self.reduce = ReducedMatrix(self.system, free)
        self.target = reduced_target(self.system, self.reduce)
        self._buffer = np.empty(self.system.pattern.nnz if self.target is None else self.target.nnz)
        same_order = all(np.array_equal(a.centers, b.centers) for a, b in zip(self.system.blocks, system.blocks))
        self.fused = (self.target, self._buffer) if self.target is not None and same_order else None

    def __call__(self, u: np.ndarray) -> sp.csr_matrix:
        """The reduced pair tangent at the full-DOF displacement ``u``."""
        if self.target is not None:
            return self.system.evaluate(u, True, out=self._buffer, target=self.target).tangent
        ev = self.system.evaluate(u, True, out=self._buffer)
        return self.reduce(ev.tangent.data)
