"""Finite-strain MPM (mpm/finite_strain.py): the neo-Hookean material of 004 Eq 18 with a
deformation gradient per particle, against the closed-form homogeneous compression
(interfaces/analytic/hyperelastic.py), the energy balance, and the small-strain limit."""
from __future__ import annotations

import math

import numpy as np
import pytest

from interfaces import (Body, BoundaryCondition, Box, Case, CaseError,
                        MieGruneisen, NeoHookean, Rectangle, isotropic_from_KG)
from interfaces.analytic.hyperelastic import (neo_hookean_compression, nominal_stress_for_stretch,
                                              stretch_for_nominal_stress)
import mpm
from mpm import finite_strain as FS
from mpm.options import merge
from mpm.solver import Model, _Runner

MAT = NeoHookean(K=2450.0, G=940.0, rho=1e-9)      # 004 Sec 2 (Fig 2)
LINEAR_TWIN = isotropic_from_KG(MAT.K, MAT.G, MAT.rho)
STRETCH = 0.8                                       # 20 % compression


def _compression_case(mat=MAT, analysis="plane_strain", stretch=STRETCH, size=4.0,
                      ramp_time=None, P=None) -> Case:
    """A block [0, size]^D compressed along y between two equal and opposite dead loads
    on ymin and ymax (by default the closed-form nominal stress of ``stretch``), with
    symmetry planes on xmin (and zmin in 3D; the axis in axisymmetric runs), the other
    sides free. (A roller support on ymin would hold only the nodes within the side's
    initial extent, and the lateral expansion of a 20 % compression carries the corner
    particles past it.)"""
    lateral = "uniaxial_stress" if analysis in ("3d", "axisymmetric") else "plane_strain_free"
    if P is None:
        P = nominal_stress_for_stretch(MAT, stretch, lateral)
    shape = Box(0.0, 0.0, 0.0, size, size, size) if analysis == "3d" else \
        Rectangle(0.0, 0.0, size, size)
    bcs = [BoundaryCondition("traction", "b", "ymin", ("y",), (-P,), ramp_time=ramp_time),
           BoundaryCondition("traction", "b", "ymax", ("y",), (P,), ramp_time=ramp_time)]
    if analysis != "axisymmetric":
        bcs.append(BoundaryCondition("fixed", "b", "xmin", ("x",), (0.0,)))
    if analysis == "3d":
        bcs.append(BoundaryCondition("fixed", "b", "zmin", ("z",), (0.0,)))
    return Case(name="compression", analysis=analysis, thickness=1.0, materials={"m": mat},
                bodies=[Body("b", shape, "m")], boundary_conditions=bcs)


def _stretches(pt, axis: int) -> float:
    """Current / initial distance between the outermost particle rows along ``axis``."""
    x0, x = pt.x0[:, axis], pt.x[:, axis]
    lo, hi = x0 <= x0.min() + 1e-9, x0 >= x0.max() - 1e-9
    return float((x[hi].mean() - x[lo].mean()) / (x0[hi].mean() - x0[lo].mean()))


def _sampled_run(case, samples: int, duration: float, **opts) -> list[dict]:
    """Run ``case`` (grid damping) for ``duration`` s, sampling ``samples`` times the
    applied nominal load, the measured stretches (particle rows), the mean F and
    stresses and the strain energy."""
    model = Model(case, merge(case, opts))
    run = _Runner(model)
    P_end = case.boundary_conditions[1].value[0]
    n = int(math.ceil(duration / model.dt / samples))
    out = []
    for _ in range(samples):
        h = run._advance(n)
        pt = model.particles
        out.append({"load": P_end * min(run.t / model.ramp_time, 1.0),
                    "lam": _stretches(pt, 1), "a": _stretches(pt, 0),
                    "Fyy": float(pt.F[:, 1, 1].mean()), "Fxx": float(pt.F[:, 0, 0].mean()),
                    "syy": float(pt.stress[:, 1].mean()), "U": float(h[-1, 2]),
                    "volume0": float(pt.volume0.sum())})
    return out


def _T1(case, **opts) -> float:
    """The run's estimated fundamental period (mpm.solver.Model.T1)."""
    return Model(case, merge(case, opts)).T1


