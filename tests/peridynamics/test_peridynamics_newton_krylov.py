"""The Newton step's linear solver: conjugate gradients preconditioned by the factors of an
earlier tangent, refactorisation when the Krylov iterations grow, the forcing term."""
import numpy as np
import pytest
import scipy.sparse as sp

from peridynamics.newton import TangentSolver, forcing, pcg


def _spd(n, seed, shift=0.5):
    """A sparse SPD matrix with the spectrum spread over ~4 decades (a 1D stiffness chain
    plus a random sparse part)."""
    rng = np.random.default_rng(seed)
    main = 2.0 + rng.random(n)
    T = sp.diags([-np.ones(n - 1), main, -np.ones(n - 1)], [-1, 0, 1])
    R = sp.random(n, n, density=4.0 / n, random_state=seed)
    return (T + shift * (R @ R.T) + 1e-4 * sp.identity(n)).tocsr()


def test_pcg_with_the_exact_factors_needs_no_iteration_and_a_perturbed_one_few():
    from scipy.sparse.linalg import splu

    K = _spd(400, 1)
    r = np.random.default_rng(2).standard_normal(400)
    lu = splu(K.tocsc())
    x, its = pcg(K, r, lu.solve, 1e-10, 30)
    assert its <= 1 and np.linalg.norm(K @ x - r) <= 2e-10 * np.linalg.norm(r)
    # tangent moved by 1 %: the old factors still precondition it to a fast contraction
    rng = np.random.default_rng(3)
    K1 = (K + 0.01 * sp.diags(rng.random(400) * K.diagonal())).tocsr()
    x, its = pcg(K1, r, lu.solve, 1e-10, 30)
    assert x is not None and 1 <= its <= 6
    assert np.linalg.norm(K1 @ x - r) <= 2e-10 * np.linalg.norm(r)
    # an indefinite matrix is detected (non-positive curvature), not silently solved
    Kn = (K - 2.0 * sp.identity(400)).tocsr()
    x, its = pcg(Kn, r, lu.solve, 1e-10, 30)
    assert x is None


def test_tangent_solver_reuses_the_factors_until_the_krylov_iterations_grow():
    K = _spd(600, 4)
    r = np.random.default_rng(5).standard_normal(600)
    s = TangentSolver(kind="superlu")       # the fallback: symmetric-mode SuperLU, same policy
    x = s.solve(K, r, rtol=1e-8)
    assert s.stats["factorizations"] == 1 and np.linalg.norm(K @ x - r) <= 2e-8 * np.linalg.norm(r)
    s = TangentSolver(kind="auto", refactor_after=4)
    x = s.solve(K, r, rtol=1e-8)
    assert s.stats["factorizations"] == 1 and np.linalg.norm(K @ x - r) <= 2e-8 * np.linalg.norm(r)
    if s.name == "pardiso":
        assert s.stats["krylov_method"] == "cg"
    rng = np.random.default_rng(6)
    small = (K + 1e-3 * sp.diags(rng.random(600) * K.diagonal())).tocsr()
    x = s.solve(small, r, rtol=1e-8)
    assert s.stats["factorizations"] == 1 and np.linalg.norm(small @ x - r) <= 2e-8 * np.linalg.norm(r)
    # a tangent far from the factorised one: the Krylov solve is slow (or fails) and the
    # solver factorises afresh, at once or at the next call
    far = (K + 3.0 * sp.diags(rng.random(600) * K.diagonal())).tocsr()
    for _ in range(2):
        x = s.solve(far, r, rtol=1e-8)
        assert np.linalg.norm(far @ x - r) <= 2e-8 * np.linalg.norm(r)
    assert s.stats["factorizations"] == 2
    s = TangentSolver(reuse=False)
    for M in (K, small):
        s.solve(M, r)
    assert s.stats["factorizations"] == 2 and s.stats["krylov_solves"] == 0


@pytest.mark.parametrize("r,tol,expect", [(1.0, 1e-11, 1e-3), (1e-2, 1e-11, 1e-4), (1e-6, 1e-11, 1e-6),
                                          (1e-10, 1e-11, 1e-3)])
def test_forcing_term(r, tol, expect):
    """1 % of r (quadratic rate), at most 1e-3, never tighter than 0.1 tol / r."""
    assert forcing(r, tol) == pytest.approx(expect, rel=1e-12)


