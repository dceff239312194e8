"""interfaces.sparse: both back ends solve, count negative pivots (inertia) and reuse
the symbolic analysis when the pattern repeats."""
import numpy as np
import pytest
import scipy.sparse as sp

from interfaces.sparse import DirectSolver, SingularMatrixError, pardiso_available

KINDS = ["superlu"] + (["pardiso"] if pardiso_available() else [])


def _laplacian(n: int) -> sp.csr_matrix:
    T = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(n, n))
    return sp.kronsum(T, T).tocsr()


@pytest.mark.parametrize("kind", KINDS)
def test_solves_and_counts_negative_pivots(kind):
    n = 20
    A = _laplacian(n)
    b = np.random.default_rng(0).random(A.shape[0])
    s = DirectSolver(kind)
    assert s.name == kind and s.method == ("lu" if kind == "superlu" else "ldlt")
    s.factorize(A)
    x = s.solve(b)
    assert np.linalg.norm(A @ x - b) < 1e-11 * np.linalg.norm(b)        # measured ~1e-12
    assert s.negative_pivots() == 0
    shift = 0.5
    B = (A - shift * sp.identity(A.shape[0])).tocsr()
    expected = int(np.sum(np.linalg.eigvalsh(B.toarray()) < 0))
    s.factorize(B)
    X = s.solve(np.stack([b, 2 * b], axis=1))
    assert np.allclose(B @ X[:, 1], 2 * b, atol=1e-9)
    got = s.negative_pivots()
    assert got in (expected, -1) and (kind == "superlu" or got == expected)


@pytest.mark.parametrize("ordering", ["minimum_degree", "metis"])
def test_explicit_orderings_keep_the_inertia(ordering):
    A = (_laplacian(20) - 0.5 * sp.identity(400)).tocsr()
    expected = int(np.sum(np.linalg.eigvalsh(A.toarray()) < 0))
    s = DirectSolver("auto", ordering=ordering)
    s.factorize(A)
    b = np.ones(400)
    assert np.allclose(A @ s.solve(b), b, atol=1e-9)
    assert s.negative_pivots() in ((expected,) if s.name == "pardiso" else (expected, -1))
    with pytest.raises(ValueError, match="ordering must be one of"):
        DirectSolver("auto", ordering="rcm")


@pytest.mark.parametrize("kind", KINDS)
def test_symbolic_analysis_reused_for_same_pattern(kind):
    A = _laplacian(10)
    s = DirectSolver(kind)
    s.factorize(A)
    s.factorize(3.0 * A)
    b = np.ones(A.shape[0])
    assert np.allclose(3.0 * A @ s.solve(b), b)
    if kind == "pardiso":
        assert s.stats | {"cholesky_fallbacks": 0} == {"analyses": 1, "factorizations": 2, "solves": 1,
                                                       "cholesky_fallbacks": 0}


@pytest.mark.parametrize("kind", KINDS)
def test_singular_matrix_is_reported(kind):
    A = sp.csr_matrix(np.array([[1.0, 1.0], [1.0, 1.0]]))
    s = DirectSolver(kind)
    try:
        s.factorize(A)
        x = s.solve(np.array([1.0, 2.0]))
    except SingularMatrixError:
        return
    # PARDISO perturbs tiny pivots instead of failing: the solution must then be unusable
    assert not np.allclose(A @ x, [1.0, 2.0])


def test_unknown_kind_refused():
    with pytest.raises(ValueError, match="solver must be one of"):
        DirectSolver("cholmod")


needs_pardiso = pytest.mark.skipif(not pardiso_available(), reason="PARDISO not available")


def _spd(n: int = 20) -> sp.csr_matrix:
    """A positive definite matrix with 2 DOFs per node and wide rows (a 2D Laplacian coupled
    to its neighbours' neighbours, times a 2x2 positive definite block)."""
    L = _laplacian(n)
    return sp.kron((L @ L + L).tocsr(), np.array([[2.0, 0.5], [0.5, 1.0]])).tocsr()


@needs_pardiso
@pytest.mark.parametrize("effort", [0, 2])
def test_cholesky_equals_ldlt_to_round_off(effort):
    A = _spd()
    b = np.random.default_rng(1).random(A.shape[0])
    ldlt = DirectSolver("pardiso", ordering="metis")
    chol = DirectSolver("pardiso", ordering="metis", try_cholesky=True, ordering_effort=effort)
    ldlt.factorize(A)
    chol.factorize(A)
    x0, x1 = ldlt.solve(b), chol.solve(b)
    assert chol.method == "cholesky" and ldlt.method == "ldlt"
    assert chol.negative_pivots() == 0 == ldlt.negative_pivots()
    # cond(A) = 4.2e3: the solves differ by 1.3e-14, residual 1e-13 (measured, relative)
    assert np.linalg.norm(x1 - x0) <= 1e-13 * np.linalg.norm(x0)
    assert np.linalg.norm(A @ x1 - b) <= 5e-13 * np.linalg.norm(b)


