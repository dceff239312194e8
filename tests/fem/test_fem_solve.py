"""fem.solve against closed forms (002 Eq 40-42, 46-47, patch tests), limits (D -> inf,
rotation) and internal consistency (Eq 43 vs Eq 45, energy accounting)."""
import math

import numpy as np
import pytest

import fem
from cases.library import dcb, dls, wood_strand
from interfaces.analytic.dcb import dcb_kb_from_stiffness, dcb_stiffness
from interfaces.analytic.dls import dls_identical_stiffness
from interfaces.case import Body, BoundaryCondition, Case, InterfacePair
from interfaces.errors import CaseError, SolverError
from interfaces.geometry import Circle, Rectangle
from interfaces.laws import LinearInterface, StickContact
from interfaces.materials import IsotropicElastic

T, L_BOND, L_ARM, W = 0.6, 25.0, 5.0, 10.0          # 002 Sec 3.1 specimen
E_YY, G_XY = 10000.0, 500.0
DT_VALUES = [1, 2, 5, 10, 20, 50, 100, 1000, math.inf]


def shear_lag(Dt):
    """002 Eq 40-42 (identical strips) from interfaces.analytic."""
    return dls_identical_stiffness(T, E_YY, G_XY, L_BOND, W, L_ARM, Dt)


# ---------------------------------------------------------------- DLS (002 Sec 3.1)
@pytest.mark.parametrize("Dt", DT_VALUES)
def test_dls_matches_shear_lag_and_both_stiffness_methods_agree(Dt):
    r = fem.solve(dls(Dt=Dt), h=0.3, fields=False)
    q = r.quantities
    # measured deviation from the printed shear lag (strips rigid in shear) at h = 0.3:
    # -0.05 % (Dt = 1) .. -0.22 % (20), +0.22 % (inf); 0.5 % is about twice the largest
    assert q["stiffness"] == pytest.approx(shear_lag(Dt), rel=5e-3)
    assert q["stiffness_energy"] == pytest.approx(q["stiffness"], rel=1e-6)
    # P = 2 x traction x t x W (002 Sec 3.1, load = 1 MPa) and Clapeyron: U = W_ext / 2
    assert q["load"] == pytest.approx(2 * 1.0 * T * W, rel=1e-10)
    assert q["total_energy"] == pytest.approx(q["external_work"], rel=1e-9)
    prof = r.profiles["interface_jump"]
    assert np.abs(prof["jump_n"]).max() < 1e-12 * np.abs(prof["jump_t"]).max() + 1e-300  # Dn = inf: exact
    if math.isinf(Dt):
        assert q["interface_energy"] == 0.0 and np.abs(prof["jump_t"]).max() < 1e-15
    else:
        # interface energy = sum over both bond lines of int 1/2 Dt [u_t]^2 W ds (002 Eq 4)
        e = sum(0.5 * Dt * np.sum(p["weight"] * p["jump_t"] ** 2) * W
                for k, p in r.profiles.items() if k.startswith("interface_jump["))
        assert q["interface_energy"] == pytest.approx(e, rel=1e-9)


def test_dls_mesh_convergence_three_refinements():
    """Stiffness converges monotonically (bond-end singularities limit the rate to ~1.2-1.4)."""
    for Dt in (10.0, math.inf):
        k = [fem.solve(dls(Dt=Dt), h=h, fields=False).quantities["stiffness"] for h in (0.3, 0.15, 0.075)]
        d1, d2 = k[1] - k[0], k[2] - k[1]
        assert np.sign(d1) == np.sign(d2) and abs(d1) / abs(d2) > 2.0     # observed order > 1
        p = math.log2(d1 / d2)
        k_inf = k[2] + d2 / (2**p - 1)                                      # Richardson
        assert k_inf == pytest.approx(shear_lag(Dt), rel=3e-3)


@pytest.mark.parametrize("kw", [dict(Dt=1e12), dict(Dt=10.0, Dn=1e12), dict(Dt=10.0, Dn=1e12, angle=30.0),
                                dict(Dt=1e12, Dn=1e12, angle=30.0)])
