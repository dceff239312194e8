"""Incremental Newton-Raphson for the CPD equilibrium R(x) = 0 (003 Eq 20-22, Algorithm 1).

Load steps scale the prescribed displacements (and external forces) linearly. Inside a
step the free DOFs are iterated with the exact tangent; convergence is measured as in
003 Table 3: the L2 norm of the residual of the free DOFs normalised by its norm at the
state right after the boundary increment (free DOFs at the last converged state), stop
at ``tol`` (1e-11); from the second step on the iterations start from a secant
extrapolation of the last converged increment (for a linear problem its first residual
is already round-off small, hence the normalisation by the un-extrapolated state). A backtracking line search on the energy (positive definite tangents) or the
residual norm guards against
diverging iterations; a step that still fails is bisected (``max_cuts`` times) before a
:class:`interfaces.errors.SolverError` is raised saying what to change.

The Newton step is inexact: K(u_k) du = -R_k is solved to the relative residual of
:func:`forcing` (which keeps the quadratic rate) by conjugate gradients on the current
exact tangent (:class:`TangentSolver`), preconditioned by float32 Cholesky factors of the
pair part of the tangent (``NewtonOptions.preconditioner = "pairs"``, the default where
:func:`peridynamics.preconditioner.pair_preconditioner_applies`: 2D, load control) or of
an earlier tangent itself (``"tangent"``, and after any failure of the pair factors): one
factorisation serves all iterations and load steps while the tangent stays close to it,
so an iteration costs one tangent assembly and a few triangular solves.

Measured (``benchmarks/bench_cpd.py --old``, bimaterial square, set 3, delta = 3.01 h,
one core, CPU seconds, both trees in one run; two runs on 2 cores at load 2.0-2.6 with
OMP_NUM_THREADS=1, the first in ``bench_cpd.json``, and at 1.6-1.8 without it). Under load
control :class:`Equations` has the kernels add the tangent straight into K_ff
(``assembly.reduced_target``) and, when the next solve will factorise, the pair part into
its own K_ff in the same pass. The fresh-factorisation iteration (that pass + pair factors
+ CG to the first forcing term) at 100 x 100 points (10.6k points, 19.6k free DOFs):
0.213 / 0.222 s (the pass 0.121, the tangent alone 0.109; pair float32 Cholesky 0.061; 2
CG iterations 0.03) against 0.300 / 0.405 s before (assembly 0.161 + reduction 0.012 +
pair tangent 0.033 + the same factorisation; the second run's CG on numpy's OpenBLAS
threads took 0.13 s): 1.41x / 1.82x. Over 2.8k / 5.3k / 10.6k points: 0.045 / 0.099 /
0.213 s (before 0.067 / 0.145 / 0.300) and 0.045 / 0.100 / 0.222 s (0.066 / 0.141 /
0.405). Whole solves: 3 Newton iterations (1 load step) and 5 (3 steps) with 14 / 31 CG
iterations as before, residual histories equal to round-off (10.6k points: 1, 9.5e-3,
9.6e-7, 1.0e-13), solutions to 3e-14 relative; 1.49x / 1.38x faster at 10.6k points in
the first run (1.4-1.6x over the three sizes), 2.22x / 2.41x in the second.

Tried and not kept (100 x 100 points, same load):

* smoothed-aggregation AMG (pyamg 5.4.1, which installs from a wheel) as the CG
  preconditioner: setup 0.9-1.0 s, 73 CG iterations to 1e-10 (2.6 s) with the default
  near-null space, 16 (0.64 s) with the three rigid-body modes: several times the float32
  factorisation (0.3 s); not added as a dependency;
* the tangent restricted to the pairs within 1.5 delta or delta (with or without the
  dropped entries lumped on the diagonal): indefinite (Cholesky fails, CG fails);
* a pair part of shorter horizon (2.5 h, 2.01 h, 1.5 h, C1 scaled to keep mu): float32
  factorisation 0.056 / 0.042 / 0.019 s instead of 0.104 s, but 3 / 6 / 8 CG iterations to
  1e-3 and 15 / 24 / 29 to 1e-10 instead of 2 and 12: at 2.5 h the fresh iteration is
  0.04 s faster and every later one slower;
* the lower neighbour blocks (b, a) of the 2D local tangent left unwritten and read from
  their transposes by the central-row sums and the scatter (bit-identical): 0.111 s for the
  tangent into K_ff instead of 0.101-0.110, not faster (column reads instead of writes);
* dropping the 17 % structurally zero entries of the 2-delta pattern (kept: products and reduction
  25-40 % faster) leaves the factorisation time unchanged (0.34-0.40 s either way: the
  fill is the same).
"""
from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from scipy.sparse.linalg import LinearOperator, gmres