def test_plane_strain_compression_to_20_percent_follows_the_closed_form():
    """Quasi-static compression to 20 % by a dead load ramped over 40 periods (plane
    strain, x free), sampled at eight points over the run: at each, the applied load
    gives the closed-form state (stretch, lateral stretch, axial Cauchy stress, energy
    W of Eq 18), compared with the measured stretches of the block (particle rows), the
    mean particle stress and the run's strain energy; F against the measured stretches.
    Measured: stress within 0.20 % of the end stress at every point, stretch 0.12 %,
    lateral stretch 0.13 %, F against the particle rows 8e-4, energy 0.45 % of the end
    energy."""
    T1 = _T1(_compression_case(), cell=0.5)
    case = _compression_case(ramp_time=40 * T1)
    samples = _sampled_run(case, 8, 48 * T1, cell=0.5, ppc=2)
    end_ref = neo_hookean_compression(MAT, STRETCH)
    worst = {k: 0.0 for k in ("sigma", "stretch", "lateral", "F", "energy")}
    for s in samples:
        ref = neo_hookean_compression(MAT, stretch_for_nominal_stress(MAT, s["load"]))
        worst["sigma"] = max(worst["sigma"], abs(s["syy"] - ref.sigma_axial[0])
                             / abs(end_ref.sigma_axial[0]))
        worst["stretch"] = max(worst["stretch"], abs(s["lam"] / ref.stretch[0] - 1.0))
        worst["lateral"] = max(worst["lateral"], abs(s["a"] / ref.lateral_stretch[0] - 1.0))
        worst["F"] = max(worst["F"], abs(s["Fyy"] - s["lam"]), abs(s["Fxx"] - s["a"]))
        worst["energy"] = max(worst["energy"], abs(s["U"] - s["volume0"] * ref.energy_density[0])
                              / (s["volume0"] * end_ref.energy_density[0]))
    assert samples[-1]["lam"] == pytest.approx(STRETCH, rel=2e-3)
    assert worst["sigma"] < 5e-3, worst
    assert worst["stretch"] < 4e-3, worst
    assert worst["lateral"] < 4e-3, worst
    assert worst["F"] < 2e-3, worst
    assert worst["energy"] < 1.5e-2, worst


def test_energy_balance_of_an_undamped_compression_to_20_percent():
    """Without damping, the work of the dead load equals strain (V0 W of Eq 18) plus
    kinetic energy all along the run, to 20 % compression."""
    case = _compression_case()
    T1 = _T1(case, cell=0.5)
    res = mpm.solve(case, cell=0.5, ppc=2, damping="none", ramp_time=8 * T1, max_time=10 * T1,
                    progress=False)
    h = res.diagnostics["history"]
    work = np.asarray(h["work_ext"]) + np.asarray(h["work_bc"])
    stored = np.asarray(h["strain"]) + np.asarray(h["kinetic"])
    err = np.max(np.abs(work - stored)) / work[-1]
    assert float(np.min(res.fields["deformation_gradient"][:, 4])) < 0.85  # large strain
    assert err < 5e-3, err      # measured 1.6e-3


def _final_state(res) -> dict:
    F = np.asarray(res.fields["deformation_gradient"]).reshape(-1, 3, 3)
    return {"F": F.mean(axis=0), "stress": np.asarray(res.fields["stress"]).mean(axis=0)}


@pytest.mark.parametrize("analysis, update", [("3d", "usl"), ("axisymmetric", "usl"),
                                              ("3d", "musl"), ("axisymmetric", "musl")])