def test_huge_finite_D_converges_to_exact_perfect_interface(kw):
    big = fem.solve(dls(**kw), h=0.3, fields=False)
    perfect = {k: (math.inf if v == 1e12 else v) for k, v in kw.items()}
    ref = fem.solve(dls(**perfect), h=0.3, fields=False)
    assert big.quantities["stiffness"] == pytest.approx(ref.quantities["stiffness"], rel=1e-6)
    assert big.quantities["stiffness_energy"] == pytest.approx(ref.quantities["stiffness"], rel=1e-6)
    assert big.diagnostics["backward_error"] < 1e-12                   # well conditioned solve


def test_rotated_specimen_gives_the_same_stiffness():
    """000 Fig 9: rotating the whole DLS (and its fibres, load and measurement direction)."""
    k0 = fem.solve(dls(Dt=10.0), h=0.3, fields=False).quantities
    for angle in (30.0, 90.0):
        k = fem.solve(dls(Dt=10.0, angle=angle, shift_x=1.0), h=0.3, fields=False).quantities
        assert k["stiffness"] == pytest.approx(k0["stiffness"], rel=1e-9)
        assert k["stiffness_energy"] == pytest.approx(k0["stiffness_energy"], rel=1e-9)


def test_two_zone_normal_interface_lies_between_uniform_cases():
    """002 Fig 6: Dn = 1 below mid-bond, perfect above, gives a stiffness between Dn = 1 and
    Dn = inf everywhere; the perfect zone has no normal jump, the soft zone interpenetrates."""
    Dt = 100.0
    k = {}
    for name, kw in {"soft": dict(Dn=1.0), "zone": dict(Dn=math.inf, zone_y=17.5, zone_Dn=1.0),
                     "perfect": dict(Dn=math.inf)}.items():
        k[name] = fem.solve(dls(Dt=Dt, **kw), h=0.3, fields=False)
    ks = {n: r.quantities["stiffness"] for n, r in k.items()}
    assert ks["soft"] < ks["zone"] < ks["perfect"]
    assert ks["perfect"] - ks["soft"] > 1e-3 * ks["perfect"]
    prof = k["zone"].profiles["interface_jump"]
    top = prof["y"] > 17.5 + 0.3
    assert np.abs(prof["jump_n"][top]).max() < 1e-12 * np.abs(prof["jump_t"]).max()
    assert np.abs(prof["jump_n"][~top]).max() > 1e-3 * np.abs(prof["jump_t"]).max()
    assert k["zone"].quantities["stiffness_energy"] == pytest.approx(ks["zone"], rel=1e-6)


def test_bilinear_normal_law_by_active_set_iteration():
    """002 Fig 6-7 'inf/1': perfect in compression, Dn = 1 in tension. The active-set iteration
    settles with no interpenetration, tension-branch elements open, and the stiffness lies
    between the linear Dn = 1 and Dn = inf results (MPM reference of 002 Sec 3.1)."""
    Dt = 100.0
    r = fem.solve(dls(Dt=Dt, Dn=1.0, Dn_compression=math.inf), h=0.3, fields=False)
    k_soft = fem.solve(dls(Dt=Dt, Dn=1.0), h=0.3, fields=False).quantities["stiffness"]
    k_perfect = fem.solve(dls(Dt=Dt), h=0.3, fields=False).quantities["stiffness"]
    q = r.quantities
    assert k_soft < q["stiffness"] < k_perfect
    assert q["stiffness_energy"] == pytest.approx(q["stiffness"], rel=1e-6)
    hist = r.diagnostics["history"]
    assert hist[-1]["elements_switched"] == 0 and 0 < hist[-1]["compressed_elements"]
    for name, prof in r.profiles.items():
        if name.startswith("interface_jump["):
            # element means (3 Gauss points per element, contiguous in s): the active-set conditions
            w = prof["weight"].reshape(-1, 3)
            jn = (w * prof["jump_n"].reshape(-1, 3)).sum(1) / w.sum(1)
            tn = (w * prof["traction_n"].reshape(-1, 3)).sum(1) / w.sum(1)
            compressed = np.isinf(prof["Dn"].reshape(-1, 3)[:, 0])
            assert compressed.any() and (~compressed).any()
            assert np.all(tn[compressed] < 0)                           # contact pushes
            assert np.all(jn[~compressed] > -1e-12 * np.abs(jn).max())  # no interpenetration
            assert jn.max() > 1e-4                                      # the tension zone opens