from interfaces.errors import SolverError
from interfaces.jit import njit
from interfaces.sparse import DirectSolver, SingularMatrixError

from .assembly import CPDSystem, reduced_target
from .preconditioner import PairTangent, pair_preconditioner_applies
from .reduction import ReducedMatrix

log = logging.getLogger(__name__)


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
    #: what the factors preconditioning the Newton steps' CG are of: ``"pairs"`` the pair part of
    #: the tangent (:mod:`peridynamics.preconditioner`; where it applies, with load control and
    #: reused factors; the tangent's own otherwise and after any failure), ``"tangent"`` always
    #: the tangent's own
    preconditioner: str = "pairs"
    extrapolate: bool = True
    #: receives one line per evaluation, Newton iteration and line-search trial (residual,
    #: wall time); None sends them to the ``peridynamics.newton`` logger at INFO level
    report: Callable[[str], None] | None = None
    #: ``"load"``: Newton at the load factors (003 Algorithm 1); ``"arc_length"``: Riks
    #: normal-plane arc-length continuation (:mod:`peridynamics.continuation`), whose first
    #: arc reaches about the first load factor, ending with Newton at load factor 1
    path: str = "load"
    #: arc-length continuation: corrector iterations aimed at per arc (the arc length follows
    #: sqrt(aim / used), at most doubled), normalised residual of the intermediate arcs, arcs allowed
    arc_iterations: int = 4
    arc_tol: float = 1e-6
    max_arcs: int = 40


@dataclass
class NewtonOutcome:
    u: np.ndarray
    history: list = field(default_factory=list)      # per step: {"load": ., "residuals": [...]}
    iterations: int = 0
    timings: dict = field(default_factory=dict)
    last: object = None                               # Evaluation at the converged state
    linear: dict = field(default_factory=dict)        # factorisation / Krylov counts


@njit(cache=True)
def vdot(a: np.ndarray, b: np.ndarray) -> float:
    """a . b on one thread. numpy's dot hands vectors of this size to OpenBLAS, which splits
    them over its threads (all cores unless OMP/OPENBLAS_NUM_THREADS say otherwise); on the
    loaded 2-core machine their synchronisation made the 2 CG iterations of a fresh Newton
    step at 100 x 100 points 0.13 s instead of 0.03 s."""
    s = 0.0
    for i in range(a.shape[0]):
        s += a[i] * b[i]
    return s


def vnorm(a: np.ndarray) -> float:
    """||a||_2 on one thread (:func:`vdot`)."""
    return math.sqrt(vdot(a, a))


def pcg(K, r: np.ndarray, precondition, rtol: float, maxiter: int):
    """Preconditioned conjugate gradients for the symmetric positive definite K x = r.

    Starts from x = M^-1 r (M^-1 = ``precondition``, the factors of an earlier tangent)
    and stops when the residual ||r - K x|| (updated recursively; checked directly at the
    end, allowing 2x round-off drift) is below ``rtol`` ||r||. Returns (x, iterations), or
    (None, iterations) when it does not converge within ``maxiter`` or meets a direction
    of non-positive curvature (K not positive definite: the caller refactorises).
    """
    rn0 = vnorm(r)
    if rn0 == 0.0:
        return np.zeros_like(r), 0
    goal = rtol * rn0
    x = precondition(r)
    res = r - K @ x
    p = None
    rz = 1.0
    it = 0
    while vnorm(res) > goal:
        if it == maxiter or not np.all(np.isfinite(res)):
            return None, it
        z = precondition(res)
        rz, rz_old = vdot(res, z), rz
        p = z if p is None else z + (rz / rz_old) * p
        q = K @ p
        pq = vdot(p, q)
        if not pq > 0.0:
            return None, it
        alpha = rz / pq
        x += alpha * p
        res -= alpha * q
        it += 1
    ok = vnorm(r - K @ x) <= 2.0 * goal        # the recursive residual drifts by round-off
    return (x if ok else None), it


#: PARDISO analysis effort (iparm(2) = 10 L + 2) and precision of the factors of the Newton
#: tangents: measured at 100 x 100 points, delta = 3.01 h (interfaces/sparse.py module doc)
ORDERING_EFFORT = 1
FACTOR_PRECISION = "single"
#: relative residual of the solve right after a float32 factorisation (TangentSolver)
FRESH_RTOL = 1e-10


#: ``NewtonOptions.preconditioner`` values
PRECONDITIONERS = ("pairs", "tangent")