@needs_pardiso
@pytest.mark.parametrize("precision", ["double", "single"])
def test_cholesky_falls_back_to_ldlt_on_an_indefinite_matrix(precision):
    A = _spd(10)
    n = A.shape[0]
    shift = float(np.sort(np.linalg.eigvalsh(A.toarray()))[3:5].mean())     # 4 negative eigenvalues
    B = (A - shift * sp.identity(n)).tocsr()
    b = np.ones(n)
    s = DirectSolver("pardiso", ordering="metis", try_cholesky=True, precision=precision)
    s.factorize(A)
    assert (s.method, s.stats["cholesky_fallbacks"], s.precision) == ("cholesky", 0, precision)
    s.factorize(B)
    assert (s.method, s.stats["cholesky_fallbacks"], s.precision) == ("ldlt", 1, "double")
    assert s.negative_pivots() == 4
    assert np.linalg.norm(B @ s.solve(b) - b) <= 1e-10 * np.linalg.norm(b)
    s.factorize(A)                          # LDL^T kept, its analysis reused
    assert s.method == "ldlt" and s.negative_pivots() == 0
    assert np.linalg.norm(A @ s.solve(b) - b) <= 1e-12 * np.linalg.norm(b)
    assert s.stats["analyses"] == 2         # one per matrix type
    plain = DirectSolver("pardiso", positive_definite=True, ordering="metis")
    with pytest.raises(SingularMatrixError):    # Cholesky without fallback still refuses
        plain.factorize(B)


@needs_pardiso
def test_single_precision_factors_refined_in_double():
    A = _spd()
    b = np.random.default_rng(2).random(A.shape[0])
    s = DirectSolver("pardiso", ordering="metis", try_cholesky=True, precision="single")
    s.factorize(A)
    x = s.solve(b)
    assert x.dtype == np.float64 and s.precision == "single"
    rel = np.linalg.norm(A @ x - b) / np.linalg.norm(b)
    assert 1e-9 < rel < 1e-3                # float32 factors, cond(A) = 4.2e3: measured 4e-5
    for _ in range(3):                      # iterative refinement, residuals in double
        x += s.solve(b - A @ x)
    assert np.linalg.norm(A @ x - b) <= 5e-13 * np.linalg.norm(b)    # measured 7e-10, 5e-14, 6e-14


def test_bad_factorisation_options_refused():
    with pytest.raises(ValueError, match=r"ordering_effort must be an integer in \[0, 10\]"):
        DirectSolver("auto", ordering="metis", ordering_effort=11)
    with pytest.raises(ValueError, match="precision must be one of double, single"):
        DirectSolver("auto", ordering="metis", precision="half")
    with pytest.raises(ValueError, match="need an explicit ordering"):
        DirectSolver("auto", precision="single")


def _upper_nnz(S):
    coo = S.tocoo()
    return int(np.sum(coo.col >= coo.row))


@needs_pardiso
def test_same_pattern_input_reused_with_missing_diagonal_entries():
    """A saddle-point matrix without stored diagonal in its constraint block, factorised again
    with new values of the same pattern (the kept positions of the upper triangle) and then
    in a non-canonical entry order: every solve exact."""
    rng = np.random.default_rng(3)
    A = _spd(6)
    m = 10
    B = sp.random(m, A.shape[0], density=0.2, random_state=4, format="csr")
    B = (B + sp.eye(m, A.shape[0])).tocsr()
    S = sp.bmat([[A, B.T], [B, None]], format="csr")
    S.sort_indices()
    b = rng.random(S.shape[0])
    s = DirectSolver("pardiso", ordering="metis")
    for scale in (1.0, 3.0):
        M = (scale * S).tocsr()
        s.factorize(M)
        assert np.linalg.norm(M @ s.solve(b) - b) <= 1e-10 * np.linalg.norm(b)
    assert s.stats["analyses"] == 1
    assert np.all(s._upper.diagonal()[A.shape[0]:] == 0) and s._upper.nnz == _upper_nnz(S) + m   # zeros stored
    perm = rng.permutation(S.nnz)                     # same entries, rows' order shuffled
    rows = np.repeat(np.arange(S.shape[0]), np.diff(S.indptr))
    shuffled = sp.csr_matrix((S.data[perm], (rows[perm], S.indices[perm])), shape=S.shape)
    shuffled = sp.csr_matrix((shuffled.data, shuffled.indices, shuffled.indptr), shape=S.shape)
    s.factorize(shuffled)
    assert np.linalg.norm(S @ s.solve(b) - b) <= 1e-10 * np.linalg.norm(b)