def test_linear_elements_agree_with_shear_lag():
    r = fem.solve(dls(Dt=10.0), h=0.1, order=1, fields=False)
    assert r.quantities["stiffness"] == pytest.approx(shear_lag(10.0), rel=1e-2)
    assert r.quantities["stiffness_energy"] == pytest.approx(r.quantities["stiffness"], rel=1e-6)


# ---------------------------------------------------------------- patch tests
def _bar(Dn, Dt, stacked: bool, analysis="plane_stress"):
    """Two blocks in series (stacked along y, interface y = 2) or side by side (interface x = 1),
    bottom on rollers, top pulled by a prescribed displacement 0.01 mm."""
    m1 = IsotropicElastic(E=1000.0, nu=0.1)
    m2 = IsotropicElastic(E=3000.0, nu=0.3) if stacked else IsotropicElastic(E=3000.0, nu=0.1)
    if stacked:
        bodies = [Body("A", Rectangle(0, 0, 1.0, 2.0), "m1"), Body("B", Rectangle(0, 2.0, 1.0, 3.0), "m2")]
        bcs = [BoundaryCondition("fixed", "A", "ymin", ("y",), (0.0,)),
               BoundaryCondition("displacement", "B", "ymax", ("y",), (0.01,))]
        meas = {"load": [["B", "ymax"]], "support": [["A", "ymin"]], "direction": "y"}
    else:
        bodies = [Body("A", Rectangle(0, 0, 1.0, 4.0), "m1"), Body("B", Rectangle(1.0, 0, 2.0, 4.0), "m2")]
        bcs = [BoundaryCondition("fixed", "*", "ymin", ("y",), (0.0,)),
               BoundaryCondition("displacement", "*", "ymax", ("y",), (0.01,))]
        meas = {"load": [["A", "ymax"], ["B", "ymax"]], "support": [["A", "ymin"], ["B", "ymin"]], "direction": "y"}
    return Case(name="bar", analysis=analysis, thickness=2.0, materials={"m1": m1, "m2": m2}, bodies=bodies,
                interfaces=[InterfacePair("A", "B", LinearInterface(Dn, Dt))], boundary_conditions=bcs,
                measurements={"stiffness": meas})


@pytest.mark.parametrize("Dn,Dt", [(math.inf, math.inf), (50.0, math.inf), (50.0, 3.0), (1e12, 1e12)])
@pytest.mark.parametrize("order", [1, 2])
def test_patch_series_bar_uniform_stress_with_interface_opening(Dn, Dt, order):
    """Uniform sigma across a normal interface (nu/E equal: lateral strains match): the jump is
    sigma/Dn and k = W t / (L1/E1 + L2/E2 + 1/Dn) exactly (002 Eq 1)."""
    r = fem.solve(_bar(Dn, Dt, stacked=True), h=0.5, order=order)
    compliance = 2.0 / 1000.0 + 3.0 / 3000.0 + (0.0 if math.isinf(Dn) else 1.0 / Dn)
    k_exact = 1.0 * 2.0 / compliance
    assert r.quantities["stiffness"] == pytest.approx(k_exact, rel=1e-10)
    assert r.quantities["stiffness_energy"] == pytest.approx(k_exact, rel=1e-10)
    sigma = k_exact * 0.01 / 2.0
    np.testing.assert_allclose(r.fields["stress"][:, 1], sigma, rtol=1e-9)
    np.testing.assert_allclose(r.fields["stress"][:, [0, 2]], 0.0, atol=1e-9 * sigma)
    prof = r.profiles["interface_jump"]
    # even at Dn = 1e12 the tiny opening sigma/Dn = 3.3e-12 mm comes out to 9 digits (jump unknowns)
    np.testing.assert_allclose(prof["jump_n"], 0.0 if math.isinf(Dn) else sigma / Dn, rtol=1e-9, atol=1e-300)
    np.testing.assert_allclose(prof["jump_t"], 0.0, atol=1e-13)