class TangentSolver:
    """K du = r for the Newton tangents of one solve: a direct factorisation, reused as the
    preconditioner of a Krylov solve in the following iterations and load steps.

    With ``approx`` (a callable giving a positive definite approximation P of K, see
    :meth:`solve`) the factorisation is of P, not of K: every system, the first included,
    is solved by CG on K preconditioned with P's float32 Cholesky factors, to the asked
    forcing term. P is refactorised (at the current state) when CG needs more than
    ``approx_refactor_after`` iterations; when P is not positive definite, or CG with its
    fresh factors fails or needs more than that, the solver factorises K itself from then
    on. At 100 x 100 CPD points (set 3, :mod:`peridynamics.preconditioner`) the pair part's
    factors cost a third of the tangent's and CG needs 2-8 iterations instead of 1-2.

    Factorisations go through :class:`interfaces.sparse.DirectSolver` (PARDISO where it
    loads, SuperLU otherwise, chosen at run time; ``name`` says which); the
    reduced tangent keeps one pattern for the whole solve, so the symbolic analysis is
    done once. After a factorisation, later systems are solved with the *current*
    tangent K to the relative residual ``rtol`` asked by the Newton loop (inexact Newton
    forcing term) by preconditioned conjugate gradients (:func:`pcg`) with the old
    factors as preconditioner: two triangular solves and one product with K per
    iteration instead of a new factorisation (a factorisation costs ~30 triangular
    solves at 100 x 100 CPD points). An indefinite factorisation (negative pivots) uses
    right-preconditioned GMRES instead. The factors are renewed when the Krylov method
    fails, and after any solve that needed more than ``refactor_after`` iterations (the
    tangent has moved away from the factorised one). ``reuse=False`` factorises every
    system.

    The factors are Cholesky while the tangent is positive definite (1.1-1.5x faster than
    LDL^T at 100 x 100 points, ordering effort 1), LDL^T from the first tangent that is not
    (``method`` of the direct solver). ``precision="single"`` (the default,
    ``FACTOR_PRECISION``) factorises in float32 (1.6-1.9x faster again):
    the system right after a factorisation is then solved by the same Krylov loop to at
    least ``FRESH_RTOL`` (one CG iteration: 2e-6 -> 7e-11 at 100 x 100 points), as accurate
    as a double-precision solve; when that fails (a tangent too ill-conditioned for float32
    factors) the solver factorises in double precision from then on. The LDL^T factors of
    an indefinite tangent are always double precision (its near-zero eigenvalues).
    """

    def __init__(self, reuse: bool = True, rtol: float = 1e-12, max_krylov: int = 30, kind: str = "auto",
                 refactor_after: int = 8, precision: str | None = None, approx_refactor_after: int = 20):
        self.reuse = reuse
        self.approx_refactor_after = approx_refactor_after
        self.use_approx = True
        self.approx_direct: DirectSolver | None = None
        self.rtol = rtol
        self.max_krylov = max_krylov
        self.refactor_after = refactor_after
        # explicit nested-dissection ordering: it also switches off MKL's default two steps of
        # iterative refinement per solve (3x the triangular-solve cost; the Krylov loop refines).
        # Cholesky while the tangent is positive definite, LDL^T from the first one that is not
        self.kind = kind
        precision = FACTOR_PRECISION if precision is None else precision
        self.precision = precision if reuse else "double"     # only the Krylov loop refines float32 solves
        self.direct = self._direct()
        self.active = self.direct                # whose factors precondition the Krylov loop
        if self.direct.name != "pardiso":
            self.precision = "double"
        self.factored = False
        self.definite = True
        self.stale = False
        self.stats = {"factorizations": 0, "krylov_solves": 0, "krylov_iterations": 0, "precision_fallbacks": 0,
                      "krylov_method": None, "approx_factorizations": 0, "approx_fallbacks": 0}
        self.times = {"factorization": 0.0, "triangular_solves": 0.0, "krylov": 0.0}

    def wants_approx(self) -> bool:
        """True when the next :meth:`solve` given ``approx`` will factorise it (no factors to
        reuse): the caller may then evaluate the approximation along with the tangent."""
        return self.reuse and self.use_approx and not (self.factored and not self.stale)

    def _direct(self) -> DirectSolver:
        return DirectSolver(self.kind, ordering="metis", try_cholesky=True, ordering_effort=ORDERING_EFFORT,
                            precision=self.precision)

    @property
    def name(self) -> str:
        return self.direct.name

    def _factor(self, K):
        t0 = time.perf_counter()
        try:
            self.direct.factorize(K)
        except SingularMatrixError as e:
            raise RuntimeError(str(e)) from None
        self.factored = True
        self.stale = False
        self.active = self.direct
        self.definite = self.direct.negative_pivots() == 0
        self.stats["factorizations"] += 1
        self.times["factorization"] += time.perf_counter() - t0

    def summary(self) -> str:
        """Factorisations and Krylov iterations so far (one line of the progress report)."""
        st = self.stats
        return (f"{st['factorizations']} factorisations, {st['krylov_iterations']} Krylov iterations "
                f"in {st['krylov_solves']} solves")

    def _back(self, r):
        t0 = time.perf_counter()
        x = self.active.solve(r)
        self.times["triangular_solves"] += time.perf_counter() - t0
        return x

    def _gmres(self, K, r: np.ndarray, rtol: float):
        M = LinearOperator(K.shape, matvec=self._back, dtype=np.float64)
        count = [0]

        def cb(_):
            count[0] += 1

        x, info = gmres(K, r, x0=self._back(r), rtol=0.1 * rtol, atol=0.0, restart=self.max_krylov,
                        maxiter=1, M=M, callback=cb, callback_type="pr_norm")
        ok = np.all(np.isfinite(x)) and np.linalg.norm(r - K @ x) <= rtol * np.linalg.norm(r)
        return (x if ok else None), count[0]

    def _krylov(self, K, r: np.ndarray, rtol: float):
        t0 = time.perf_counter()
        if self.definite:
            x, its = pcg(K, r, self._back, rtol, self.max_krylov)
        else:
            x, its = self._gmres(K, r, rtol)
        self.times["krylov"] += time.perf_counter() - t0
        if x is not None:
            self.stats["krylov_solves"] += 1
            self.stats["krylov_iterations"] += its
            self.stats["krylov_method"] = "cg" if self.definite else "gmres"
            limit = self.refactor_after if self.active is self.direct else self.approx_refactor_after
            self.stale = its > limit
        return x

    def solve(self, K, r: np.ndarray, rtol: float | None = None, approx: Callable | None = None) -> np.ndarray:
        """Solve K x = r to the relative residual ``rtol`` (default ``self.rtol``); ``approx()``
        returns the positive definite approximation of K to factorise instead of K (None: K)."""
        rtol = self.rtol if rtol is None else max(rtol, self.rtol)
        if self.factored and self.reuse and not self.stale:
            x = self._krylov(K, r, rtol)
            if x is not None:
                return x
        if approx is not None and self.reuse and self.use_approx:
            x = self._approx_solve(K, r, rtol, approx)
            if x is not None:
                return x
            self.use_approx = False
            self.stats["approx_fallbacks"] += 1
        self._factor(K)
        if self.reuse:                   # fresh factors: no Krylov iteration in double precision
            single = self.direct.precision == "single"
            x = self._krylov(K, r, min(rtol, FRESH_RTOL) if single else rtol)
            if x is not None:
                return x
            if single:
                return self._double_precision_solve(K, r, rtol)
        x = self._back(r)
        # one step of iterative refinement
        x += self._back(r - K @ x)
        return x

    def _approx_solve(self, K, r: np.ndarray, rtol: float, approx: Callable):
        """CG on K preconditioned by fresh float32 factors of ``approx()`` (PARDISO only); None
        when those are not positive definite or CG fails. Fresh factors that need more than
        ``approx_refactor_after`` iterations give their solution but are not tried again."""
        if self.approx_direct is None:
            self.approx_direct = DirectSolver(self.kind, ordering="metis", try_cholesky=True,
                                              ordering_effort=ORDERING_EFFORT, precision="single")
        if self.approx_direct.name != "pardiso":             # no float32 factors: K's own are as cheap
            return None
        t0 = time.perf_counter()
        try:
            self.approx_direct.factorize(approx())
        except SingularMatrixError:
            return None
        finally:
            self.times["factorization"] += time.perf_counter() - t0
        self.stats["approx_factorizations"] += 1
        if self.approx_direct.negative_pivots() != 0:
            return None
        self.active, self.factored, self.stale, self.definite = self.approx_direct, True, False, True
        x = self._krylov(K, r, rtol)
        if x is None:
            self.active, self.factored = self.direct, False
        elif self.stale:
            self.use_approx = False
            self.stats["approx_fallbacks"] += 1
        return x

    def _double_precision_solve(self, K, r: np.ndarray, rtol: float) -> np.ndarray:
        """Float32 factors too poor for the Krylov loop: double precision from now on."""
        self.precision = "double"
        self.direct.release()
        self.direct = self._direct()
        self.factored = False
        self.stats["precision_fallbacks"] += 1
        return self.solve(K, r, rtol)


