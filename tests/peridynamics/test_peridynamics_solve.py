"""CPD solves of the 003 cases: discretization, equilibrium, Table 3, overlap study, delta-convergence."""
import math

import numpy as np
import pytest

from cases import library
from interfaces import Body, BoundaryCondition, Case, IsotropicElastic, Rectangle, Result, TransverselyIsotropicElastic
from interfaces.errors import CaseError
import peridynamics
from peridynamics.discretization import discretize

H = 0.05


def _square(**kw):
    return library.bimaterial_square(**kw)


# ---------------------------------------------------------------- discretization
@pytest.mark.parametrize("interface", ["vertical", "horizontal", "diagonal"])
def test_overlap_band_and_boundary_layers(interface):
    case = _square(parameter_set=1, load_case=1, interface=interface)
    delta = 3.01 * H
    disc = discretize(case, H, delta, delta)
    X = disc.X
    # signed distance to the sharp interface line
    dist = {"vertical": X[:, 0], "horizontal": X[:, 1], "diagonal": (X[:, 1] - X[:, 0]) / math.sqrt(2)}[interface]
    shared = disc.member.all(axis=1)
    body = ~disc.layer
    # 003 Sec 3.1: shared = within l_ov / 2 of the interface (overlap band of width l_ov)
    assert np.array_equal(shared[body], np.abs(dist[body]) <= delta / 2 + 1e-9)
    # vertex grid: 21 x 21 body points; 3 layers (depth h..delta) on the left and right sides
    assert body.sum() == 21 * 21
    L = X[disc.layer]
    assert disc.layer.sum() == 2 * 3 * 21
    assert np.all((np.abs(L[:, 0]) > 0.5) & (np.abs(L[:, 0]) <= 0.5 + delta + 1e-12))
    # every point has a material; layer points inherit the sets of the boundary point they extend
    assert np.all(disc.member.any(axis=1))
    mid = disc.material_id
    assert set(np.unique(mid)) == {0, 1, 2}
    # prescribed: the two sides (outermost row + layers) with both components
    nodes = np.concatenate([p.nodes for p in disc.prescribed])
    assert np.all(np.isclose(np.abs(X[nodes, 0]), 0.5) | disc.layer[nodes])
    assert len(nodes) == 2 * 4 * 21


def test_hole_points_removed_and_band_only_where_both_materials_are():
    case = _square(parameter_set=4, load_case=1, interface="vertical", hole=True)
    delta = 3.01 * H
    disc = discretize(case, H, delta, delta)
    X = disc.X
    inside_hole = np.all(np.abs(X) < 0.2 - 1e-9, axis=1)
    assert not inside_hole.any()
    shared = disc.member.all(axis=1)
    assert np.all(np.abs(X[shared, 0]) <= delta / 2 + 1e-9)
    assert not np.any(shared & np.all(np.abs(X) < 0.2 - 1e-9, axis=1))
    # points on the hole edge exist (grid lines at +-0.2) and the band continues above/below the hole
    assert np.any(shared & (np.abs(X[:, 1]) > 0.2))


@pytest.mark.parametrize("overlap,rows", [(2.0, 11), (1.0, 5), (0.5, 3), (0.25, 1)])
def test_overlap_sizes_of_sec43(overlap, rows):
    """003 Sec 4.3, delta/h = 5.01: l_ov = delta/4 leaves a single interfacial layer."""
    case = _square(parameter_set=3, load_case=2, interface="horizontal")
    delta = 5.01 * H
    disc = discretize(case, H, delta, overlap * delta)
    shared = disc.member.all(axis=1) & ~disc.layer
    assert len(np.unique(np.round(disc.X[shared, 1], 9))) == rows


def test_too_small_overlap_is_rejected():
    case = _square(parameter_set=3, load_case=2, interface="horizontal")
    with pytest.raises(CaseError, match="overlap"):
        peridynamics.solve(case, h=H, overlap=0.25, grid="cell")


def test_bad_options_and_unsupported_input():
    case = _square(parameter_set=1, load_case=1)
    with pytest.raises(CaseError, match="unknown CPD option"):
        peridynamics.solve(case, h=H, horizon=3)
    with pytest.raises(CaseError, match="cpd.h"):
        peridynamics.solve(case, h=-1.0)
    with pytest.raises(CaseError, match="load_steps"):
        peridynamics.solve(case, h=H, load_steps=[0.5, 0.2, 1.0])
    with pytest.raises(CaseError, match="calibration"):
        peridynamics.solve(case, h=H, calibration="best")
    wood = case.replace(materials={"A": TransverselyIsotropicElastic(E_A=1e4, E_T=1e3, G_A=500, nu_A=0.2),
                                   "B": case.materials["B"]})
    with pytest.raises(CaseError, match="isotropic"):
        peridynamics.solve(wood, h=H)