@pytest.mark.parametrize("strain_scale", [1.0, 1000.0])
def test_krylov_newton_matches_a_factorisation_every_iteration(strain_scale):
    """The inexact Newton-CG solve and the exact one (a fresh factorisation every
    iteration) reach the same equilibrium in the same number of iterations, in the linear
    regime and at 003 Table 3's finite stretch (bimaterial square, compliant interface)."""
    import math

    from cases import library
    from peridynamics.discretization import discretize
    from peridynamics.interface import split_band
    from peridynamics.newton import NewtonOptions, newton_solve
    from peridynamics.solver import boundary_vectors, build_system

    case = library.bimaterial_square(parameter_set=2, load_case=1, interface="vertical", Dn=1e-2, Dt=math.inf,
                                     strain_scale=strain_scale)
    h = 0.1
    disc, springs, ties = split_band(case, discretize(case, h, 3.01 * h, 3.01 * h))
    system, _ = build_system(case, disc, "continuum", None, springs, ties)
    fixed, u_bar, f_ext = boundary_vectors(disc)
    runs = [newton_solve(system, fixed, u_bar, f_ext, NewtonOptions(load_steps=2, reuse_factorization=reuse))
            for reuse in (True, False)]
    krylov, exact = runs
    assert krylov.linear["krylov_solves"] >= 2 and exact.linear["krylov_solves"] == 0
    assert krylov.linear["factorizations"] < exact.linear["factorizations"]
    assert [len(s["residuals"]) for s in krylov.history] == [len(s["residuals"]) for s in exact.history]
    scale = np.abs(exact.u).max()
    # both stop below tol = 1e-11 of the normalised residual; measured difference 2.9e-14
    # (linear) and 1.1e-16 (finite stretch) of max |u|
    assert np.abs(krylov.u - exact.u).max() < 1e-13 * scale


def test_progress_lines_report_every_evaluation_iteration_and_trial(capsys, caplog):
    """``progress=True`` prints one line per evaluation, iteration and line-search trial with
    the residual the history records; without it the same lines go to the logger."""
    import logging
    import re

    import peridynamics
    from cases import library

    case = library.bimaterial_square(parameter_set=3, load_case=3, interface="vertical")
    res = peridynamics.solve(case, h=0.1, progress=True)
    lines = capsys.readouterr().err.splitlines()
    hist = res.diagnostics["newton_history"][0]["residuals"]
    its = [float(m.group(1)) for m in (re.search(r"iteration \d+: normalised residual (\S+)", s) for s in lines) if m]
    assert np.allclose(its, hist, rtol=1e-3)
    assert sum("trial step 1:" in s for s in lines) == len(hist) - 1
    assert sum("evaluated in" in s for s in lines) >= len(hist)
    assert all(re.match(r"CPD Newton \[ *\d+\.\d s\]", s) for s in lines if "CPD Newton" in s)
    with caplog.at_level(logging.INFO, logger="peridynamics.newton"):
        peridynamics.solve(case, h=0.1, progress=False)
    assert capsys.readouterr().err == "" and sum("normalised residual" in r.message for r in caplog.records) >= len(hist)
    with pytest.raises(Exception, match="cpd.progress"):
        peridynamics.solve(case, h=0.1, progress="yes")


def test_an_indefinite_failing_step_says_the_state_is_unstable():
    from peridynamics.newton import StepFailure, _advice

    f = StepFailure(1.0, [1.0, 0.19], "line search found no decrease; tangent indefinite (208 negative pivots)")
    assert "unstable" in _advice(f) and "load_steps" in _advice(f)
    assert "unstable" not in _advice(StepFailure(1.0, [1.0], "line search found no decrease"))
    assert "rigid-body" in _advice(StepFailure(1.0, [1.0], "singular tangent (x); tangent indefinite (3 negative pivots)"))


def _free_free_chain(n: int, eps: float) -> sp.csr_matrix:
    """1D stiffness chain with free ends plus eps on the diagonal: cond ~ 4 / eps."""
    main = np.full(n, 2.0)
    main[0] = main[-1] = 1.0
    return sp.diags([-np.ones(n - 1), main + eps, -np.ones(n - 1)], [-1, 0, 1]).tocsr()