def test_uniaxial_stress_compression_in_3d_and_axisymmetric(analysis, update):
    """A cube (three symmetry planes) and a solid cylinder (axisymmetric, free outer
    surface) compressed 20 % by a dead load: stretches, F and the axial Cauchy stress
    against the closed-form uniaxial-stress state (x and z free), and the stored energy
    of Eq 18 (energy balance of the damped run). Measured at 8 cells per side: USL
    stretches within 0.08 %, stress within 0.1 %, energy balance 0.4 % (3D) / 0.7 %
    (axisymmetric, grid damping included); MUSL stretches within 0.04 %, stress 0.2 %
    (its damped-run balance, -1.6 %, is that of the linear MUSL runs too: not asserted)."""
    size = 4.0
    case = _compression_case(analysis=analysis, size=size)
    res = mpm.solve(case, cell=0.5, ppc=2, update=update, progress=False)
    ref = neo_hookean_compression(MAT, STRETCH, "uniaxial_stress")
    end = _final_state(res)
    lam, a = end["F"][1, 1], end["F"][0, 0]
    assert lam == pytest.approx(STRETCH, rel=2e-3)
    assert a == pytest.approx(ref.lateral_stretch[0], rel=1e-3)
    assert end["F"][2, 2] == pytest.approx(ref.lateral_stretch[0], rel=1e-3)
    sigma = neo_hookean_compression(MAT, lam, "uniaxial_stress").sigma_axial[0]
    assert end["stress"][1] == pytest.approx(sigma, rel=5e-3)
    V0 = size**3 if analysis == "3d" else 0.5 * size**2 * size * 2 * math.pi
    # measured +0.6 %: the stretch error times the nominal stress, dW = P dlam
    assert res.quantities["strain_energy"] == pytest.approx(V0 * ref.energy_density[0], rel=1.5e-2)
    if update == "usl":
        assert abs(res.quantities["energy_balance_error"]) < 1.5e-2


@pytest.mark.parametrize("update", ["usl", "musl", "usf"])
def test_small_strain_limit_is_the_linear_elastic_run(update):
    """At 1e-5 strain the neo-Hookean block and the linear block of the same K and G give
    the same displacements, stresses and strain energy (relative differences of the order
    of the strain), in each stress-update scheme."""
    runs = {}
    for name, mat in (("nh", MAT), ("linear", LINEAR_TWIN)):
        case = _compression_case(mat=mat, P=-1e-5 * MAT.K)
        runs[name] = mpm.solve(case, cell=0.5, ppc=2, update=update, progress=False)
    u_nh, u_lin = runs["nh"].fields["displacement"], runs["linear"].fields["displacement"]
    scale = np.abs(u_lin).max()
    assert np.abs(u_nh - u_lin).max() < 1e-3 * scale
    s_nh, s_lin = runs["nh"].fields["stress"], runs["linear"].fields["stress"]
    assert np.abs(s_nh - s_lin).max() < 1e-3 * np.abs(s_lin).max()
    assert runs["nh"].quantities["strain_energy"] == pytest.approx(
        runs["linear"].quantities["strain_energy"], rel=1e-3)


def test_a_run_mixes_neo_hookean_and_linear_fields():
    """Two blocks far apart (no shared nodes), one neo-Hookean compressed 20 %, one
    linear: each follows its own law in the same run (the neo-Hookean block its closed
    form, the linear block the single-body linear run)."""
    P = nominal_stress_for_stretch(MAT, STRETCH)
    bcs = []
    for body in ("nh", "lin"):
        load = P if body == "nh" else -1.0
        bcs += [BoundaryCondition("traction", body, "ymin", ("y",), (-load,)),
                BoundaryCondition("fixed", body, "xmin", ("x",), (0.0,)),
                BoundaryCondition("traction", body, "ymax", ("y",), (load,))]
    case = Case(name="mixed", analysis="plane_strain", thickness=1.0,
                materials={"nh": MAT, "lin": LINEAR_TWIN},
                bodies=[Body("nh", Rectangle(0.0, 0.0, 4.0, 4.0), "nh"),
                        Body("lin", Rectangle(8.0, 0.0, 4.0, 4.0), "lin")],
                boundary_conditions=bcs)
    res = mpm.solve(case, cell=0.5, ppc=2, progress=False)
    field = res.fields["material"]
    F = np.asarray(res.fields["deformation_gradient"]).reshape(-1, 3, 3)
    lam = F[field == 0, 1, 1].mean()
    assert lam == pytest.approx(STRETCH, rel=2e-3)
    assert np.allclose(F[field == 1], np.eye(3))    # linear fields keep F = I
    ref = neo_hookean_compression(MAT, lam)
    assert res.fields["stress"][field == 0, 1].mean() == pytest.approx(ref.sigma_axial[0], rel=5e-3)
    single = Case(name="lin", analysis="plane_strain", thickness=1.0, materials={"lin": LINEAR_TWIN},
                  bodies=[case.bodies[1]], boundary_conditions=bcs[3:])
    alone = mpm.solve(single, cell=0.5, ppc=2, progress=False)
    u_mixed = res.fields["displacement"][field == 1]
    assert np.abs(u_mixed - alone.fields["displacement"]).max() < 1e-3 * np.abs(alone.fields["displacement"]).max()