# ---------------------------------------------------------------- small-strain physics
@pytest.mark.parametrize("interface,load_case", [("horizontal", 3), ("vertical", 1), ("diagonal", 2)])
def test_equilibrium_and_clapeyron(interface, load_case):
    """Reactions balance; W = 1/2 sum(f_int . u) over prescribed DOFs (linear regime, 0.1 %)."""
    case = _square(parameter_set=1, load_case=load_case, interface=interface)
    res = peridynamics.solve(case, h=H)
    q = res.quantities
    hist = res.diagnostics["newton_history"][0]["residuals"]
    assert hist[-1] <= 1e-11 and len(hist) <= 5
    scale = max(abs(v) for k, v in q.items() if k.startswith("reaction"))
    assert scale > 0
    for c in "xy":
        assert abs(q[f"reaction_all_xmin_{c}"] + q[f"reaction_all_xmax_{c}"]) < 1e-8 * scale
    U = res.fields["displacement"]
    # Clapeyron for the total energy (layers included): W = 1/2 f_int . u on the prescribed points
    disc = discretize(case, H, 3.01 * H, 3.01 * H)
    system, _ = peridynamics.solver.build_system(case, disc, "continuum", None)
    ev = system.evaluate(U, False)
    fixed = np.concatenate([p.nodes for p in disc.prescribed])
    work = 0.5 * float(np.sum(ev.residual[fixed] * U[fixed]))
    assert q["strain_energy_with_layers"] == pytest.approx(work, rel=3e-3)
    assert 0 < q["strain_energy"] < q["strain_energy_with_layers"]
    # profiles along the case lines, inside the square
    prof = res.profiles["vertical"]
    assert np.allclose(prof["x"], 0.1) and prof["y"].min() >= -0.5 and prof["y"].max() <= 0.5
    assert len(prof["s"]) > 30 and np.all(np.isfinite(prof["ux"]))
    # JSON round trip of the Result
    back = Result.from_json(res.to_json())
    assert back.quantities["strain_energy"] == pytest.approx(q["strain_energy"])


def test_homogeneous_body_has_no_interface_effect():
    """Same material on both sides: the overlap coupling reproduces the one-body solution
    away from the band and deviates only near it (003 Fig 9 bottom, without the hole)."""
    case = _square(parameter_set=4, load_case=1, interface="vertical")
    one = case.replace(bodies=[Body("A", Rectangle(-0.5, -0.5, 1.0, 1.0), "A")], interfaces=[])
    r2 = peridynamics.solve(case, h=H)
    r1 = peridynamics.solve(one, h=H)
    X2, X1 = r2.fields["position"], r1.fields["position"]
    o2, o1 = np.lexsort(X2.T), np.lexsort(X1.T)
    assert np.allclose(X2[o2], X1[o1])
    dU = np.linalg.norm(r2.fields["displacement"][o2] - r1.fields["displacement"][o1], axis=1)
    scale = np.abs(r1.fields["displacement"]).max()
    # measured max |du| / max |u|: 8.5 % in the band (|x| <= l_ov / 2), 4.7 % from there to
    # delta, 2.4 % to 2 delta, 1.4 % beyond (0 in the prescribed layers)
    x = np.abs(X2[o2, 0])
    band, far = x <= 1.505 * H, (x > 6.02 * H) & (x < 0.5 - 1e-9)
    assert 0.04 * scale < dU[band].max() < 0.15 * scale    # the model "feels" the interface
    assert dU[far].max() < 0.03 * scale
    assert dU[far].max() < 0.3 * dU[band].max()


