"""Composite-cylinders transverse bulk modulus with a spring interface (plane strain):
closed form against the linear system of the four conditions, an independent 1D radial
finite-element model, Hashin-Rosen's perfect-interface form and the limits."""
import math

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from interfaces.analytic import (CompositeCylinders, bulk_shear_from_young_poisson, composite_cylinders_bulk_modulus,
                                 plane_strain_bulk_modulus)
from interfaces.analytic.registry import MODELS, PROFILES
from interfaces.errors import CaseError

KF, GF = bulk_shear_from_young_poisson(70000.0, 0.25)     # glass (000 Sec 3)
KM, GM = bulk_shear_from_young_poisson(2400.0, 0.33)      # polymer
kf, km = plane_strain_bulk_modulus(KF, GF), plane_strain_bulk_modulus(KM, GM)
DNS = [1e9, 1e6, 1e4, 1e3, 10.0, 1e-3]


def _linear_system(m: CompositeCylinders, eps0: float):
    """(A, B, C, sigma_rr(b)) from the four conditions, solved numerically."""
    a, b = m.a, m.b
    M = np.array([
        [2 * m.k_f, -2 * m.k_m, 2 * m.G_m / a ** 2, 0.0],         # sigma_rr continuous at a
        [2 * m.k_f + m.Dn * a, -m.Dn * a, -m.Dn / a, 0.0],         # sigma_rr(a) = Dn [u]
        [0.0, b, 1 / b, 0.0],                                      # u(b) = eps0 b
        [0.0, 2 * m.k_m, -2 * m.G_m / b ** 2, -1.0],               # sigma_rr(b)
    ])
    return np.linalg.solve(M, np.array([0.0, 0.0, eps0 * b, 0.0]))


@pytest.mark.parametrize("Dn", DNS)
@pytest.mark.parametrize("phi", [0.01, 0.3, 0.7])
def test_closed_form_against_the_linear_system(Dn, phi):
    m = CompositeCylinders(kf, km, GM, phi, 0.7, Dn)
    A, B, C, s_b = _linear_system(m, 0.005)
    assert m.bulk_modulus == pytest.approx(s_b / (2 * 0.005), rel=1e-12)
    np.testing.assert_allclose(m.coefficients(0.005), (A, B, C), rtol=1e-10)


def _radial_fe(m: CompositeCylinders, n: int, eps0: float) -> float:
    """Independent 1D plane-strain axisymmetric linear FE (eps_rr, eps_tt; eps_zz = 0): fibre
    [0, a], matrix [a, b], duplicated nodes at a joined by a spring 2 pi a Dn; u(b) = eps0 b.
    Returns k = U / (2 eps0^2 pi b^2)."""
    def region(r0, r1, K, G, n_el):
        r = np.linspace(r0, r1, n_el + 1)
        lam = K - 2 * G / 3
        D = lam * np.ones((2, 2)) + 2 * G * np.eye(2)
        gp, gw = np.polynomial.legendre.leggauss(3)
        h = np.diff(r)
        ke = np.zeros((n_el, 2, 2))
        for xi, wq in zip(gp, gw):
            rq = r[:-1] + (xi + 1) / 2 * h
            Bm = np.zeros((n_el, 2, 2))
            Bm[:, 0, 0], Bm[:, 0, 1] = -1 / h, 1 / h
            Bm[:, 1, 0], Bm[:, 1, 1] = (1 - xi) / 2 / rq, (1 + xi) / 2 / rq
            ke += np.einsum("eik,ij,ejl->ekl", Bm, D, Bm) * (wq * h / 2 * 2 * np.pi * rq)[:, None, None]
        return ke

    Kf = m.k_f - 1.0 / 3.0     # any (K, G) with K + G/3 = k_f: the fibre is in pure in-plane dilatation
    blocks = [(0, region(0.0, m.a, Kf, 1.0, n)), (n + 1, region(m.a, m.b, m.k_m - m.G_m / 3, m.G_m, n))]
    ndof = 2 * (n + 1)
    rows, cols, vals = [], [], []
    for off, ke in blocks:
        idx = np.stack([np.arange(n) + off, np.arange(n) + off + 1], axis=1)
        rows.append(np.repeat(idx, 2, axis=1).ravel())
        cols.append(np.tile(idx, (1, 2)).ravel())
        vals.append(ke.reshape(n, 4).ravel())
    ks = 2 * np.pi * m.a * m.Dn
    rows.append(np.array([n, n + 1, n, n + 1]))
    cols.append(np.array([n, n + 1, n + 1, n]))
    vals.append(np.array([ks, ks, -ks, -ks]))
    K = sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(ndof, ndof)).tocsr()
    u = np.zeros(ndof)
    u[-1] = eps0 * m.b
    free = np.arange(ndof - 1)
    u[free] = spla.spsolve(K[free][:, free].tocsc(), -K[free][:, [ndof - 1]] @ u[[ndof - 1]])
    return 0.5 * u @ (K @ u) / (2 * eps0 ** 2 * np.pi * m.b ** 2)


