"""Compliant CPD overlap interface: exact derivatives, local limit of the springs, refusals."""
import math

import numpy as np
import pytest

from cases import library
from interfaces import BilinearNormalInterface, CoulombFriction, LinearInterface
from interfaces.errors import CaseError, SolverError
import peridynamics
from peridynamics.discretization import discretize
from peridynamics.interface import split_band
from peridynamics.solver import build_system


def _system(case, h, overlap=1.0, dfac=3.01):
    delta = dfac * h
    disc = discretize(case, h, delta, overlap * delta)
    disc, springs, ties = split_band(case, disc)
    system, _ = build_system(case, disc, "continuum", None, springs, ties)
    return disc, springs, ties, system


def _fd(system, u, eps=1e-7):
    """Central differences of energy and residual in the independent DOFs."""
    dofs = system.dofs
    x = np.zeros(dofs.n)
    x[dofs.index] = u.ravel()
    ev = system.evaluate(dofs.expand(x).reshape(u.shape))
    g_a = dofs.reduce(ev.residual.ravel())
    P = np.zeros((u.size, dofs.n))
    P[np.arange(u.size), dofs.index] = 1.0
    K_a = P.T @ ev.tangent.toarray() @ P
    g = np.empty(dofs.n)
    K = np.empty((dofs.n, dofs.n))
    for k in range(dofs.n):
        xp, xm = x.copy(), x.copy()
        xp[k] += eps
        xm[k] -= eps
        ep = system.evaluate(dofs.expand(xp).reshape(u.shape), False)
        em = system.evaluate(dofs.expand(xm).reshape(u.shape), False)
        g[k] = (ep.energy - em.energy) / (2 * eps)
        K[:, k] = (dofs.reduce(ep.residual.ravel()) - dofs.reduce(em.residual.ravel())) / (2 * eps)
    return (np.linalg.norm(g - g_a) / np.linalg.norm(g), np.linalg.norm(K - K_a) / np.linalg.norm(K), ev)


@pytest.mark.parametrize("build,h,dfac,Dn,Dt", [
    (lambda Dn, Dt: library.bimaterial_square(parameter_set=3, interface="diagonal", Dn=Dn, Dt=Dt), 0.2, 3.01, 3e-4, 1e-4),
    (lambda Dn, Dt: library.bimaterial_square(parameter_set=3, interface="vertical", Dn=Dn, Dt=Dt), 0.2, 3.01, math.inf, 1e-4),
    (lambda Dn, Dt: library.cuboid(interface="horizontal", size=(0.2, 0.2, 0.3), Dn=Dn, Dt=Dt), 0.1, 1.51, 2e-3, 5e-4),
    (lambda Dn, Dt: library.cuboid(interface="vertical", size=(0.3, 0.2, 0.2), Dn=Dn, Dt=Dt), 0.1, 1.51, 2e-3, math.inf),
])
def test_residual_and_tangent_with_springs_are_exact_derivatives(build, h, dfac, Dn, Dt):
    case = build(Dn, Dt)
    disc, springs, ties, system = _system(case, h, dfac=dfac)
    assert springs.count > 0 and springs.counted.any()
    assert (len(ties) > 0) == (math.isinf(Dn) or math.isinf(Dt))
    rng = np.random.default_rng(5)
    u = 0.02 * h * rng.standard_normal(disc.X.shape)
    err_g, err_K, ev = _fd(system, u)
    assert ev.spring_energy.sum() > 0
    assert err_g < 1e-6 and err_K < 1e-6


@pytest.mark.parametrize("overlap,interface", [(1.0, "vertical"), (0.25, "horizontal"), (1.0, "diagonal")])
def test_uniform_jump_stores_the_interface_law_energy(overlap, interface):
    """Local limit: a rigid relative translation g of B against A stores 1/2 (Dn g_n^2 + Dt g_t^2) |Gamma|."""
    Dn, Dt = 7.0, 3.0
    case = library.bimaterial_square(parameter_set=1, interface=interface, Dn=Dn, Dt=Dt)
    disc, springs, _, system = _system(case, 0.05, overlap)
    g = np.array([0.013, -0.021])
    u = np.zeros_like(disc.X)
    u[disc.owner == 1] = g                   # every B node (originals and copies) translates
    e = system.springs.springs.energy(u)[springs.counted].sum()
    n = {"vertical": np.array([1.0, 0.0]), "horizontal": np.array([0.0, 1.0]),
         "diagonal": np.array([-1.0, 1.0]) / math.sqrt(2)}[interface]
    length = math.sqrt(2) if interface == "diagonal" else 1.0
    gn = g @ n
    assert np.allclose(springs.normal[springs.counted], n)
    assert e == pytest.approx(0.5 * (Dn * gn ** 2 + Dt * (g @ g - gn ** 2)) * length, rel=1e-12)