# ---------------------------------------------------------------- finite deformation (003 Table 3)
def _table3(h):
    case = _square(parameter_set=2, load_case=1, interface="vertical", strain_scale=1000.0)
    res = peridynamics.solve(case, h=h, load_steps=[0.01, 0.25, 0.5, 0.75, 1.0])
    hist = res.diagnostics["newton_history"]
    assert [s["load"] for s in hist] == [0.01, 0.25, 0.5, 0.75, 1.0]
    for k, step in enumerate(hist):
        r = step["residuals"]
        # normalised by the state right after the boundary increment; later steps start
        # from the secant predictor, which lowers the first residual
        assert (r[0] == 1.0 if k == 0 else r[0] < 1.0) and r[-1] <= 1e-11
        # 003 Table 3: 4 iterations per step; measured at h = 0.05: 3, 3, 3, 4, 5
        assert len(r) - 1 <= 5
        # quadratic rate in the asymptotic range, for the iterations that end above tol
        # (the last one solves its linear system only to the forcing floor 0.1 tol / r,
        # peridynamics.newton.forcing: enough to land below tol, not to show the rate)
        for a, b in zip(r[:-1], r[1:]):
            if a < 1e-2 and b > 1e-11:
                assert b < 10.0 * a * a
    # the converged state is in equilibrium: the reactions of the two gripped sides balance
    q = res.quantities
    for c in "xy":
        assert abs(q[f"reaction_all_xmin_{c}"] + q[f"reaction_all_xmax_{c}"]) < 1e-9 * abs(q["reaction_all_xmax_x"])
    U = res.fields["displacement"]
    X = res.fields["position"]
    right = np.isclose(X[:, 0], 0.5)
    assert np.allclose(U[right, 0], 0.5)                   # 100 % stretch: u = X on the sides
    # lateral contraction of the free edges; material B (nu_2D = 0.7) contracts more than A
    top = np.isclose(X[:, 1], 0.5) & ~res.fields["boundary_layer"].astype(bool)
    uyA = U[top & (X[:, 0] < -0.2) & (X[:, 0] > -0.4), 1].mean()
    uyB = U[top & (X[:, 0] > 0.2) & (X[:, 0] < 0.4), 1].mean()
    assert uyB < uyA < 0
    return res


def test_finite_stretch_table3_reduced():
    _table3(H)


@pytest.mark.slow
def test_finite_stretch_table3_full_resolution():
    res = _table3(0.01)
    assert res.diagnostics["n_points"] > 101 * 101


# ---------------------------------------------------------------- overlap study (003 Sec 4.3)
def _overlap_study(h, dfac):
    case = _square(parameter_set=3, load_case=2, interface="horizontal")
    prof = {}
    for ov in (2.0, 1.0, 0.5, 0.25):
        r = peridynamics.solve(case, h=h, delta_factor=dfac, overlap=ov)
        assert r.diagnostics["newton_history"][-1]["residuals"][-1] <= 1e-11
        prof[ov] = r.profiles["vertical"]
    delta = dfac * h
    y = prof[1.0]["y"]
    near = np.abs(y) <= 1.5 * delta
    d_small = np.abs(prof[0.25]["ux"] - prof[2.0]["ux"])
    # 003 Sec 4.3: the overlap size changes the deformation mainly near the interface
    assert d_small[near].max() > 2.0 * d_small[~near & (np.abs(y) > 3 * delta)].max()
    return prof


def test_overlap_study_reduced():
    """Reduced: h = 0.025, delta/h = 3.01 (delta/2 and delta/4 both leave one layer here)."""
    _overlap_study(0.025, 3.01)


@pytest.mark.slow
def test_overlap_study_full_resolution():
    """003 Sec 4.3: h = 0.01, delta = 0.0501 (delta/h = 5.01)."""
    _overlap_study(0.01, 5.01)


# ---------------------------------------------------------------- delta-convergence (003 Sec 4.2)
def _fem_profile(case, line, element_size):
    """The FEM reference profile: a broken FEM fails this test, it never skips it."""
    import fem

    return fem.solve(case, element_size=element_size).profiles[line]


def _delta_convergence(case, line, comp, hs, element_size):
    ref = _fem_profile(case, line, element_size)
    ax = "x" if line == "horizontal" else "y"
    errors = []
    for h in hs:
        p = peridynamics.solve(case, h=h).profiles[line]
        uf = np.interp(p[ax], ref[ax], ref[comp])
        errors.append(float(np.sqrt(np.mean((p[comp] - uf) ** 2) / np.mean(uf ** 2))))
    return errors


def test_delta_convergence_to_plane_strain_fem_reduced():
    """delta/h = 3.01 fixed, delta -> 0: set 3, vertical interface, load case I (003 Fig 9 centre)."""
    case = _square(parameter_set=3, load_case=1, interface="vertical")
    e = _delta_convergence(case, "horizontal", "ux", [0.1, 0.05, 0.025], 0.025)
    assert e[0] > e[1] > e[2]
    assert e[2] / e[0] < 0.35                  # about first order in delta
    assert e[2] < 0.06