@pytest.mark.parametrize("Dn,Dt", [(math.inf, math.inf), (5.0, 0.5)])
def test_patch_parallel_bimaterial_uniform_strain(Dn, Dt):
    """Layers side by side under a uniform axial strain: sigma_i = E_i eps, no interface traction,
    k = (E1 w1 + E2 w2) t / H whatever the interface (perfect or imperfect)."""
    r = fem.solve(_bar(Dn, Dt, stacked=False), h=0.5)
    k_exact = (1000.0 * 1.0 + 3000.0 * 2.0) * 2.0 / 4.0
    assert r.quantities["stiffness"] == pytest.approx(k_exact, rel=1e-10)
    assert r.quantities["interface_energy"] == pytest.approx(0.0, abs=1e-12 * r.quantities["strain_energy"])
    syy = r.fields["stress"][:, 1]
    mat = r.fields["material"]
    np.testing.assert_allclose(syy[mat == 0], 1000.0 * 0.01 / 4.0, rtol=1e-9)
    np.testing.assert_allclose(syy[mat == 1], 3000.0 * 0.01 / 4.0, rtol=1e-9)
    assert r.diagnostics["pinned_dofs"]          # x-translation was free and is pinned


def test_axisymmetric_core_and_sleeve_under_axial_strain():
    """Rod (E1) in a sleeve (E2), same nu, uniform axial strain: u_r = -nu eps r in both, no
    interface traction; P = pi eps (E1 R1^2 + E2 (R2^2 - R1^2)) over the whole ring."""
    R1, R2, H, d = 1.0, 1.5, 3.0, 0.003
    mats = {"core": IsotropicElastic(E=2000.0, nu=0.25), "sleeve": IsotropicElastic(E=7000.0, nu=0.25)}
    case = Case(name="rod", analysis="axisymmetric", thickness=1.0, materials=mats,
                bodies=[Body("core", Rectangle(0, 0, R1, H), "core"), Body("sleeve", Rectangle(R1, 0, R2 - R1, H), "sleeve")],
                interfaces=[InterfacePair("core", "sleeve", LinearInterface(20.0, 4.0))],
                boundary_conditions=[BoundaryCondition("fixed", "*", "ymin", ("y",), (0.0,)),
                                     BoundaryCondition("displacement", "*", "ymax", ("y",), (d,))],
                measurements={"stiffness": {"load": [["core", "ymax"], ["sleeve", "ymax"]],
                                            "support": [["core", "ymin"], ["sleeve", "ymin"]], "direction": "y"}})
    r = fem.solve(case, h=0.25)
    eps = d / H
    P = math.pi * eps * (2000.0 * R1**2 + 7000.0 * (R2**2 - R1**2))
    assert r.quantities["load"] == pytest.approx(P, rel=1e-9)
    assert r.quantities["stiffness"] == pytest.approx(P / d, rel=1e-9)
    assert r.quantities["strain_energy"] == pytest.approx(0.5 * P * d, rel=1e-9)
    x, u = r.fields["position"], r.fields["displacement"]
    np.testing.assert_allclose(u[:, 0], -0.25 * eps * x[:, 0], atol=1e-12)


# ---------------------------------------------------------------- DCB (002 Sec 3.2)
def _dcb_run(Dn, h, length=50.0):
    return fem.solve(dcb(Dn=Dn, length=length), h=h, fields=False).quantities


def _independent_kb(references, size):
    """kb (002 Eq 46-47 inverted) of the cracked-strip model of tests/references, which
    shares nothing with fem/ but the wood constants."""
    w = wood_strand(fiber=(1.0, 0.0))
    k = references.dcb_cracked_strip.dcb_perfect_stiffness(w.E_A, w.E_T, w.G_A, w.nu_A, size=size)
    return k, dcb_kb_from_stiffness(k, 25.0, 0.6, 10.0, 10000.0)


