"""Sparse direct solver for the symmetric systems of FEM and CPD, chosen at run time.

PARDISO (Intel MKL, through the ``pypardiso`` wheel) is used when it loads: a
supernodal symmetric-indefinite LDL^T with its own fill-reducing ordering, several
times faster than SuperLU on the 2D/3D elasticity matrices here, and it reports the
inertia (numbers of positive and negative pivots) that the FEM needs to detect an
indefinite stiffness. When the pattern of a new matrix equals the previous one the
symbolic analysis (ordering + symbolic factorisation) is reused and only the numeric
factorisation is repeated (Newton iterations, load steps, sweeps over a parameter).

For the Newton tangents of a stable material (positive definite once the Dirichlet DOFs
are removed) ``try_cholesky=True`` factorises by Cholesky (PARDISO matrix type 2) and
falls back to LDL^T when PARDISO meets a non-positive pivot (MKL error -4), for that and
every later factorisation of the solver (``method`` says which one ran,
``stats["cholesky_fallbacks"]`` counts the switches); the FEM keeps LDL^T, whose inertia
it needs. ``ordering_effort`` L (0-10, iparm(2) = 10 L + K, documented from oneMKL 2026.0;
an MKL that refuses it runs at 0) lets the analysis amalgamate supernodes and refine the
ordering: a few per cent more flops in larger dense blocks that the BLAS runs faster.
``precision="single"`` factorises in float32 (iparm(28) = 1): a solve is then accurate
only to ~cond(A) 6e-8 and serves as the preconditioner of a Krylov method or an
iterative refinement that works in double precision (``peridynamics.newton``). With
``try_cholesky`` only the Cholesky factors are float32: the LDL^T after a non-positive
pivot is double (an indefinite tangent is close to a singular one; ``precision`` says
which precision the last factorisation used).

Numeric factorisation of the CPD tangent at 100 x 100 points, delta = 3.01 h, set 3
(19.6k equations, 4.2M stored entries, rows of ~214), one core, CPU seconds, best of 3,
measured side by side at load 3-5 (``benchmarks/bench_cpd.py`` has the whole iteration):

=====================================  =========  ===========
factorisation                          GFlop      CPU s
=====================================  =========  ===========
LDL^T, METIS (before)                  15.0       0.59-0.68
LDL^T, minimum degree                  18.1       0.65
LDL^T, parallel METIS (iparm(2) = 3)   15.0       0.64
Cholesky, METIS                        15.0       0.56-0.64
Cholesky, minimum degree               18.1-18.7  0.58-0.59
Cholesky, METIS, effort 1-2            15.8       0.46-0.54
Cholesky, METIS, effort 3-10           17.1-18.2  0.46-0.53
Cholesky, effort 1, two-level          15.8       0.49-0.56
LDL^T, METIS, effort 1                 15.8       0.61-0.71
float32 LDL^T, METIS, effort 1         15.8       0.35-0.36
float32 Cholesky, METIS, effort 1-5    15.8-18.2  0.26-0.30
=====================================  =========  ===========

One float32 Cholesky solve leaves a relative residual of 2.3e-6 there, one CG iteration
7e-11, two 4e-15 (cond ~5.5e3 at 50 x 50 points). Outside PARDISO a factorisation costs the
extraction of the upper triangle (15-20 ms), replaced by one gather (8 ms) when the
pattern repeats.

SuperLU (scipy) in symmetric mode with minimum-degree ordering on A^T + A is the
fallback, taken when pypardiso is missing or MKL cannot be loaded, or on request
(``kind="superlu"``). ``DirectSolver.name`` says which one ran; solvers put it in
their Result diagnostics.
"""
from __future__ import annotations

import os

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

KINDS = ("auto", "pardiso", "superlu")
ORDERINGS = (None, "minimum_degree", "metis")
PRECISIONS = ("double", "single")
_PARDISO_ORDERING = {"minimum_degree": 0, "metis": 2}    # PARDISO iparm(2)


class SingularMatrixError(RuntimeError):
    """The matrix is exactly singular (a zero pivot)."""


class _NotPositiveDefinite(Exception):
    """PARDISO's Cholesky met a non-positive pivot."""


def pardiso_available() -> bool:
    """True when pypardiso imports and MKL's PARDISO loads on this machine."""
    return _load_pardiso() is not None


_PARDISO_CLASS: list = []