@pytest.mark.parametrize("Dn", [1e6, 2e4, 1e3, 10.0])
@pytest.mark.parametrize("a", [0.7, 7e-4])
def test_closed_form_against_radial_finite_elements(Dn, a):
    m = CompositeCylinders(kf, km, GM, 0.3, a, Dn)
    k1, k2 = _radial_fe(m, 200, 0.005), _radial_fe(m, 400, 0.005)
    exact = m.bulk_modulus
    assert k1 > k2 > exact                       # displacement FE over-estimates the energy, O(h^2)
    assert (k1 - exact) / (k2 - exact) == pytest.approx(4.0, rel=2e-2)
    assert (4 * k2 - k1) / 3 == pytest.approx(exact, rel=1e-8)


def test_limits_and_hashin_rosen_form():
    phi = 0.3
    perfect = CompositeCylinders(kf, km, GM, phi, 0.7, math.inf).bulk_modulus
    hashin_rosen = km + phi / (1 / (kf - km) + (1 - phi) / (km + GM))
    assert perfect == pytest.approx(hashin_rosen, rel=1e-13)
    assert CompositeCylinders(kf, km, GM, phi, 0.7, 1e14).bulk_modulus == pytest.approx(perfect, rel=1e-9)
    empty = km * GM * (1 - phi) / (GM + phi * km)
    assert CompositeCylinders(kf, km, GM, phi, 0.7, 0.0).bulk_modulus == pytest.approx(empty, rel=1e-13)
    assert CompositeCylinders(kf, km, GM, phi, 0.7, 1e-9).bulk_modulus == pytest.approx(empty, rel=1e-9)
    # the interface enters only through a Dn: a smaller fibre with a proportionally stiffer interface is the same
    assert composite_cylinders_bulk_modulus(kf, km, GM, phi, 7e-4, 1e4) == pytest.approx(
        composite_cylinders_bulk_modulus(kf, km, GM, phi, 0.7, 10.0), rel=1e-13)
    ks = [CompositeCylinders(kf, km, GM, phi, 0.7, d).bulk_modulus for d in [0.0, 1.0, 1e2, 1e4, math.inf]]
    assert np.all(np.diff(ks) > 0)


def test_negative_dn_down_to_the_rigid_limit():
    a = 0.7
    rigid = -2 * kf / a
    m = CompositeCylinders(kf, km, GM, 0.3, a, rigid)
    assert m.bulk_modulus == pytest.approx((km + GM * 0.3) / 0.7, rel=1e-9)
    with pytest.raises(CaseError, match="rigid-interphase limit"):
        CompositeCylinders(kf, km, GM, 0.3, a, 0.5 * rigid)


def test_registry_model_and_profile():
    p = dict(K_p=KF, G_p=GF, K_m=KM, G_m=GM, a=0.7, phi=0.3, Dn=1e3, Dt=1e3)
    q = MODELS["composite_cylinders"](**p)
    assert q["bulk_modulus"] == pytest.approx(composite_cylinders_bulk_modulus(kf, km, GM, 0.3, 0.7, 1e3), rel=1e-14)
    assert q["bulk_modulus_debonded"] < q["bulk_modulus"] < q["bulk_modulus_perfect"]
    prof = PROFILES["composite_cylinders"](**p, eps0=0.01)["radial"]
    assert prof["u_r"][-1] == pytest.approx(0.01 * 0.7 / math.sqrt(0.3), rel=1e-12)
    assert prof["sigma_rr"][-1] == pytest.approx(2 * q["bulk_modulus"] * 0.01, rel=1e-12)
    with pytest.raises(CaseError, match="analytic.G_p"):
        MODELS["composite_cylinders"](K_p=KF, K_m=KM, G_m=GM, a=0.7, phi=0.3)
    with pytest.raises(CaseError, match="exactly one of"):
        MODELS["composite_cylinders"](**{**p, "b": 2.0})