def test_stiff_springs_tend_to_the_shared_dof_coupling():
    """Dn = Dt = D -> inf tends to today's shared-DOF coupling: the differences of the strain
    energy and of the displacements shrink like 1/D (measured: 7.1e-3, 7.4e-4, 7.4e-5 of the
    energy at D = 1e-4, 1e-3, 1e-2 MPa/mm, i.e. D h / mu = 2.8 .. 280)."""
    base = dict(parameter_set=3, load_case=3, interface="vertical")
    opts = dict(h=0.1, overlap=1.0, calibration="lattice")  # the same material constants for all D
    ref = peridynamics.solve(library.bimaterial_square(**base), **opts)
    e0, u0 = ref.quantities["strain_energy"], ref.fields["displacement"]
    de, du = [], []
    for D in (1e-4, 1e-3, 1e-2):
        r = peridynamics.solve(library.bimaterial_square(Dn=D, Dt=D, **base), **opts)
        de.append(abs(r.quantities["strain_energy"] / e0 - 1))
        du.append(np.abs(r.fields["displacement"][:len(u0)] - u0).max() / np.abs(u0).max())
        assert r.quantities["interface_energy"] > 0
    for err in (de, du):
        assert 8.0 < err[0] / err[1] < 12.0 and 8.0 < err[1] / err[2] < 12.0
    assert de[2] < 1e-4


def test_very_stiff_springs_converge_at_the_round_off_floor_and_keep_the_1_over_D_trend():
    """D h / mu = 2.8e5 .. 2.8e9: the ill-conditioned tangent puts the residual's round-off
    floor above tol = 1e-11, where Newton used to cut steps and fail. It now stops at the
    floor (peridynamics.newton.below_roundoff), and the energy still departs from the
    shared-DOF coupling like 1/D (measured 7.186e-8, 7.186e-10, 7.194e-12: the trend of
    the test above, 7.4e-5 at D = 1e-2, continued)."""
    base = dict(parameter_set=3, load_case=3, interface="vertical")
    opts = dict(h=0.1, overlap=1.0, calibration="lattice")
    e0 = peridynamics.solve(library.bimaterial_square(**base), **opts).quantities["strain_energy"]
    de = [abs(peridynamics.solve(library.bimaterial_square(Dn=D, Dt=D, **base), **opts)
              .quantities["strain_energy"] / e0 - 1) for D in (10.0, 1e3, 1e5)]
    assert 99.0 < de[0] / de[1] < 101.0 and 99.0 < de[1] / de[2] < 101.0
    assert 6.5e-8 < de[0] < 8e-8


@pytest.mark.parametrize("law,word", [(BilinearNormalInterface(Dn_tension=1.0, Dt=1.0), "BilinearNormalInterface"),
                                      (CoulombFriction(0.3), "CoulombFriction")])
def test_laws_cpd_cannot_represent_are_refused(law, word):
    case = library.bimaterial_square()
    case.interfaces[0].law = law
    with pytest.raises(CaseError, match=word):
        peridynamics.solve(case, h=0.1)


def test_perfect_direction_on_an_oblique_interface_is_refused():
    case = library.bimaterial_square(interface="diagonal", Dn=math.inf, Dt=1.0)
    with pytest.raises(CaseError, match="grid axis"):
        peridynamics.solve(case, h=0.1)


def test_newton_failure_reports_the_failing_step_history():
    case = library.bimaterial_square(parameter_set=2, load_case=1, interface="vertical", strain_scale=1000.0)
    with pytest.raises(SolverError, match=r"failing step: max_iter = 1 reached; its normalised residuals \[1, ") as e:
        peridynamics.solve(case, h=0.1, max_iter=1, load_steps=2)
    assert "load factor 0.0078" in str(e.value) and "load_steps" in str(e.value)


def test_one_symbolic_analysis_for_all_iterations_and_load_steps():
    """The reduced tangent keeps one pattern: PARDISO analyses it once, then only refactorises."""
    from interfaces.sparse import pardiso_available
    from peridynamics.newton import NewtonOptions, newton_solve
    from peridynamics.solver import boundary_vectors

    case = library.bimaterial_square(parameter_set=3, load_case=3, interface="vertical", Dn=1e-4, Dt=math.inf)
    disc, springs, ties, system = _system(case, 0.1)
    fixed, u_bar, f_ext = boundary_vectors(disc)
    out = newton_solve(system, fixed, u_bar, f_ext, NewtonOptions(load_steps=3, reuse_factorization=False))
    lin = out.linear
    assert lin["factorizations"] == out.iterations >= 3
    assert lin["solver"] in ("pardiso", "superlu")
    if pardiso_available():
        assert lin["solver"] == "pardiso" and lin["symbolic_analyses"] == 1
    res = peridynamics.solve(case, h=0.1, solver="superlu")
    assert res.diagnostics["linear_solver"]["solver"] == "superlu"
    with pytest.raises(CaseError, match="cpd.solver"):
        peridynamics.solve(case, h=0.1, solver="mumps")