def forcing(r: float, tol: float) -> float:
    """Relative linear residual asked of the Newton step at normalised residual ``r``.

    1 % of r (at most 1e-3) keeps the quadratic rate of an inexact Newton method (the
    linear error is of the order of the quadratic term r^2); no tighter than 0.1 tol / r,
    which already brings the next residual below ``tol`` (solving further would only
    cost Krylov iterations that the stopping test cannot see).
    """
    return min(1e-3, max(1e-2 * r, 0.1 * tol / max(r, 1e-300)))


@dataclass
class StepFailure:
    """Why one attempt at a load step failed, with that attempt's own history."""

    load: float
    residuals: list
    reason: str


def _advice(f: StepFailure) -> str:
    if "collapsed" in f.reason or "coincide" in f.reason:
        return "increase load_steps or reduce the load (points were crushed)"
    if "singular" in f.reason.lower():
        return ("check that the prescribed displacements remove every rigid-body motion of every body "
                "(a debonded interface, Dn = Dt = 0, leaves a body free)")
    if "indefinite" in f.reason:
        return ("the state is unstable (negative tangent eigenvalues: in 3D the free faces of a material "
                "with C3 < 0, i.e. nu < 1/4, soften and the Newton step leaves the quadratic basin); "
                "use path = arc_length (the path may have a limit point), increase load_steps, shrink the free "
                "faces, or use nu >= 1/4 (or Dn, Dt > 0)")
    if "max_iter" in f.reason:
        return "increase load_steps or max_iter, or loosen tol"
    return "increase load_steps, loosen tol, or check for points crushed by a too-large deformation"