def test_dcb_matches_beam_on_elastic_foundation(references):
    """Perfect interface (interface elements with Dn = inf) against an independent FEM of
    the same cracked strip on the same mesh; then FEM vs Eq 46-47 with that kb.

    The printed kb = 7808 MPa (002, 250 eight-node elements) is not asserted: kb is not
    mesh-converged. The perfect-bond DCB has a crack-tip singularity, the stiffness
    converges at first order and kb (~ Delta^-4, Delta/a = 0.04) amplifies that 50-fold:
    kb = 7971 (h = 0.2), 7696 (0.1), 7573 (0.05) in both models, so 7808 is one mesh's value
    (between h = 0.1 and 0.2), not a reference. Measured: fem vs the independent model
    6e-9 in stiffness at h = 0.2 (3e-9 at 0.1); Eq 46-47 vs FEM -0.54 % (Dn = 0.1),
    -0.78 % (1), -1.36 % (10), -1.85 % (100), -0.43 % (1e4): the beam model's error (mesh
    changes it by < 1e-4), largest where Dn ~ kb / (2 W)."""
    h = 0.2
    perfect = _dcb_run(math.inf, h)
    assert perfect["stiffness_energy"] == pytest.approx(perfect["stiffness"], rel=1e-6)
    k_ref, kb = _independent_kb(references, h)
    assert perfect["stiffness"] == pytest.approx(k_ref, rel=1e-7)
    assert dcb_kb_from_stiffness(perfect["stiffness"], 25.0, 0.6, 10.0, 10000.0) == pytest.approx(kb, rel=5e-6)
    for Dn, tol in ((0.1, 1e-2), (1.0, 1.2e-2), (10.0, 2e-2), (100.0, 2.5e-2), (1e4, 1e-2)):
        q = _dcb_run(Dn, h)
        ref = dcb_stiffness(25.0, 0.6, 10.0, 10000.0, Dn, kb)
        assert q["stiffness"] == pytest.approx(ref, rel=tol), Dn
        assert q["stiffness"] < ref                       # the foundation model is stiffer here
        assert q["stiffness_energy"] == pytest.approx(q["stiffness"], rel=1e-6)


def test_dcb_soft_interface_needs_a_long_bond():
    """At Dn = 0.01 the foundation length Delta = (E h^3 / (6 Dn))^(1/4) = 13.8 mm is not small
    against the 25 mm bond of the 002 specimen, so the semi-infinite model of Appendix B does
    not apply there (FEM 12 % softer); with a 75 mm bond FEM and Eq 46-47 agree again."""
    kb = dcb_kb_from_stiffness(_dcb_run(math.inf, 0.2)["stiffness"], 25.0, 0.6, 10.0, 10000.0)
    ref = dcb_stiffness(25.0, 0.6, 10.0, 10000.0, 0.01, kb)
    assert _dcb_run(0.01, 0.2, length=100.0)["stiffness"] == pytest.approx(ref, rel=1e-2)
    assert _dcb_run(0.01, 0.2)["stiffness"] < 0.92 * ref


def test_a_free_dcb_is_reported_at_rest_not_on_its_pins():
    """The DCB is free and self-equilibrated. FEM pins three DOFs of the lower arm's load
    side; reported on those pins, the upper arm carried the whole opening (0.066 mm at its
    load point, 0 at the lower one) and the bonded half turned rigidly (upper arm 0.007
    mm at x = 40), while MPM, which comes to rest from rest, opened each arm by half.
    Reported as a body at rest (no mean translation or rotation in the mass metric), the
    symmetric specimen opens by half on each arm and the bonded half stays put; the
    stiffness does not change."""
    r = fem.solve(dcb(Dn=1.0), h=0.3)
    q = r.quantities
    assert r.diagnostics["pinned_dofs"]
    assert q["load_displacement"] == pytest.approx(-q["support_displacement"], rel=5e-8)
    arm = r.profiles["upper_arm"]
    at_40 = np.interp(40.0, arm["x"], arm["uy"])
    assert abs(at_40) < 1e-3 * q["load_displacement"]
    assert q["stiffness"] == pytest.approx(q["stiffness_energy"], rel=1e-7)