@pytest.mark.slow
@pytest.mark.parametrize("D", [math.inf, 1e-2])
def test_cuboid_at_the_papers_spacing_reduced_size(D):
    """003 Sec 4.5 spacing Delta = 0.035, delta = 3.01 Delta, on a 0.3 x 0.2 x 0.2 cuboid
    (540 points, 3.8e7 quadruples per tangent, ~4 s each on one core): quadratic Newton,
    with the perfect and with a compliant interface (D h / mu ~ 28)."""
    case = library.cuboid(interface="horizontal", load_case=2, size=(0.3, 0.2, 0.2), Dn=D, Dt=D)
    res = peridynamics.solve(case, h=0.035)
    r = res.diagnostics["newton_history"][0]["residuals"]
    assert r[-1] <= 1e-11 and len(r) <= 5
    for a, b in zip(r[:-1], r[1:]):
        if a < 1e-3 and b > 1e-13:
            assert b < 1e3 * a * a
    q = res.quantities
    assert abs(q["reaction_all_xmin_x"] + q["reaction_all_xmax_x"]) < 1e-8 * abs(q["reaction_all_xmax_x"])
    assert (q.get("interface_energy", 0.0) > 0) == math.isfinite(D)


@pytest.mark.slow
def test_cuboid_with_soft_surface_modes_converges():
    """0.5 x 0.4 x 0.4 at the paper's spacing (3024 points, ~100 s on one core): material A's
    C3 < 0 (nu = 0.1) leaves its free faces four negative tangent eigenvalues (-8e-9 .. -4.5e-10
    against 9.2e-5 at the top, measured), so the factors are indefinite (GMRES, not CG) and the
    quadratic constant r_(k+1) / r_k^2 rises from ~1e-3 (smaller cuboids, definite) to ~2e3:
    Newton still converges, in 4 iterations (measured 1, 1.4e-3, 3.9e-6, 1.6e-9, 2.8e-13)."""
    case = library.cuboid(interface="horizontal", load_case=2, size=(0.5, 0.4, 0.4))
    res = peridynamics.solve(case, h=0.035, progress=False)
    lin = res.diagnostics["linear_solver"]
    assert lin["krylov_method"] == "gmres" and lin["factorizations"] <= 3
    r = res.diagnostics["newton_history"][0]["residuals"]
    assert r[-1] <= 1e-11 and len(r) <= 5
    for a, b in zip(r[:-1], r[1:]):
        if b > 1e-11:
            assert b < 1e4 * a * a
    q = res.quantities
    assert abs(q["reaction_all_xmin_x"] + q["reaction_all_xmax_x"]) < 1e-8 * abs(q["reaction_all_xmax_x"])


def test_zones_set_the_springs_point_by_point_and_the_jump_profile():
    """InterfacePair zones (002 Fig 6 style): band points inside the zone use its law."""
    from interfaces import Rectangle

    case = library.bimaterial_square(parameter_set=3, load_case=3, interface="vertical", Dn=2e-4, Dt=1e-4)
    case.interfaces[0].zones = [(Rectangle(-1.0, -1.0, 2.0, 1.0), LinearInterface(2e-4, 5e-5))]
    disc, springs, _, system = _system(case, 0.1)
    y = disc.X[springs.node_a, 1]
    width = disc.vol[springs.node_a][springs.counted].sum() / 1.0      # band volume / interface length
    Stt = springs.S[:, 1, 1] / (disc.vol[springs.node_a] / width)
    in_zone = y <= 1e-9                                                  # the zone's closed rectangle holds y = 0
    assert np.allclose(Stt[in_zone], 5e-5) and np.allclose(Stt[~in_zone], 1e-4)
    assert np.allclose(springs.S[:, 0, 0] / springs.S[:, 1, 1], np.where(in_zone, 4.0, 2.0))
    res = peridynamics.solve(case, h=0.1)
    prof = res.profiles["interface_jump"]
    assert len(prof["s"]) == 11 and np.allclose(prof["x"], 0.0)     # the interface row of the vertex grid
    assert np.all(np.isfinite(prof["jump_t"])) and np.abs(prof["jump_t"]).max() > 0


def test_list_and_all_leave_cpd_out_where_it_cannot_run():
    import cases
    from cases.methods import resolve_methods, supported_methods

    case = cases.build("two_layer", Dt=3.0)
    assert supported_methods(case) == ["fem", "mpm", "cpd"] and peridynamics.supports(case) is None
    case.interfaces[0].law = BilinearNormalInterface(Dn_tension=1.0, Dt=1.0)
    assert "cpd" not in supported_methods(case) and "cpd" not in resolve_methods(case, "all")
    with pytest.raises(CaseError, match="BilinearNormalInterface"):
        resolve_methods(case, "fem,cpd")