class Equations:
    """The reduced equilibrium equations of one solve, G(v, lam) = R_f(v) - lam f_ext,f = 0.

    v are the independent DOFs (``system.dofs``) with the fixed ones at lam * u_bar; R_f the
    free part of the internal force (the CPD residual, 003 Eq 20). Holds what the Newton
    and path-following drivers share: the DOF split, the K_ff map (:class:`ReducedMatrix`),
    one :class:`TangentSolver`, one tangent buffer and the progress lines.
    """

    def __init__(self, system: CPDSystem, fixed_dofs: np.ndarray, u_bar: np.ndarray, f_ext: np.ndarray,
                 opts: NewtonOptions, solver: str = "auto"):
        self.system = system
        dofs = self.dofs = system.dofs
        self.fixed = np.unique(dofs.index[fixed_dofs])
        self.free = np.setdiff1d(np.arange(dofs.n), self.fixed)
        self.ubar = np.zeros(dofs.n)
        self.ubar[dofs.index[fixed_dofs]] = u_bar[fixed_dofs]
        self.fext = dofs.reduce(np.asarray(f_ext, dtype=float))
        self.red = ReducedMatrix(system, self.free)
        self.lin = TangentSolver(reuse=opts.reuse_factorization, kind=solver)
        # the pair part of the tangent as the factorised preconditioner (load control only: the
        # arc-length driver reads the tangent's inertia from its own factors)
        use_pairs = (opts.preconditioner == "pairs" and opts.path == "load" and opts.reuse_factorization
                     and pair_preconditioner_applies(system))
        self.pairs = PairTangent(system, self.free) if use_pairs else None
        self._state = (None, None)              # (evaluation with a tangent, its independent DOFs)
        self.times = {"assembly": 0.0, "linear_solve": 0.0, "line_search": 0.0}
        # under load control the kernels assemble K_ff itself (no full tangent, no gather; the
        # arc-length driver needs the full one for K_fc u_bar)
        self.target = reduced_target(system, self.red) if opts.path == "load" else None
        # one tangent buffer and one reduced-matrix buffer, refilled by every evaluation: only
        # the current tangent is ever used (the factors live in the direct solver)
        self._tangent_buffer = np.empty(system.pattern.nnz) if self.target is None else None
        self._reduced_buffer = np.empty(len(self.red.indices)) if self.red.injective else None
        self._reduced = (None, None)
        self._say = opts.report or log.info
        self._t0 = time.perf_counter()

    def note(self, msg: str) -> None:
        self._say(f"CPD Newton [{time.perf_counter() - self._t0:8.1f} s] {msg}")

    def evaluate(self, v: np.ndarray, tangent: bool):
        t0 = time.perf_counter()
        u = self.dofs.expand(v)
        if tangent and self.target is not None:
            # the pair part in the same pass when the next solve will factorise it
            fused = self.pairs.fused if self.pairs is not None and self.lin.wants_approx() else None
            ev = self.system.evaluate(u, True, out=self._reduced_buffer, target=self.target, pairs=fused)
        else:
            ev = self.system.evaluate(u, tangent, out=self._tangent_buffer if tangent else None)
        if tangent:
            self._state = (ev, v.copy())
        dt = time.perf_counter() - t0
        self.times["assembly" if tangent else "line_search"] += dt
        self.note(f"  {'residual + tangent' if tangent else 'residual only'} evaluated in {dt:.1f} s")
        return ev

    def residual(self, ev, lam: float) -> np.ndarray:
        """G on the free DOFs at load factor ``lam``."""
        return self.dofs.reduce(ev.residual.ravel())[self.free] - lam * self.fext[self.free]

    def energy(self, ev, v: np.ndarray, lam: float) -> float:
        """Potential energy W - lam f_ext . v (free DOFs)."""
        return ev.energy - lam * vdot(self.fext[self.free], v[self.free])

    def load_derivative(self, ev) -> np.ndarray:
        """dG/dlam on the free DOFs: K_fc u_bar_c - f_ext,f with the tangent of ``ev``."""
        ku = self.dofs.reduce(ev.tangent @ self.dofs.expand(self.ubar))
        return ku[self.free] - self.fext[self.free]

    def solve(self, ev, rhs: np.ndarray, rtol: float) -> np.ndarray:
        """K_ff(ev) x = rhs to the relative residual ``rtol`` (K_ff mapped once per evaluation)."""
        if self._reduced[0] is not ev:
            K = ev.tangent if self.target is not None else self.red(ev.tangent.data, out=self._reduced_buffer)
            self._reduced = (ev, K)
        approx = None
        if self.pairs is not None and self._state[0] is ev:
            v = self._state[1]
            approx = lambda: ev.pair_tangent if ev.pair_tangent is not None else self.pairs(self.dofs.expand(v))  # noqa: E731
        t0 = time.perf_counter()
        x = self.lin.solve(self._reduced[1], rhs, rtol=rtol, approx=approx)
        self.times["linear_solve"] += time.perf_counter() - t0
        self.note(f"  linear solve in {time.perf_counter() - t0:.1f} s ({self.lin.summary()}, asked {rtol:.1e})")
        return x

    def negative_pivots(self) -> int:
        """Negative pivots of the last factorisation (the tangent's negative eigenvalues at the
        state it was factorised at; -1 before any, when the pivoting hides them, or when the
        factors are of the pair part)."""
        if not self.lin.factored or self.lin.active is not self.lin.direct:
            return -1
        return self.lin.direct.negative_pivots()

    def failure(self, lam: float, residuals: list, reason: str) -> StepFailure:
        if self.lin.factored and not self.lin.definite:
            reason += f"; tangent indefinite ({self.lin.direct.negative_pivots()} negative pivots)"
        return StepFailure(lam, residuals, reason)