@pytest.mark.parametrize("pset,load_case,interface,line,hole,ratio,last", [
    # measured errors 32.7 / 19.3 / 11.7 % (ratios 0.59, 0.61): the stiff inclusion converges slowest
    (1, 3, "horizontal", "vertical", False, (0.7, 0.7), 0.15),    # 003 Fig 9 top
    # measured 3.08 / 1.64 / 1.24 % (ratios 0.53, 0.75): the hole edge's own horizon error
    (4, 1, "vertical", "horizontal", True, (0.65, 0.85), 0.016),  # 003 Fig 9 bottom (hole)
], ids=["set1", "hole"])
def test_delta_convergence_reduced_set1_and_hole(pset, load_case, interface, line, hole, ratio, last):
    """The reduced grid of the set-3 test (delta/h = 3.01, h = 0.1, 0.05, 0.025; FEM at
    0.025, which is 1e-5 from FEM at 0.01 on these errors) for the other two 003 Fig 9 cases."""
    case = _square(parameter_set=pset, load_case=load_case, interface=interface, hole=hole)
    e = _delta_convergence(case, line, "ux", [0.1, 0.05, 0.025], 0.025)
    assert e[1] < ratio[0] * e[0] and e[2] < ratio[1] * e[1]
    assert e[2] < last


@pytest.mark.slow
@pytest.mark.parametrize("pset,load_case,interface,line,hole", [
    (1, 3, "horizontal", "vertical", False),   # 003 Fig 9 top
    (3, 1, "vertical", "horizontal", False),   # 003 Fig 9 centre
    (4, 1, "vertical", "horizontal", True),    # 003 Fig 9 bottom (hole)
])
def test_delta_convergence_full(pset, load_case, interface, line, hole):
    case = _square(parameter_set=pset, load_case=load_case, interface=interface, hole=hole)
    e = _delta_convergence(case, line, "ux", [0.05, 0.025, 0.0125], 0.01)
    assert e[0] > e[1] > e[2]
    assert e[2] < 0.6 * e[0]


# ---------------------------------------------------------------- 3D (003 Sec 4.5)
@pytest.mark.parametrize("interface", ["vertical", "horizontal"])
def test_cuboid_3d_converges_quadratically(interface):
    case = library.cuboid(interface=interface, load_case=1, size=(0.4, 0.2, 0.2))
    res = peridynamics.solve(case, h=0.05, delta_factor=2.01)
    r = res.diagnostics["newton_history"][0]["residuals"]
    assert r[-1] <= 1e-11 and len(r) <= 5
    assert res.diagnostics["tuples"]["quadruples"] > 0
    q = res.quantities
    assert abs(q["reaction_all_xmin_x"] + q["reaction_all_xmax_x"]) < 1e-8 * abs(q["reaction_all_xmax_x"])
    assert q["reaction_all_xmax_x"] > 0
    assert res.fields["position"].shape[1] == 3 and np.all(np.isfinite(res.fields["displacement"]))


def test_non_convergence_raises_solver_error_with_advice():
    from interfaces.errors import SolverError
    case = _square(parameter_set=2, load_case=1, interface="vertical", strain_scale=1000.0)
    with pytest.raises(SolverError, match="load_steps"):
        peridynamics.solve(case, h=0.1, max_iter=1)


@pytest.mark.slow
def test_cuboid_3d_paper_horizon():
    """003 Sec 4.5 horizon delta = 3.01 h (one- and three-neighbour interactions) on a small cuboid."""
    case = library.cuboid(interface="horizontal", load_case=2, size=(0.3, 0.2, 0.2))
    res = peridynamics.solve(case, h=0.05, delta_factor=3.01)
    r = res.diagnostics["newton_history"][0]["residuals"]
    assert r[-1] <= 1e-11 and len(r) <= 5
    for a, b in zip(r[:-1], r[1:]):
        if a < 1e-3 and b > 1e-13:
            assert b < 1e3 * a * a


def test_large_runs_warn_before_solving(monkeypatch):
    monkeypatch.setattr(peridynamics.solver, "TUPLE_WARNING", 0.0)
    case = _square(parameter_set=3, load_case=1)
    with pytest.warns(RuntimeWarning, match="triples"):
        res = peridynamics.solve(case, h=0.1)
    assert not any("triples" in w for w in res.diagnostics["warnings"])   # warned once, before the solve


def test_overlap_band_energy_is_flagged_beside_fem():
    """The overlap band holds both materials' energy (003 Sec 3): the Result says so, so a
    table that sets CPD's strain energy beside FEM's does not mislead."""
    res = peridynamics.solve(_square(parameter_set=4, load_case=1), h=0.1)
    assert any("overlap band" in w for w in res.diagnostics["warnings"])