# ---------------------------------------------------------------- outputs and errors
def test_result_outputs_profiles_fields_and_vtk(tmp_path):
    r = fem.solve(dls(Dt=20.0), h=0.3)
    assert set(r.timings) >= {"assembly", "solve"} and r.diagnostics["dofs"] > 0
    axis = r.profiles["axis"]
    assert axis["s"][0] == 0.0 and np.isfinite(axis["uy"][axis["y"] <= 30.0]).all()
    assert np.isnan(axis["uy"][axis["y"] > 30.01]).all()           # past the central strip: no body
    assert axis["uy"][0] == pytest.approx(0.0, abs=1e-15)           # gripped end
    assert np.all(np.diff(axis["uy"][axis["y"] <= 30.0]) > 0)
    pos, disp = r.fields["position"], r.fields["displacement"]
    assert pos.shape == disp.shape and r.fields["stress"].shape == (len(pos), 3)
    assert r.cells["connectivity"].max() < len(pos)
    out = r.to_vtk(tmp_path / "dls.vtu")
    assert out.exists()
    assert "stiffness" in r.to_json()


def test_bad_input_is_rejected_with_clear_messages():
    case = dls(Dt=10.0)
    with pytest.raises(CaseError, match="unknown"):
        fem.solve(case, h=0.3, preconditioner="ilu")
    with pytest.raises(CaseError, match="solver must be one of auto, pardiso, superlu"):
        fem.solve(case, h=0.3, solver="cg")
    with pytest.raises(CaseError, match="order"):
        fem.solve(case, h=0.3, order=3)
    with pytest.raises(CaseError, match="element_size"):
        fem.solve(case, h=-1.0)
    contact = dls(Dt=10.0)
    contact.interfaces[0].law = StickContact()
    with pytest.raises(CaseError, match="mpm"):
        fem.solve(contact, h=0.3)
    disc = Case(name="c", analysis="plane_strain", materials={"m": IsotropicElastic(E=1.0, nu=0.3)},
                bodies=[Body("c", Circle(0, 0, 1.0), "m")])
    with pytest.raises(CaseError, match="rectangles and polygons"):
        fem.solve(disc, h=0.3, mesher="structured")      # curved shapes are meshed by gmsh
    with pytest.raises(CaseError, match="mesher must be one of auto, structured, gmsh"):
        fem.solve(disc, h=0.3, mesher="delaunay")


@pytest.mark.parametrize("interface", ["vertical", "horizontal", "diagonal"])
@pytest.mark.parametrize("load_case", [1, 2, 3])
def test_uniform_deformation_is_exact_on_quads_and_triangles(interface, load_case):
    """003 bimaterial square with one material and u = H X on all four sides (body '*'):
    the exact field u = H X is reproduced (quads; triangles for the 45-degree interface),
    U = 1/2 eps : C : eps x area, and the perfect interface carries no jump."""
    from cases.library import bimaterial_square
    base = bimaterial_square(interface=interface, load_case=load_case)
    m = IsotropicElastic(E=1000.0, nu=0.3)
    H = np.array(base.boundary_conditions[0].value).reshape(2, 2)
    bcs = [BoundaryCondition("deformation_gradient", "*", side, ("x", "y"), tuple(H.ravel()))
           for side in ("xmin", "xmax", "ymin", "ymax")]
    case = base.replace(materials={"A": m, "B": m}, boundary_conditions=bcs)
    r = fem.solve(case, h=0.125)
    assert r.cells["type"] == ("triangle" if interface == "diagonal" else "quad")
    eps = 0.5 * (H + H.T)
    ev = np.array([eps[0, 0], eps[1, 1], 2 * eps[0, 1]])
    assert r.quantities["strain_energy"] == pytest.approx(0.5 * ev @ m.stiffness("plane_strain") @ ev, rel=1e-10)
    x, u = r.fields["position"], r.fields["displacement"]
    np.testing.assert_allclose(u, x @ H.T, atol=1e-13)
    assert np.abs(r.profiles["interface_jump"]["jump_n"]).max() < 1e-14