def test_finite_strain_kernel_matches_the_material_and_tracks_the_motion():
    """One kernel call: F <- (I + dt L) F, V = J V0, the Cauchy stress of
    ``NeoHookean.cauchy_stress``, the Green-Lagrange strain, V0 W; 2D plane strain, 2D
    axisymmetric (F_tt = r / r0) and 3D."""
    rng = np.random.default_rng(3)
    kind, params = FS.material_tables(_compression_case(analysis="3d"))
    for D, axisymmetric in ((2, False), (2, True), (3, False)):
        P = 5
        F0 = np.tile(np.eye(3), (P, 1, 1))
        F0[:, :D, :D] += 0.1 * rng.uniform(-1, 1, (P, D, D))
        L = rng.uniform(-1, 1, (P, D, D))
        dt = 0.05
        x0 = rng.uniform(1, 2, (P, D))
        x = x0 * 1.1
        nv = 6 if D == 3 else (4 if axisymmetric else 3)
        stress, strain = np.zeros((P, nv)), np.zeros((P, nv))
        V0 = rng.uniform(1, 2, P)
        V = V0.copy()
        F = F0.copy()
        foff0 = rng.uniform(-0.5, 0.5, (P, D))
        foff = foff0.copy()
        U = FS.finite_strain_update(L, F, stress, strain, V, V0, x, x0, foff, foff0,
                                    np.zeros(P, np.int64), kind, params, dt, axisymmetric,
                                    np.zeros((0, 2)))
        A = np.tile(np.eye(3), (P, 1, 1))
        A[:, :D, :D] += dt * L
        expected = A @ F0
        if D == 2:
            expected[:, 2, 2] = 1.1 if axisymmetric else 1.0
        np.testing.assert_allclose(F, expected, rtol=1e-13)
        np.testing.assert_allclose(foff, np.einsum("pij,pj->pi", expected[:, :D, :D], foff0),
                                   rtol=1e-13)
        J = np.linalg.det(expected)
        np.testing.assert_allclose(V, J * V0, rtol=1e-12)
        sigma = MAT.cauchy_stress(expected)
        E = 0.5 * (np.swapaxes(expected, 1, 2) @ expected - np.eye(3))
        if D == 3:
            ij = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)]
        else:
            ij = [(0, 0), (1, 1), (0, 1)] + ([(2, 2)] if axisymmetric else [])
        for a, (i, j) in enumerate(ij):
            np.testing.assert_allclose(stress[:, a], sigma[:, i, j], rtol=1e-10, atol=1e-9)
            np.testing.assert_allclose(strain[:, a], E[:, i, j] * (1 if i == j else 2), atol=1e-13)
        assert U == pytest.approx(float(np.sum(V0 * MAT.energy_density(expected))), rel=1e-12)


def test_unsupported_materials_are_refused_in_one_line():
    ps = _compression_case(analysis="plane_stress", P=-1.0)
    with pytest.raises(CaseError, match="neo-Hookean materials need analysis plane_strain"):
        mpm.solve(ps, cell=0.5)
    mg = _compression_case(mat=MieGruneisen(C0=4.6e6, S1=1.44, gamma0=2.0, G=76000.0,
                                            rho=8.87e-9), analysis="plane_stress", P=-1.0)
    assert "Mie-Grueneisen materials need analysis plane_strain" in mpm.supports(mg)
    with pytest.raises(CaseError, match="Mie-Grueneisen materials need analysis plane_strain"):
        mpm.solve(mg, cell=0.5)