#: a Newton update below this many ulps of the largest reference coordinate cannot move a
#: point (x = X + u is rounded to them): the residual has reached its round-off floor
ROUNDOFF_ULPS = 64.0


def below_roundoff(du: np.ndarray, X: np.ndarray) -> bool:
    """True when every component of ``du`` is below :data:`ROUNDOFF_ULPS` ulps of max |X|."""
    return float(np.max(np.abs(du), initial=0.0)) <= \
        ROUNDOFF_ULPS * np.finfo(np.float64).eps * float(np.max(np.abs(X), initial=0.0))


def newton_at_load(eq: Equations, v: np.ndarray, lam1: float, scale: float | None, opts: NewtonOptions,
                   contraction: list):
    """Newton iterations at the fixed load factor ``lam1`` from the start ``v`` (fixed DOFs
    already at lam1 u_bar): (v, residuals, ev, (line-search steps, times)) or a StepFailure.

    ``scale`` normalises the residual (None: the first residual); ``contraction`` holds the
    largest r_(k+1) / r_k^2 seen in the solve (updated here).
    """
    free = eq.free
    res_hist = []
    steps = []
    times = []                                   # (wall, cpu) per iteration
    clock = (time.perf_counter(), time.process_time())
    try:
        ev = eq.evaluate(v, True)
    except ValueError as e:
        return eq.failure(lam1, res_hist, f"start of step: {e}")
    for it in range(opts.max_iter + 1):
        R = eq.residual(ev, lam1)
        rn = vnorm(R)
        if not np.isfinite(rn):
            return eq.failure(lam1, res_hist, "non-finite residual")
        if scale is None or not scale > 0:
            scale = max(rn, 1e-300)
        res_hist.append(rn / scale)
        eq.note(f"load {lam1:.4g} iteration {it}: normalised residual {rn / scale:.3e}")
        if rn <= opts.tol * scale or rn == 0.0:
            return v, res_hist, ev, (steps, times)
        if it == opts.max_iter:
            break
        if ev.tangent is None:
            ev = eq.evaluate(v, True)
        eta = forcing(rn / scale, opts.tol)
        try:
            du = eq.solve(ev, -R, eta)
        except RuntimeError as e:
            return eq.failure(lam1, res_hist, f"singular tangent ({e})")
        if not np.all(np.isfinite(du)):
            return eq.failure(lam1, res_hist, "non-finite Newton increment (singular tangent)")
        if len(res_hist) > 1 and res_hist[-1] > 0.5 * res_hist[-2] and below_roundoff(du, eq.system.X):
            # the residual stagnates at its floor: a load tiny against the stiffness (a
            # two-layer block at 1e-3 of its stress) leaves round-off above tol x scale,
            # and line searches and step cuts then ran for minutes before failing
            eq.note(f"load {lam1:.4g}: the Newton update is below the round-off of the positions")
            return v, res_hist, ev, (steps, times)
        # full Newton step, evaluated with the tangent (reused by the next iteration
        # when accepted) unless the step is expected to converge: the next residual
        # predicted from the quadratic constant seen so far is below 0.1 tol (the
        # forcing term is then at its tol floor); backtracking with energy-only
        # evaluations otherwise
        r_now = rn / scale
        if len(res_hist) > 1 and res_hist[-2] > 0:
            contraction[0] = max(contraction[0], r_now / res_hist[-2] ** 2)
        with_tangent = contraction[0] * r_now ** 2 > 0.1 * opts.tol
        w0 = eq.energy(ev, v, lam1)
        alpha = 1.0
        accepted = None
        why = "line search found no decrease"
        for trial_no in range(9 if opts.line_search else 1):
            trial = v.copy()
            trial[free] += alpha * du
            try:
                et = eq.evaluate(trial, trial_no == 0 and with_tangent)
            except ValueError as e:          # points collapsed: shorten the step
                why = f"line search: {e}"
                eq.note(f"  trial step {alpha:g} rejected: {e}")
                alpha *= 0.5
                continue
            rt = vnorm(eq.residual(et, lam1))
            wt = eq.energy(et, trial, lam1)
            # the energy decrease is a valid acceptance test only for a positive definite
            # tangent (a descent direction towards a minimum); with negative pivots the
            # equilibrium is a saddle and the Newton step may lower the energy while leaving
            # it (measured: 0.8 x 0.6 x 0.6 cuboid, residual 0.19 -> 128 accepted on energy),
            # so only the residual norm (the merit ||R||^2, for which the Newton step is
            # always a descent direction) decides
            ok = not opts.line_search or (np.isfinite(rt) and (rt < rn or (eq.lin.definite and wt <= w0)))
            eq.note(f"  trial step {alpha:g}: normalised residual {rt / scale:.3e}, energy change "
                    f"{wt - w0:.3e} ({'accepted' if ok else 'rejected'})")
            if ok:
                accepted = (trial, et)
                break
            alpha *= 0.5
        if accepted is None:
            return eq.failure(lam1, res_hist, why)
        v, ev = accepted
        steps.append(alpha)
        now = (time.perf_counter(), time.process_time())
        times.append((now[0] - clock[0], now[1] - clock[1]))
        clock = now
    return eq.failure(lam1, res_hist, f"max_iter = {opts.max_iter} reached")