# ---------------------------------------------------------------- full-resolution validations
@pytest.mark.slow
def test_full_resolution_dls_and_dcb_validation(references):
    """The cases' own FEM resolution (h = 0.1 mm): DLS over the Dt range of 002 Fig 5 and DCB
    over Dn of 002 Fig 9, both stiffness methods."""
    for Dt in DT_VALUES:
        q = fem.solve(dls(Dt=Dt), fields=False).quantities
        assert q["stiffness"] == pytest.approx(shear_lag(Dt), rel=5e-3)
        assert q["stiffness_energy"] == pytest.approx(q["stiffness"], rel=1e-8)
    k_ref, kb = _independent_kb(references, 0.1)                  # 7696 MPa at the cases' mesh
    assert fem.solve(dcb(), fields=False).quantities["stiffness"] == pytest.approx(k_ref, rel=1e-7)
    # kb is mesh-dependent (crack-tip singularity): the stiffness converges at first order
    # (measured order 1.11 from h = 0.2, 0.1, 0.05; 1.01 from 0.1, 0.05, 0.025, where kb = 7513);
    # Richardson-extrapolated kb = 7454 MPa
    k_coarse, k_fine = _independent_kb(references, 0.2)[0], _independent_kb(references, 0.05)[0]
    order = math.log2((k_coarse - k_ref) / (k_ref - k_fine))
    assert 0.9 < order < 1.4
    for Dn in (0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0, 1e3, 1e4, 1e12):
        q = fem.solve(dcb(Dn=Dn), fields=False).quantities
        assert q["stiffness"] == pytest.approx(dcb_stiffness(25.0, 0.6, 10.0, 10000.0, Dn, kb), rel=3e-2)
        assert q["stiffness_energy"] == pytest.approx(q["stiffness"], rel=1e-6)


def test_dls_interface_slip_profile_matches_shear_lag():
    """The FEM slip along the first bond line (u_central - u_outer, 002 Fig 7 convention of the
    shared profiles) against the shear-lag slip tau/Dt of 002 Eq A.8."""
    from interfaces.analytic.registry import dls_profiles
    case = dls(Dt=10.0)
    prof = fem.solve(case, h=0.15, fields=False).profiles["interface_jump"]
    ref = dls_profiles(**{k: v for k, v in case.analytic.items() if k != "model"})["interface_jump"]
    np.testing.assert_allclose(prof["x"], ref["x"][0], atol=1e-12)            # bond line x = t
    slip = np.interp(prof["s"], ref["s"], ref["jump_t"])
    assert np.abs(prof["jump_t"] - slip).max() < 5e-3 * np.abs(slip).max()
    # recovered tractions (weak-form interface force, fem.post.recover_tractions) are D [u]
    np.testing.assert_allclose(prof["traction_t"], 10.0 * prof["jump_t"], rtol=0, atol=1e-9 * np.abs(slip).max())


@pytest.mark.parametrize("Dt", [10.0, 1e12, math.inf])
def test_interface_tractions_balance_the_load_also_for_perfect_interfaces(Dt):
    """Each bond line carries P/2 in shear and no net normal force; for D = inf the traction is
    the constraint reaction, and D = 1e12 gives the same traction field."""
    r = fem.solve(dls(Dt=Dt), h=0.3, fields=False)
    P = r.quantities["load"]
    for name, prof in r.profiles.items():
        if name.startswith("interface_jump["):
            assert abs(np.sum(prof["weight"] * prof["traction_t"]) * W) == pytest.approx(P / 2, rel=1e-9)
            assert np.sum(prof["weight"] * prof["traction_n"]) * W == pytest.approx(0.0, abs=1e-9 * P)
    if Dt == 1e12:
        ref = fem.solve(dls(Dt=math.inf), h=0.3, fields=False).profiles["interface_jump"]
        np.testing.assert_allclose(r.profiles["interface_jump"]["traction_t"], ref["traction_t"],
                                   rtol=0, atol=1e-6 * np.abs(ref["traction_t"]).max())