def _column(materials: dict, P: float, split: bool) -> Case:
    """The 4 x 4 block of :func:`_compression_case`, whole or cut at mid-height into two
    bodies (default perfect bond) with the materials ``materials['low']`` / ``['up']``."""
    if split:
        bodies = [Body("low", Rectangle(0.0, 0.0, 4.0, 2.0), "low"),
                  Body("up", Rectangle(0.0, 2.0, 4.0, 2.0), "up")]
    else:
        bodies = [Body("low", Rectangle(0.0, 0.0, 4.0, 4.0), "low")]
    up = bodies[-1].name
    bcs = [BoundaryCondition("traction", "low", "ymin", ("y",), (-P,)),
           BoundaryCondition("traction", up, "ymax", ("y",), (P,))]
    bcs += [BoundaryCondition("fixed", b.name, "xmin", ("x",), (0.0,)) for b in bodies]
    return Case(name="column", analysis="plane_strain", thickness=1.0, materials=materials,
                bodies=bodies, boundary_conditions=bcs)


def test_bonded_neo_hookean_and_linear_fields_share_nodes():
    """Multimaterial nodes between a neo-Hookean and a linear field (perfect bond): at
    1e-5 strain the column equals the uncut linear block (to 7.5e-6 of the displacement,
    the order of the strain); two bonded neo-Hookean halves compressed 20 % equal the
    uncut neo-Hookean block to round-off."""
    small = -1e-5 * MAT.K
    mixed = mpm.solve(_column({"low": LINEAR_TWIN, "up": MAT}, small, True), cell=0.5,
                      progress=False)
    whole = mpm.solve(_column({"low": LINEAR_TWIN}, small, False), cell=0.5, progress=False)
    order = np.lexsort(mixed.fields["position"].T)
    ref_order = np.lexsort(whole.fields["position"].T)
    du = mixed.fields["displacement"][order] - whole.fields["displacement"][ref_order]
    assert np.abs(du).max() < 5e-5 * np.abs(whole.fields["displacement"]).max()  # 7.5e-6
    P = nominal_stress_for_stretch(MAT, STRETCH)
    split = mpm.solve(_column({"low": MAT, "up": MAT}, P, True), cell=0.5, progress=False)
    uncut = mpm.solve(_column({"low": MAT}, P, False), cell=0.5, progress=False)
    Fs = np.asarray(split.fields["deformation_gradient"])[order]
    Fu = np.asarray(uncut.fields["deformation_gradient"])[ref_order]
    assert np.abs(Fs - Fu).max() < 1e-10                                        # 7e-15
    assert split.quantities["strain_energy"] == pytest.approx(uncut.quantities["strain_energy"],
                                                              rel=1e-10)


def test_a_resumed_finite_strain_run_repeats_the_uninterrupted_one(tmp_path, interrupt_mpm):
    """The checkpoint keeps F and the loaded-edge offsets it carries: a neo-Hookean run
    interrupted mid-compression and resumed ends bit for bit where the uninterrupted run
    ends."""
    case = _compression_case()
    ref = mpm.solve(case, cell=0.5, progress=False)
    path = tmp_path / "nh.npz"
    opts = {"cell": 0.5, "progress": False, "checkpoint": str(path), "checkpoint_every": 1e9}
    patch = interrupt_mpm(2)
    with pytest.raises(KeyboardInterrupt):
        mpm.solve(case, **opts)
    patch.undo()
    res = mpm.solve(case, resume=True, **opts)
    for key in ("displacement", "stress", "deformation_gradient"):
        assert np.array_equal(res.fields[key], ref.fields[key]), key
    assert res.quantities["strain_energy"] == ref.quantities["strain_energy"]


def test_stiffness_measurement_at_finite_strain():
    """002 Eq 43 on the block compressed 20 %: the side displacements are extrapolated
    from the particle rows with F - I, so k = P W / (H (lam - 1)) of the closed form."""
    base = _compression_case()
    case = Case(name="compression", analysis="plane_strain", thickness=1.0,
                materials=base.materials, bodies=base.bodies,
                boundary_conditions=base.boundary_conditions,
                measurements={"stiffness": {"load": [["b", "ymax"]], "support": [["b", "ymin"]],
                                            "direction": "y"}})
    res = mpm.solve(case, cell=0.5, progress=False)
    P = case.boundary_conditions[1].value[0]
    k = P * 4.0 / (4.0 * (STRETCH - 1.0))
    # measured -0.52 % (the stretch error of the side rows, x 4 on 1 - lam); the
    # particle-row value without the extrapolation is 6 % off
    assert res.quantities["stiffness"] == pytest.approx(k, rel=1e-2)
