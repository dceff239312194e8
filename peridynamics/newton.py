"""Incremental Newton-Raphson for the CPD equilibrium R(x) = 0 (003 Eq 20-22, Algorithm 1).

Load steps scale the prescribed displacements (and external forces) linearly. Inside a
step the free DOFs are iterated with the exact tangent; convergence is measured as in
003 Table 3: the L2 norm of the residual of the free DOFs normalised by its norm at the
first iteration of the step (right after the boundary increment; from the second step on
the free DOFs start from a secant extrapolation of the last converged increment), stop
at ``tol`` (1e-11). A backtracking line search on the energy / residual guards against
diverging iterations; a step that still fails is bisected (``max_cuts`` times) before a
:class:`interfaces.errors.SolverError` is raised saying what to change.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import LinearOperator, gmres, splu

from interfaces.errors import SolverError

from .assembly import CPDSystem


class ReducedMatrix:
    """K_ff of the fixed pattern: index map from the full CSR data to the free-DOF block."""

    def __init__(self, system: CPDSystem, free: np.ndarray):
        pat = system.pattern
        marker = pat.matrix(np.arange(1, pat.nnz + 1, dtype=np.float64))
        sub = marker[free][:, free].tocsr()
        sub.sort_indices()
        self.map = sub.data.astype(np.int64) - 1
        self.indices = sub.indices
        self.indptr = sub.indptr
        self.shape = sub.shape

    def __call__(self, data: np.ndarray) -> sp.csr_matrix:
        return sp.csr_matrix((data[self.map], self.indices, self.indptr), shape=self.shape)


@dataclass
class NewtonOptions:
    """``load_factors`` (increasing, ending at 1) overrides ``load_steps`` equal steps."""

    load_steps: int = 1
    load_factors: tuple = ()
    tol: float = 1e-11
    max_iter: int = 25
    max_cuts: int = 6
    line_search: bool = True
    reuse_factorization: bool = True
    extrapolate: bool = True


@dataclass
class NewtonOutcome:
    u: np.ndarray
    history: list = field(default_factory=list)      # per step: {"load": ., "residuals": [...]}
    iterations: int = 0
    timings: dict = field(default_factory=dict)
    last: object = None                               # Evaluation at the converged state
    linear: dict = field(default_factory=dict)        # factorisation / Krylov counts


class TangentSolver:
    """Sparse direct solve of K du = r, with the LU factors reused as a preconditioner.

    The first solve (and any solve where the reused factors stop being a good
    preconditioner) factorises K with SuperLU (minimum-degree ordering on K + K^T,
    symmetric mode). Later Newton iterations solve the *current* tangent to a relative
    true residual ``rtol`` by GMRES right-preconditioned with the old factors, which costs
    two triangular solves and one product with K per Krylov iteration instead of a new
    factorisation; if GMRES needs more than ``max_krylov`` iterations the tangent has
    moved too far and K is factorised afresh. The Newton loop asks for a relative linear
    residual of min(1e-3, 1e-2 ||R_k|| / ||R_0||) (an inexact-Newton forcing term that
    preserves the quadratic rate). ``reuse=False`` factorises every iteration.
    """

    def __init__(self, reuse: bool = True, rtol: float = 1e-12, max_krylov: int = 30):
        self.reuse = reuse
        self.rtol = rtol
        self.max_krylov = max_krylov
        self.lu = None
        self.stats = {"factorizations": 0, "krylov_solves": 0, "krylov_iterations": 0}

    def _factor(self, K):
        Kc = K.tocsc()
        try:
            self.lu = splu(Kc, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                           options=dict(SymmetricMode=True))
        except RuntimeError:
            self.lu = splu(Kc, permc_spec="MMD_AT_PLUS_A")
        self.stats["factorizations"] += 1

    def _krylov(self, K, r: np.ndarray, rtol: float):
        lu = self.lu
        M = LinearOperator(K.shape, matvec=lu.solve, dtype=np.float64)
        count = [0]

        def cb(_):
            count[0] += 1

        x, info = gmres(K, r, x0=lu.solve(r), rtol=0.1 * rtol, atol=0.0, restart=self.max_krylov,
                        maxiter=1, M=M, callback=cb, callback_type="pr_norm")
        rn = np.linalg.norm(r)
        if np.all(np.isfinite(x)) and np.linalg.norm(r - K @ x) <= rtol * rn:
            self.stats["krylov_solves"] += 1
            self.stats["krylov_iterations"] += count[0]
            return x
        return None

    def solve(self, K, r: np.ndarray, rtol: float | None = None) -> np.ndarray:
        """Solve K x = r to the relative residual ``rtol`` (default ``self.rtol``)."""
        if self.lu is not None and self.reuse:
            x = self._krylov(K, r, self.rtol if rtol is None else max(rtol, self.rtol))
            if x is not None:
                return x
        self._factor(K)
        x = self.lu.solve(r)
        # one step of iterative refinement against the unpivoted factorisation
        x += self.lu.solve(r - K @ x)
        return x


def newton_solve(system: CPDSystem, fixed_dofs: np.ndarray, u_bar: np.ndarray,
                 f_ext: np.ndarray, opts: NewtonOptions, u0: np.ndarray | None = None) -> NewtonOutcome:
    """Solve for the free displacements under prescribed ``u_bar`` on ``fixed_dofs``.

    ``u_bar`` and ``f_ext`` are full DOF vectors at load factor 1.
    """
    n = system.n_nodes * system.dim
    free = np.setdiff1d(np.arange(n), fixed_dofs)
    red = ReducedMatrix(system, free)
    u = np.zeros(n) if u0 is None else u0.astype(float).ravel().copy()
    out = NewtonOutcome(u=u)
    lin = TangentSolver(reuse=opts.reuse_factorization)
    prev = {"u": None, "lam": 0.0}
    t = {"assembly": 0.0, "linear_solve": 0.0, "line_search": 0.0}

    def evaluate(v, tangent):
        t0 = time.perf_counter()
        ev = system.evaluate(v, tangent)
        t["assembly" if tangent else "line_search"] += time.perf_counter() - t0
        return ev

    def attempt(lam0, lam1):
        """Newton iterations from load factor lam0 to lam1; returns (u, residual list) or None."""
        v = u.copy()
        if opts.extrapolate and prev["u"] is not None and lam0 > prev["lam"]:
            # secant predictor: continue the last converged increment (free DOFs)
            v[free] += (lam1 - lam0) / (lam0 - prev["lam"]) * (u[free] - prev["u"][free])
        v[fixed_dofs] = lam1 * u_bar[fixed_dofs]
        res_hist = []
        steps = []
        scale = None
        try:
            ev = evaluate(v, True)
        except ValueError:
            return None
        for it in range(opts.max_iter + 1):
            R = ev.residual.ravel()[free] - lam1 * f_ext[free]
            rn = float(np.linalg.norm(R))
            if not np.isfinite(rn):
                return None
            if scale is None:
                scale = max(rn, 1e-300)
            res_hist.append(rn / scale)
            if rn <= opts.tol * scale or rn == 0.0:
                return v, res_hist, ev, steps
            if it == opts.max_iter:
                return None
            t0 = time.perf_counter()
            try:
                # forcing term of an inexact Newton method: the linear error stays below
                # 1 % of the current (normalised) residual, which keeps the quadratic rate
                du = lin.solve(red(ev.tangent.data), -R, rtol=min(1e-3, 1e-2 * rn / scale))
            except RuntimeError:
                return None
            t["linear_solve"] += time.perf_counter() - t0
            if not np.all(np.isfinite(du)):
                return None
            # full Newton step, evaluated with the tangent (reused by the next iteration
            # when accepted); backtracking with energy-only evaluations otherwise
            w0 = ev.energy - lam1 * float(f_ext[free] @ v[free])
            alpha = 1.0
            accepted = None
            for trial_no in range(9 if opts.line_search else 1):
                trial = v.copy()
                trial[free] += alpha * du
                try:
                    et = evaluate(trial, trial_no == 0)
                except ValueError:              # points collapsed: shorten the step
                    alpha *= 0.5
                    continue
                rt = np.linalg.norm(et.residual.ravel()[free] - lam1 * f_ext[free])
                wt = et.energy - lam1 * float(f_ext[free] @ trial[free])
                if not opts.line_search or (np.isfinite(rt) and (rt < rn or wt <= w0)):
                    accepted = (trial, et)
                    break
                alpha *= 0.5
            if accepted is None:
                return None
            v, ev = accepted
            if ev.tangent is None:
                ev = evaluate(v, True)
            steps.append(alpha)
        return None

    targets = list(opts.load_factors) if opts.load_factors else \
        [k / opts.load_steps for k in range(1, opts.load_steps + 1)]
    lam = 0.0
    cuts = 0
    while targets:
        target = targets[0]
        got = attempt(lam, target)
        if got is None:
            cuts += 1
            if cuts > opts.max_cuts:
                raise SolverError(
                    f"CPD Newton-Raphson did not converge to tol = {opts.tol:g} at load factor {target:.4g} "
                    f"after {opts.max_cuts} step cuts (last history: "
                    f"{out.history[-1]['residuals'] if out.history else []}); increase load_steps, "
                    "loosen tol, or check for points crushed by a too-large deformation")
            targets.insert(0, 0.5 * (lam + target))      # bisect the step
            continue
        u, hist, ev, alphas = got
        out.history.append({"load": target, "residuals": hist, "line_search_steps": alphas})
        out.iterations += len(hist) - 1
        out.last = ev
        prev["u"], prev["lam"] = out.u, lam
        out.u = u
        lam = target
        targets.pop(0)
    out.u = u
    out.timings = t
    out.linear = lin.stats
    return out