def step_record(load: float, hist: list, alphas: list, times: list, **extra) -> dict:
    """One converged load step of the Newton history. Per iteration: the linear solve and the
    evaluation of the next iterate (its residual and, unless the step is expected to converge,
    its tangent); the first iteration of a step also evaluates the tangent at its start."""
    return {"load": load, "residuals": hist, "line_search_steps": alphas,
            "iteration_wall_s": [w for w, _ in times], "iteration_cpu_s": [c for _, c in times], **extra}


def not_converged(f: StepFailure, opts: NewtonOptions, what: str) -> SolverError:
    hist = ", ".join(f"{r:.3g}" for r in f.residuals)
    return SolverError(
        f"CPD Newton-Raphson did not converge to tol = {opts.tol:g} at load factor {f.load:.4g} "
        f"after {what} (failing step: {f.reason}; its normalised residuals [{hist}]); {_advice(f)}")


def _load_stepping(eq: Equations, opts: NewtonOptions, u: np.ndarray, out: NewtonOutcome,
                   failures: list) -> np.ndarray:
    """Load control (003 Algorithm 1): Newton at the given load factors, a secant predictor
    from the second step on, bisection of a failing step. Returns the independent DOFs."""
    free, fixed = eq.free, eq.fixed
    prev = {"u": None, "lam": 0.0}
    # largest r_(k+1) / r_k^2 seen in the solve (1e-2 before any): a near-singular tangent (the
    # soft surface modes of a C3 < 0 material) raises it by orders of magnitude
    contraction = [1e-2]
    targets = list(opts.load_factors) if opts.load_factors else \
        [k / opts.load_steps for k in range(1, opts.load_steps + 1)]
    lam = 0.0
    cuts = 0
    while targets:
        target = targets[0]
        v = u.copy()
        v[fixed] = target * eq.ubar[fixed]
        scale = None
        if opts.extrapolate and prev["u"] is not None and lam > prev["lam"]:
            # the normalisation is the residual right after the boundary increment (003
            # Table 3); the secant predictor below can make the first residual itself
            # round-off small (linear problems), which would make tol unreachable
            try:
                scale = vnorm(eq.residual(eq.evaluate(v, False), target))
            except ValueError:
                scale = None
            # secant predictor: continue the last converged increment (free DOFs)
            v[free] += (target - lam) / (lam - prev["lam"]) * (u[free] - prev["u"][free])
        got = newton_at_load(eq, v, target, scale, opts, contraction)
        if isinstance(got, StepFailure):
            failures.append(got)
            cuts += 1
            if cuts > opts.max_cuts:
                raise not_converged(failures[-1], opts, f"{opts.max_cuts} step cuts")
            eq.note(f"load {target:.4g} failed ({got.reason}): bisected")
            targets.insert(0, 0.5 * (lam + target))      # bisect the step
            continue
        v, hist, ev, (alphas, times) = got
        out.history.append(step_record(target, hist, alphas, times, negative_pivots=eq.negative_pivots()))
        out.iterations += len(hist) - 1
        out.last = ev
        prev["u"], prev["lam"] = u, lam
        u = v
        lam = target
        targets.pop(0)
    return u