def _load_pardiso():
    if not _PARDISO_CLASS:
        try:
            from pypardiso import PyPardisoSolver
            probe = PyPardisoSolver(mtype=-2)   # raises when MKL's mkl_rt cannot be found
            # pypardiso searches sys.prefix for mkl_rt in every constructor (~0.4 s each) unless
            # PYPARDISO_MKL_RT names it: record the library it found, once
            os.environ.setdefault("PYPARDISO_MKL_RT", probe.libmkl._name)
            _PARDISO_CLASS.append(PyPardisoSolver)
        except Exception:               # ImportError, OSError from ctypes
            _PARDISO_CLASS.append(None)
    return _PARDISO_CLASS[0]


def _upper_triangle(A: sp.csr_matrix) -> sp.csr_matrix:
    """The upper triangle (diagonal included) of a csr matrix, rows sorted, duplicates summed:
    one mask over the stored entries (scipy's triu goes through coo and back, 3x slower)."""
    if not A.has_canonical_format:       # sort a copy: callers may rely on their entry order
        A = A.copy()
        A.sum_duplicates()
    n = A.shape[0]
    rows = np.repeat(np.arange(n, dtype=A.indices.dtype), np.diff(A.indptr))
    keep = A.indices >= rows
    indptr = np.zeros(n + 1, dtype=A.indptr.dtype)
    np.cumsum(np.bincount(rows[keep], minlength=n), out=indptr[1:])
    return sp.csr_matrix((A.data[keep], A.indices[keep], indptr), shape=A.shape)


def _with_diagonal(upper: sp.csr_matrix) -> sp.csr_matrix:
    """``upper`` with every diagonal entry stored (PARDISO needs them, even zero ones)."""
    rows = np.repeat(np.arange(upper.shape[0]), np.diff(upper.indptr))
    stored = np.zeros(upper.shape[0], dtype=bool)
    stored[rows[upper.indices == rows]] = True
    missing = np.flatnonzero(~stored)
    if missing.size:                     # through coo: a csr sum would drop the explicit zeros
        upper = sp.csr_matrix((np.concatenate([upper.data, np.zeros(missing.size, upper.dtype)]),
                               (np.concatenate([rows, missing]), np.concatenate([upper.indices, missing]))),
                              shape=upper.shape)
        upper.sum_duplicates()
    return upper


class _PardisoInput:
    """The PARDISO input of a symmetric csr matrix: its upper triangle with the whole diagonal
    stored, in the working precision. For a matrix in canonical form the positions of those
    entries among the stored ones are kept, so that the next matrix of the same pattern (a
    Newton tangent) costs one gather instead of the triangle's extraction (20 ms of a 0.3 s
    factorisation at 100 x 100 CPD points)."""

    def __init__(self, dtype):
        self.dtype = dtype
        self._pattern = None             # (indptr, indices) of the last canonical input
        self._source = None              # position in A.data of each stored upper entry
        self._added = None               # stored upper entries that are added zero diagonals

    def __call__(self, A: sp.csr_matrix) -> sp.csr_matrix:
        if self._pattern is not None and A.indptr.shape == self._pattern[0].shape \
                and np.array_equal(A.indptr, self._pattern[0]) and np.array_equal(A.indices, self._pattern[1]):
            data = A.data[self._source].astype(self.dtype)
            data[self._added] = 0.0
            return sp.csr_matrix((data, self._upper_indices, self._upper_indptr), shape=A.shape)
        if not A.has_canonical_format:
            self._pattern = None
            upper = _with_diagonal(_upper_triangle(A))
            return sp.csr_matrix((upper.data.astype(self.dtype), upper.indices, upper.indptr), shape=A.shape)
        # the same extraction applied to the entries' positions (+1: an added diagonal is 0)
        where = sp.csr_matrix((np.arange(1.0, A.nnz + 1.0), A.indices, A.indptr), shape=A.shape)
        upper = _with_diagonal(_upper_triangle(where))
        source = upper.data.astype(np.int64) - 1
        self._added = np.flatnonzero(source < 0)
        self._source = np.maximum(source, 0)
        self._upper_indptr, self._upper_indices = upper.indptr, upper.indices
        self._pattern = (A.indptr.copy(), A.indices.copy())
        return self(A)


