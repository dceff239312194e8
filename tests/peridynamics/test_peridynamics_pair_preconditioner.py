"""The pair part of the CPD tangent as the factorised preconditioner of the inexact Newton
steps (peridynamics.preconditioner): additivity, positive definiteness, the same Newton
history and equilibrium as the tangent's own factors, fallbacks, refusals."""
import numpy as np
import pytest
import scipy.sparse as sp

from interfaces.sparse import pardiso_available

pytestmark = pytest.mark.skipif(not pardiso_available(), reason="float32 factors need PARDISO")


def _square(h=0.05, **kw):
    from cases import library
    from peridynamics.discretization import discretize
    from peridynamics.solver import boundary_vectors, build_system

    case = library.bimaterial_square(parameter_set=3, load_case=1, interface="vertical", **kw)
    disc = discretize(case, h, 3.01 * h, 3.01 * h, grid="cell")
    system, _ = build_system(case, disc, "continuum", None)
    fixed, u_bar, f_ext = boundary_vectors(disc)
    return system, fixed, u_bar, f_ext


def test_pair_tangent_is_the_C1_part_and_positive_definite():
    """K = P + (tangent of the (0, C2, 0) material) to round-off, and P_ff is SPD."""
    from peridynamics.assembly import CPDSystem, MaterialBlock
    from peridynamics.preconditioner import PairTangent, pair_preconditioner_applies
    from peridynamics.reduction import ReducedMatrix

    system, fixed, u_bar, _ = _square()
    assert pair_preconditioner_applies(system)
    free = np.setdiff1d(np.arange(system.X.size), fixed)
    u = u_bar + 1e-4 * np.random.default_rng(1).standard_normal(u_bar.shape)
    K = ReducedMatrix(system, free)(system.evaluate(u).tangent.data).toarray()
    P = PairTangent(system, free)(u)
    rest = [MaterialBlock(b.name, b.centers, b.nptr, b.nidx, np.array([0.0, b.C[1], 0.0])) for b in system.blocks]
    s2 = CPDSystem(system.X, system.vol, rest, system.delta)
    K2 = ReducedMatrix(s2, free)(s2.evaluate(u).tangent.data).toarray()
    assert np.abs(P.toarray() + K2 - K).max() <= 1e-12 * np.abs(K).max()
    assert P.nnz < 0.5 * np.count_nonzero(K)                       # the narrower stencil
    assert np.linalg.eigvalsh(P.toarray()).min() > 0


@pytest.mark.parametrize("steps", [1, 3])
def test_pair_preconditioned_newton_equals_the_direct_one(steps):
    """Same iteration counts, residual histories equal to the forcing term's accuracy,
    equilibria equal to 1e-9 of the displacement (the linear solves stop at the forcing term)."""
    from peridynamics.newton import NewtonOptions, forcing, newton_solve

    system, fixed, u_bar, f_ext = _square()
    runs = {pre: newton_solve(system, fixed, u_bar, f_ext, NewtonOptions(load_steps=steps, preconditioner=pre))
            for pre in ("pairs", "tangent")}
    pairs, direct = runs["pairs"], runs["tangent"]
    assert pairs.linear["preconditioner"] == "pairs" and direct.linear["preconditioner"] == "tangent"
    assert pairs.linear["factorizations"] == 0 and pairs.linear["approx_factorizations"] >= 1
    assert pairs.linear["approx_fallbacks"] == 0
    assert pairs.iterations == direct.iterations
    for a, b in zip(pairs.history, direct.history):
        a, b = np.array(a["residuals"]), np.array(b["residuals"])
        allowed = [2 * forcing(r, 1e-11) * r for r in b[:-1]]
        assert np.all((np.abs(a[1:] - b[1:]) <= allowed) | (b[1:] < 1e-11))
    assert np.abs(pairs.u - direct.u).max() <= 1e-9 * np.abs(direct.u).max()


def _random_spd(seed: int, n: int = 300):
    """A sparse symmetric positive definite K (A A^T + I) and a right-hand side."""
    A = sp.random(n, n, density=0.02, random_state=seed)
    return (A @ A.T + sp.identity(n)).tocsr(), np.random.default_rng(seed).standard_normal(n)


def test_an_indefinite_approximation_falls_back_to_the_tangent_factors():
    """approx() not positive definite: the solver factorises K itself from then on."""
    from peridynamics.newton import TangentSolver

    K, r = _random_spd(5)
    solver = TangentSolver(reuse=True)
    x = solver.solve(K, r, rtol=1e-10, approx=lambda: (-K).tocsr())
    assert np.linalg.norm(K @ x - r) <= 2e-10 * np.linalg.norm(r)
    assert solver.stats["approx_fallbacks"] == 1 and solver.stats["factorizations"] == 1
    assert solver.active is solver.direct
    solver.solve(K, r, rtol=1e-10, approx=lambda: (-K).tocsr())        # not tried again
    assert solver.stats["approx_factorizations"] == 1


def test_a_good_approximation_is_reused_and_a_poor_one_given_up():
    from peridynamics.newton import TangentSolver

    K, r = _random_spd(6)
    good = TangentSolver(reuse=True)
    for _ in range(3):
        x = good.solve(K, r, rtol=1e-10, approx=lambda: (K + 0.05 * sp.diags(K.diagonal())).tocsr())
        assert np.linalg.norm(K @ x - r) <= 2e-10 * np.linalg.norm(r)
    assert good.stats["approx_factorizations"] == 1 and good.stats["factorizations"] == 0
    poor = TangentSolver(reuse=True, approx_refactor_after=2)
    x = poor.solve(K, r, rtol=1e-10, approx=lambda: sp.diags(K.diagonal()).tocsr())
    assert x is not None and np.linalg.norm(K @ x - r) <= 2e-10 * np.linalg.norm(r)
    poor.solve(K, r, rtol=1e-10, approx=lambda: sp.diags(K.diagonal()).tocsr())
    assert poor.stats["approx_fallbacks"] == 1 and poor.stats["factorizations"] == 1


def test_pairs_only_where_they_apply_and_unknown_values_refused():
    from interfaces.errors import CaseError
    from peridynamics.newton import Equations, NewtonOptions, newton_solve
    from peridynamics.solver import _options

    system, fixed, u_bar, f_ext = _square()
    assert Equations(system, fixed, u_bar, f_ext, NewtonOptions()).pairs is not None
    for opts in (NewtonOptions(path="arc_length"), NewtonOptions(preconditioner="tangent"),
                 NewtonOptions(reuse_factorization=False)):
        assert Equations(system, fixed, u_bar, f_ext, opts).pairs is None
    with pytest.raises(ValueError, match="preconditioner must be one of pairs, tangent"):
        newton_solve(system, fixed, u_bar, f_ext, NewtonOptions(preconditioner="amg"))
    from cases import library

    case = library.bimaterial_square(parameter_set=3, load_case=1, interface="vertical")
    with pytest.raises(CaseError, match="cpd.preconditioner must be one of pairs, tangent"):
        _options(case, {"preconditioner": "ilu"})