@pytest.mark.parametrize("eps,fallbacks", [(1e-6, 0), (1e-8, 1)])
def test_float32_factors_refined_or_replaced_by_double_ones(eps, fallbacks):
    """Single-precision factors precondition CG to the asked residual; when the tangent is
    too ill-conditioned for them (cond 4e8) the solver factorises in double precision."""
    from interfaces.sparse import pardiso_available

    if not pardiso_available():
        pytest.skip("PARDISO not available")
    K = _free_free_chain(2000, eps)
    r = np.random.default_rng(0).standard_normal(2000)
    s = TangentSolver(kind="pardiso", precision="single")
    x = s.solve(K, r, rtol=1e-8)
    assert np.linalg.norm(K @ x - r) <= 1e-8 * np.linalg.norm(r)       # measured 7e-12, 8e-10
    assert s.stats["precision_fallbacks"] == fallbacks
    assert s.precision == ("single" if fallbacks == 0 else "double")
    assert s.direct.method == "cholesky"


def test_single_precision_factors_keep_the_newton_history():
    """Float32 Cholesky factors (refined by CG) against double-precision LDL^T on the
    bimaterial square, set 3: same iterations, same equilibrium, same residual history to
    the forcing term's accuracy."""
    from cases import library
    from interfaces.sparse import pardiso_available
    from peridynamics import newton
    from peridynamics.discretization import discretize
    from peridynamics.newton import NewtonOptions, newton_solve
    from peridynamics.solver import boundary_vectors, build_system

    if not pardiso_available():
        pytest.skip("PARDISO not available")
    case = library.bimaterial_square(parameter_set=3, load_case=1, interface="vertical")
    h = 0.05
    disc = discretize(case, h, 3.01 * h, 3.01 * h, grid="cell")
    system, _ = build_system(case, disc, "continuum", None)
    fixed, u_bar, f_ext = boundary_vectors(disc)
    runs = {}
    for precision in ("single", "double"):
        newton.FACTOR_PRECISION = precision
        try:
            runs[precision] = newton_solve(system, fixed, u_bar, f_ext,
                                           NewtonOptions(load_steps=2, preconditioner="tangent"))
        finally:
            newton.FACTOR_PRECISION = "single"
    single, double = runs["single"], runs["double"]
    assert single.linear["factorization"] == "cholesky" and single.linear["cholesky_fallbacks"] == 0
    assert single.linear["precision_fallbacks"] == 0
    assert [len(s["residuals"]) for s in single.history] == [len(s["residuals"]) for s in double.history]
    a, b = (np.array(single.history[0]["residuals"]), np.array(double.history[0]["residuals"]))
    # after the fresh factorisation (solved to 1e-10 or round-off): measured 1e-11 relative
    assert a[1] == pytest.approx(b[1], rel=1e-8)
    # after a CG solve to the forcing term eta_k: the residuals differ by less than the linear
    # residual allowed, eta_k r_k (measured 6e-16 to 3e-14 against 1e-8 at the second
    # iteration); below tol = 1e-11 they are round-off
    diff = np.abs(a[2:] - b[2:])
    allowed = [forcing(r, 1e-11) * r for r in b[1:-1]]
    assert np.all((diff <= allowed) | (b[2:] < 1e-11))
    scale = np.abs(double.u).max()
    assert np.abs(single.u - double.u).max() < 1e-13 * scale          # measured 2.3e-14


def test_a_load_tiny_against_the_stiffness_converges_at_the_residual_round_off_floor():
    """CPD is linear in the small-load limit: the two-layer block's energies scale with
    the stress squared. At 1e-3 of the paper's stress and below, the residual's round-off
    lies above tol x its first value; the solve stops when the Newton update can no longer
    move a point (it ran line searches and step cuts for over ten minutes before)."""
    import cases
    import peridynamics

    def per_stress2(stress):
        q = peridynamics.solve(cases.build("two_layer", stress=stress)).quantities
        return np.array([q["interface_energy"], q["strain_energy"]]) / stress ** 2

    ref = per_stress2(5e-3)
    # measured: 6.1e-5 / 5.1e-6 (5e-4) and 4.5e-5 / 4.0e-6 (5e-7) from 5e-3, the load's
    # own geometric nonlinearity (0.5 MPa is 0.67 % / 0.06 % off the small-load limit)
    for stress in (5e-4, 5e-7):
        np.testing.assert_allclose(per_stress2(stress), ref, rtol=2.5e-4)