@pytest.mark.parametrize("E_i", [300.0, 20000.0])          # compliant (Dn > 0) and stiff (Dn < 0)
def test_interphase_equivalent_interface_matches_a_resolved_interphase_layer(E_i):
    """002 Eq 52 is exact for a stack loaded across the layers when nu = 0: the interface model
    (substrates meeting at the mid-plane, Dn from Eq 52, negative for a stiff interphase)
    and a mesh that resolves the interphase layer give the same stiffness and the same
    closed form sigma = E_eff eps; a negative Dn makes the system a saddle point."""
    E1, E2, t_i, w = 1000.0, 2500.0, 0.2, 2.0
    mats = {"s1": IsotropicElastic(E=E1, nu=0.0), "s2": IsotropicElastic(E=E2, nu=0.0),
            "i": IsotropicElastic(E=E_i, nu=0.0)}
    law = LinearInterface.from_interphase(t_i, E_i, E_i / 2, E1, E2, E1 / 2, E2 / 2)
    bcs = [BoundaryCondition("fixed", "*", "ymin", ("x", "y"), (0.0, 0.0)),
           BoundaryCondition("traction", "*", "ymax", ("x", "y"), (0.0, 1.0))]
    meas = {"stiffness": {"load": [["*", "ymax"]], "support": [["*", "ymin"]], "direction": "y"}}
    interface_model = Case(name="eq52", analysis="plane_stress", materials=mats, boundary_conditions=bcs,
                           bodies=[Body("A", Rectangle(0, 0, 1.0, w), "s1"), Body("B", Rectangle(0, w, 1.0, w), "s2")],
                           interfaces=[InterfacePair("A", "B", law)], measurements=meas)
    layered = Case(name="layer", analysis="plane_stress", materials=mats, boundary_conditions=bcs,
                   bodies=[Body("A", Rectangle(0, 0, 1.0, w - t_i / 2), "s1"),
                           Body("I", Rectangle(0, w - t_i / 2, 1.0, t_i), "i"),
                           Body("B", Rectangle(0, w + t_i / 2, 1.0, w - t_i / 2), "s2")],
                   measurements=meas)
    k_closed = 1.0 / ((w - t_i / 2) / E1 + t_i / E_i + (w - t_i / 2) / E2)
    r_if = fem.solve(interface_model, h=0.1)
    r_layer = fem.solve(layered, h=0.1)
    assert (law.Dn < 0) == (E_i > max(E1, E2))
    assert r_layer.quantities["stiffness"] == pytest.approx(k_closed, rel=1e-10)
    assert r_if.quantities["stiffness"] == pytest.approx(k_closed, rel=1e-10)
    assert r_if.quantities["stiffness_energy"] == pytest.approx(k_closed, rel=1e-10)
    if law.Dn < 0:
        assert r_if.quantities["interface_energy"] < 0 and r_if.diagnostics["negative_pivots"] != 0
        assert any("saddle" in w_ for w_ in r_if.diagnostics["warnings"])
    assert any("bonded perfectly" in w_ for w_ in r_layer.diagnostics["warnings"])


def test_rigid_mode_pins_need_no_memory_quadratic_in_the_prescribed_dofs():
    """An axisymmetric body prescribes u_r = 0 at every axis node: a 10 m sleeve has
    40000 such DOFs. The null space of the prescribed rows of the rigid modes came from
    an SVD with the full n x n factor U (12.8 GB there; the run was killed); it needs a
    few columns. The pins still leave no rigid mode free."""
    import tracemalloc
    from fem.boundary import pin_rigid_modes
    rng = np.random.default_rng(3)
    modes = rng.standard_normal((30000, 3))
    modes[:20000, 2] = 0.0                  # the prescribed DOFs hold two of the three modes
    tracemalloc.start()
    pins = pin_rigid_modes(modes, np.arange(20000), np.zeros(30000), np.arange(20000, 30000))
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 20e6                      # the rows themselves are 0.5 MB (old: 3.2 GB)
    assert len(pins) == 1 and pins[0] >= 20000
    held = modes[np.concatenate([np.arange(20000), pins])]
    assert np.linalg.matrix_rank(held) == 3


def test_elements_larger_than_the_specimen_are_named_in_the_refusal():
    """A DCB meshed with 60 mm elements (the specimen is 50 mm long) has two negative
    pivots; the refusal names the element size besides free motion and the material."""
    with pytest.raises(SolverError, match=r"negative pivots .* too coarse for the bodies \(a smaller element_size\)"):
        fem.solve(dcb(), h=60.0)
    assert fem.solve(dcb(), h=30.0).quantities["stiffness"] > 0