class DirectSolver:
    """Factorise a sparse symmetric matrix once, solve many right-hand sides.

    ``kind``: ``"auto"`` (PARDISO if available, else SuperLU), ``"pardiso"`` (error if
    unavailable) or ``"superlu"``. ``positive_definite=True`` lets PARDISO use Cholesky
    (matrix type 2); the default is symmetric indefinite LDL^T (type -2), needed for the
    saddle points of negative interface parameters (002 Eq 52). ``try_cholesky=True``
    (PARDISO only) factorises by Cholesky while the matrices are positive definite and by
    LDL^T from the first one that is not (``method``: ``"cholesky"``, ``"ldlt"``, or
    ``"lu"`` for SuperLU; ``stats["cholesky_fallbacks"]``).

    ``ordering`` (PARDISO only): ``None`` keeps MKL's defaults (nested dissection by
    METIS); ``"minimum_degree"`` makes the symbolic analysis ~2.5x faster on the 2D FEM
    matrices here (264k equations: 0.8 s instead of 2.2 s) at equal factorisation time;
    ``"metis"`` asks for nested dissection explicitly. Either explicit choice also sets
    Bunch-Kaufman pivoting with 1e-8 pivot perturbation (MKL's symmetric defaults), and
    then ``ordering_effort`` (0-10) and ``precision`` (``"double"`` or ``"single"``) apply
    (module docstring).
    """

    def __init__(self, kind: str = "auto", positive_definite: bool = False, ordering: str | None = None,
                 try_cholesky: bool = False, ordering_effort: int = 0, precision: str = "double"):
        if kind not in KINDS:
            raise ValueError(f"solver must be one of {', '.join(KINDS)}, got {kind!r}")
        if ordering not in ORDERINGS:
            raise ValueError(f"ordering must be one of {', '.join(map(str, ORDERINGS))}, got {ordering!r}")
        if isinstance(ordering_effort, bool) or not isinstance(ordering_effort, (int, np.integer)) \
                or not 0 <= ordering_effort <= 10:
            raise ValueError(f"ordering_effort must be an integer in [0, 10], got {ordering_effort!r}")
        if precision not in PRECISIONS:
            raise ValueError(f"precision must be one of {', '.join(PRECISIONS)}, got {precision!r}")
        if (ordering_effort or precision != "double") and ordering is None:
            raise ValueError("ordering_effort and precision need an explicit ordering "
                             f"({', '.join(map(str, ORDERINGS[1:]))})")
        cls = _load_pardiso() if kind in ("auto", "pardiso") else None
        if kind == "pardiso" and cls is None:
            raise ValueError("solver 'pardiso' is not available here (pip install pypardiso); "
                             "use 'auto' or 'superlu'")
        self.name = "pardiso" if cls is not None else "superlu"
        self._cls = cls
        self._ordering = ordering
        self._effort = int(ordering_effort)
        self._single = precision == "single" and cls is not None
        self.try_cholesky = bool(try_cholesky) and cls is not None
        self._mtype = 2 if (positive_definite or self.try_cholesky) else -2
        self._handles: dict = {}         # PARDISO matrix type -> (PyPardisoSolver, analysed pattern)
        self._input = _PardisoInput(np.float64)
        self._pardiso = self._handle(self._mtype) if cls is not None else None
        self._upper: sp.csr_matrix | None = None
        self._lu = None
        self.n = 0
        self.method = "lu" if cls is None else "cholesky" if self._mtype == 2 else "ldlt"
        self.stats = {"analyses": 0, "factorizations": 0, "solves": 0, "cholesky_fallbacks": 0}

    def _dtype(self, mtype: int):
        """Working precision of matrix type ``mtype``: float32 when asked, except for the LDL^T
        that replaces a failed Cholesky (an indefinite tangent is near a singular one)."""
        return np.float32 if self._single and (mtype == 2 or not self.try_cholesky) else np.float64

    @property
    def precision(self) -> str:
        """Precision of the last factorisation (``"single"`` or ``"double"``)."""
        return "single" if self._pardiso is not None and self._dtype(self._mtype) == np.float32 else "double"

    def _handle(self, mtype: int):
        """The PARDISO instance of matrix type ``mtype`` (created with this solver's iparm)."""
        if mtype not in self._handles:
            solver = self._cls(mtype=mtype)
            if self._ordering is not None:
                order = 10 * self._effort + _PARDISO_ORDERING[self._ordering]
                for i, value in ((1, 1), (2, order), (10, 8), (21, 1), (28, int(self._dtype(mtype) == np.float32))):
                    solver.set_iparm(i, value)  # iparm(1) = 1: use the values given
            self._handles[mtype] = [solver, None]
        return self._handles[mtype][0]

    # -- factorisation -------------------------------------------------------------
    def factorize(self, A: sp.spmatrix) -> None:
        """Numeric factorisation of the symmetric ``A`` (the symbolic one is redone only
        when the sparsity pattern changed). Raises SingularMatrixError on a zero pivot."""
        A = sp.csr_matrix(A, dtype=np.float64)
        self.n = A.shape[0]
        if self._pardiso is not None:
            self._factorize_pardiso(A)
        else:
            self._factorize_superlu(A)
        self.stats["factorizations"] += 1

    def _factorize_pardiso(self, A: sp.csr_matrix) -> None:
        upper = self._input(A)
        try:
            factored = self._numeric(self._mtype, upper)
        except _NotPositiveDefinite:
            self._mtype = -2             # LDL^T from now on: the next tangents are likely indefinite too
            self.stats["cholesky_fallbacks"] += 1
            factored = self._numeric(-2, upper)
        self._pardiso = self._handle(self._mtype)
        self.method = "cholesky" if self._mtype == 2 else "ldlt"
        self._upper = factored

    def _numeric(self, mtype: int, upper: sp.csr_matrix) -> sp.csr_matrix:
        """Analysis (when the pattern is new to this matrix type) and numeric factorisation of
        ``upper`` in the type's precision (returned: the solves use it)."""
        dtype = self._dtype(mtype)
        if dtype != upper.dtype:
            upper = sp.csr_matrix((upper.data.astype(dtype), upper.indices, upper.indptr), shape=upper.shape)
        solver = self._handle(mtype)
        pattern = self._handles[mtype][1]
        same = (pattern is not None and pattern[0].shape == upper.indptr.shape
                and np.array_equal(pattern[0], upper.indptr) and np.array_equal(pattern[1], upper.indices))
        solver.set_iparm(12, 0)          # CSR, not transposed
        rhs = np.zeros((self.n, 1), order="F", dtype=dtype)
        try:
            if not same:
                self._analyse(solver, upper, rhs)
                self._handles[mtype][1] = (upper.indptr.copy(), upper.indices.copy())
                self.stats["analyses"] += 1
            solver.set_phase(22)
            solver._call_pardiso(upper, rhs)
        except Exception as e:           # PyPardisoError carries MKL's error code
            self._handles[mtype][1] = None
            if mtype == 2 and self.try_cholesky and getattr(e, "value", None) == -4:
                raise _NotPositiveDefinite() from None
            raise SingularMatrixError(f"PARDISO factorisation failed ({e})") from None
        return upper

    def _analyse(self, solver, upper: sp.csr_matrix, rhs: np.ndarray) -> None:
        solver.set_phase(11)
        try:
            solver._call_pardiso(upper, rhs)
        except Exception:
            if self._effort == 0:
                raise
            # an MKL without the effort digit of iparm(2): plain ordering
            self._effort = 0
            solver.set_iparm(2, _PARDISO_ORDERING[self._ordering])
            solver._call_pardiso(upper, rhs)

    def _factorize_superlu(self, A: sp.csr_matrix) -> None:
        if self.n == 0:
            self._lu = None
            return
        try:
            self._lu = spla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A",
                                 options={"SymmetricMode": True, "DiagPivotThresh": 0.01})
        except RuntimeError as e:        # SuperLU: exactly singular
            raise SingularMatrixError(str(e)) from None
        self.stats["analyses"] += 1

    # -- results -------------------------------------------------------------------
    def solve(self, b: np.ndarray) -> np.ndarray:
        """x with A x = b for the last factorised A (b of shape (n,) or (n, k))."""
        b = np.asarray(b, dtype=np.float64)
        self.stats["solves"] += 1
        if self.n == 0:
            return np.zeros_like(b)
        if self._pardiso is None:
            return self._lu.solve(b)
        rhs = np.asfortranarray(b.reshape(self.n, -1), dtype=self._upper.dtype)
        self._pardiso.set_phase(33)
        x = self._pardiso._call_pardiso(self._upper, rhs)
        return x.reshape(b.shape).astype(np.float64, copy=False)

    def negative_pivots(self) -> int:
        """Number of negative pivots of the last factorisation (the matrix's negative
        eigenvalues by Sylvester's law of inertia); -1 when the pivoting hides it."""
        if self.n == 0:
            return 0
        if self._pardiso is not None:
            return 0 if self.method == "cholesky" else int(self._pardiso.get_iparm(23))
        lu = self._lu
        return int(np.sum(lu.U.diagonal() < 0)) if np.all(lu.perm_r == lu.perm_c) else -1

    def release(self) -> None:
        """Free the factors (PARDISO keeps them in MKL-managed memory)."""
        for entry in getattr(self, "_handles", {}).values():
            if entry[1] is not None:
                try:
                    entry[0].free_memory(everything=True)
                except Exception:
                    pass
                entry[1] = None
        self._lu = None

    def __del__(self):
        self.release()


__all__ = ["DirectSolver", "SingularMatrixError", "pardiso_available", "KINDS", "ORDERINGS", "PRECISIONS"]