#: ``NewtonOptions.path`` values: load control (003 Algorithm 1) or arc-length continuation
PATHS = ("load", "arc_length")


def newton_solve(system: CPDSystem, fixed_dofs: np.ndarray, u_bar: np.ndarray,
                 f_ext: np.ndarray, opts: NewtonOptions, u0: np.ndarray | None = None,
                 solver: str = "auto") -> NewtonOutcome:
    """Solve for the free displacements under prescribed ``u_bar`` on ``fixed_dofs``.

    ``u_bar`` and ``f_ext`` are full (node) DOF vectors at load factor 1; the unknowns
    are the system's independent DOFs (``system.dofs``: the compliant overlap identifies
    the DOFs of perfect directions). ``u0`` and the returned ``u`` are full DOF vectors.
    ``opts.path`` picks the driver: ``"load"`` (load steps, :func:`_load_stepping`) or
    ``"arc_length"`` (:func:`peridynamics.continuation.arc_length`).
    """
    if opts.path not in PATHS:
        raise ValueError(f"path must be one of {', '.join(PATHS)}, got {opts.path!r}")
    if opts.preconditioner not in PRECONDITIONERS:
        raise ValueError(f"preconditioner must be one of {', '.join(PRECONDITIONERS)}, got {opts.preconditioner!r}")
    eq = Equations(system, fixed_dofs, u_bar, f_ext, opts, solver)
    u = np.zeros(eq.dofs.n)
    if u0 is not None:
        u[eq.dofs.index] = u0.astype(float).ravel()
    out = NewtonOutcome(u=u)
    failures: list[StepFailure] = []
    if opts.path == "arc_length":
        from .continuation import arc_length

        u = arc_length(eq, opts, u, out, failures)
    else:
        u = _load_stepping(eq, opts, u, out, failures)
    out.u = eq.dofs.expand(u)
    out.timings = eq.times
    lin = eq.lin
    out.linear = dict(lin.stats, solver=lin.name, preconditioner="pairs" if eq.pairs is not None else "tangent", symbolic_analyses=lin.direct.stats["analyses"],
                      factorization=lin.direct.method, cholesky_fallbacks=lin.direct.stats["cholesky_fallbacks"],
                      **{f"time_{k}": v for k, v in lin.times.items()},
                      failed_attempts=[{"load": f.load, "reason": f.reason, "residuals": f.residuals}
                                       for f in failures])
    return out
