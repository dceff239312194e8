"""Composite-spheres bulk modulus with a spring interface (000 Sec 3) and 002 Eq 52."""
import math

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from interfaces.analytic import (CompositeSpheres, bulk_shear_from_young_poisson, composite_spheres_bulk_modulus,
                                 hashin_bulk_modulus, interphase_to_interface, sphere_in_cube_volume_fraction)
from interfaces.errors import CaseError

# 000 Sec 3: glass particles in a polymer matrix
KP, GP = bulk_shear_from_young_poisson(70000.0, 0.25)
KM, GM = bulk_shear_from_young_poisson(2400.0, 0.33)
A_MICRO = 0.7  # mm (700 um)
PHI = sphere_in_cube_volume_fraction(A_MICRO, 1.0, octant=True)
DNS = [math.inf, 1e9, 1e6, 1e5, 2e4, 1e3, 10.0, 1e-3, 0.0]


def test_young_poisson_helper():
    K, G = bulk_shear_from_young_poisson(70000.0, 0.25)
    assert K == pytest.approx(70000.0 / 1.5, rel=1e-15) and G == pytest.approx(28000.0, rel=1e-15)
    assert 9 * K * G / (3 * K + G) == pytest.approx(70000.0, rel=1e-14)
    with pytest.raises(CaseError, match="nu must be in"):
        bulk_shear_from_young_poisson(1.0, 0.5)


def test_volume_fraction_of_the_000_particulate_composite():
    assert round(PHI * 100, 2) == 17.96  # 000 Sec 3: Vp = 17.96%
    # the same as a sphere of diameter 700 um centred in a 1000 um cube
    assert sphere_in_cube_volume_fraction(0.35, 1.0) == pytest.approx(PHI, rel=1e-14)
    assert sphere_in_cube_volume_fraction(0.5, 1.0) == pytest.approx(math.pi / 6, rel=1e-15)
    with pytest.raises(CaseError, match="radius must be <= 0.5"):
        sphere_in_cube_volume_fraction(0.7, 1.0)


def test_perfect_interface_is_hashin_exactly():
    for phi in (0.0, 0.05, PHI, 0.5, 0.9):
        hashin = KM + phi * (KP - KM) / (1 + (1 - phi) * (KP - KM) / (KM + 4 * GM / 3))
        assert composite_spheres_bulk_modulus(KP, KM, GM, phi, A_MICRO) == pytest.approx(hashin, rel=1e-12)
        assert hashin_bulk_modulus(KP, KM, GM, phi) == pytest.approx(hashin, rel=1e-15)


def test_debonded_interface_is_the_empty_cavity():
    for phi in (0.05, PHI, 0.5):
        cavity = 4 * GM * KM * (1 - phi) / (4 * GM + 3 * phi * KM)
        assert composite_spheres_bulk_modulus(KP, KM, GM, phi, A_MICRO, 0.0) == pytest.approx(cavity, rel=1e-12)
        # Hashin's formula with an empty particle
        assert hashin_bulk_modulus(1e-300, KM, GM, phi) == pytest.approx(cavity, rel=1e-12)
        assert composite_spheres_bulk_modulus(KP, KM, GM, phi, A_MICRO, 1e-9) == pytest.approx(cavity, rel=1e-8)


def _linear_system(m: CompositeSpheres, eps0: float):
    """Solve the four conditions for (A, B, C, sigma_rr(b)) numerically (independent of the closed form)."""
    a, b = m.a, m.b
    M = np.array([
        [3 * m.K_p, -3 * m.K_m, 4 * m.G_m / a ** 3, 0.0],                     # sigma_rr continuous at a
        [3 * m.K_p + m.Dn * a, -m.Dn * a, -m.Dn / a ** 2, 0.0],               # sigma_rr(a) = Dn [u]
        [0.0, b, 1 / b ** 2, 0.0],                                              # u(b) = eps0 b
        [0.0, 3 * m.K_m, -4 * m.G_m / b ** 3, -1.0],                           # sigma_rr(b)
    ])
    return np.linalg.solve(M, np.array([0.0, 0.0, eps0 * b, 0.0]))


@pytest.mark.parametrize("Dn", DNS[1:-1])
@pytest.mark.parametrize("phi", [0.01, PHI, 0.6])
def test_closed_form_against_the_linear_system(Dn, phi):
    m = CompositeSpheres(KP, KM, GM, phi, A_MICRO, Dn)
    eps0 = 0.005
    A, B, C, s_b = _linear_system(m, eps0)
    assert m.bulk_modulus == pytest.approx(s_b / (3 * eps0), rel=1e-12)
    np.testing.assert_allclose(m.coefficients(eps0), (A, B, C), rtol=1e-11)


def _radial_fe(m: CompositeSpheres, n: int, eps0: float) -> float:
    """Independent 1D spherically symmetric linear FE: particle [0, a] and shell [a, b] with
    duplicated nodes at r = a joined by a spring 4 pi a^2 Dn; u(b) = eps0 b. Returns K = 2U/(9 eps0^2 V)."""
    def region(r0, r1, K, G, n_el):
        r = np.linspace(r0, r1, n_el + 1)
        lam = K - 2 * G / 3
        D = lam * np.ones((3, 3)) + 2 * G * np.eye(3)
        gp, gw = np.polynomial.legendre.leggauss(3)
        ke = np.zeros((n_el, 2, 2))
        h = np.diff(r)
        for xi, wq in zip(gp, gw):
            rq = r[:-1] + (xi + 1) / 2 * h
            N1, N2 = (1 - xi) / 2, (1 + xi) / 2
            Bm = np.zeros((n_el, 3, 2))
            Bm[:, 0, 0], Bm[:, 0, 1] = -1 / h, 1 / h
            Bm[:, 1, 0] = Bm[:, 2, 0] = N1 / rq
            Bm[:, 1, 1] = Bm[:, 2, 1] = N2 / rq
            ke += np.einsum("eik,ij,ejl->ekl", Bm, D, Bm) * (wq * h / 2 * 4 * np.pi * rq ** 2)[:, None, None]
        return ke

    kp = region(0.0, m.a, m.K_p, 1.0, n)  # the particle is in pure dilatation: its G does not enter
    km = region(m.a, m.b, m.K_m, m.G_m, n)
    ndof = 2 * (n + 1)
    rows, cols, vals = [], [], []
    for off, ke in ((0, kp), (n + 1, km)):
        e = np.arange(ke.shape[0]) + off
        idx = np.stack([e, e + 1], axis=1)
        rows.append(np.repeat(idx, 2, axis=1).ravel())
        cols.append(np.tile(idx, (1, 2)).ravel())
        vals.append(ke.reshape(len(e), 4).ravel())
    ks = 4 * np.pi * m.a ** 2 * m.Dn
    i, j = n, n + 1
    rows.append(np.array([i, j, i, j]))
    cols.append(np.array([i, j, j, i]))
    vals.append(np.array([ks, ks, -ks, -ks]))
    K = sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(ndof, ndof)).tocsr()
    u = np.zeros(ndof)
    u[-1] = eps0 * m.b
    free = np.arange(ndof - 1)
    u[free] = spla.spsolve(K[free][:, free].tocsc(), -K[free][:, [ndof - 1]] @ u[[ndof - 1]])
    U = 0.5 * u @ (K @ u)
    return 2 * U / (9 * eps0 ** 2 * (4 / 3 * np.pi * m.b ** 3))


@pytest.mark.parametrize("Dn", [1e6, 2e4, 1e3, 10.0])
@pytest.mark.parametrize("a", [A_MICRO, 7e-4])  # micro- and nanoparticles (000 Fig 13)
def test_closed_form_against_radial_finite_elements(Dn, a):
    m = CompositeSpheres(KP, KM, GM, PHI, a, Dn)
    k1, k2 = _radial_fe(m, 200, 0.005), _radial_fe(m, 400, 0.005)
    exact = m.bulk_modulus
    # displacement-driven FE over-estimates the energy, converging at O(h^2)
    assert k1 > k2 > exact
    assert (k1 - exact) / (k2 - exact) == pytest.approx(4.0, rel=2e-2)
    assert (4 * k2 - k1) / 3 == pytest.approx(exact, rel=1e-8)


@pytest.mark.parametrize("Dn", DNS)
def test_energies_sum_to_000_eq34(Dn):
    m = CompositeSpheres(KP, KM, GM, PHI, A_MICRO, Dn)
    eps0 = 0.005
    e = m.energies(eps0)
    total = e["strain_energy"] + e["interface_energy"]
    assert total == pytest.approx(4.5 * m.bulk_modulus * eps0 ** 2 * e["volume"], rel=1e-12)  # 000 Eq 34-35
    # mean-stress route, 000 Eq 36: sigma_rr(b) = 3 K eps0
    assert float(m.radial_stress(m.b, eps0)) == pytest.approx(3 * m.bulk_modulus * eps0, rel=1e-12)
    if 0.0 < Dn < math.inf:
        # sigma_rr(a) = Dn [u_r] and sigma_rr continuous
        s_p = float(m.radial_stress(m.a, eps0))
        s_m = float(m.radial_stress(np.nextafter(m.a, 2), eps0))
        assert s_p == pytest.approx(s_m, rel=1e-9)
        assert s_p == pytest.approx(Dn * m.interface_jump(eps0), rel=1e-10)
    assert float(m.radial_displacement(m.b, eps0)) == pytest.approx(eps0 * m.b, rel=1e-14)


def test_size_effect_and_monotonicity():
    # 000 Fig 13: for the same Dn, nanoparticles lose much more stiffness than microparticles
    Dn = 1e6
    micro = composite_spheres_bulk_modulus(KP, KM, GM, PHI, A_MICRO, Dn)
    nano = composite_spheres_bulk_modulus(KP, KM, GM, PHI, 7e-4, Dn)
    perfect = hashin_bulk_modulus(KP, KM, GM, PHI)
    cavity = composite_spheres_bulk_modulus(KP, KM, GM, PHI, A_MICRO, 0.0)
    assert (perfect - micro) / (perfect - cavity) < 0.01
    assert (nano - cavity) / (perfect - cavity) < 0.12  # 0.109: "near the plateau" (000 Sec 3)
    ks = [composite_spheres_bulk_modulus(KP, KM, GM, PHI, A_MICRO, d) for d in DNS[::-1]]
    assert np.all(np.diff(ks) > 0)


def test_negative_dn_down_to_the_rigid_limit():
    limit = -3 * KP / A_MICRO
    stiff = CompositeSpheres(KP, KM, GM, PHI, A_MICRO, 2 * limit)
    assert stiff.bulk_modulus > hashin_bulk_modulus(KP, KM, GM, PHI)
    rigid = CompositeSpheres(KP, KM, GM, PHI, A_MICRO, limit)
    assert rigid.bulk_modulus == pytest.approx((3 * KM + 4 * GM * PHI) / (3 * (1 - PHI)), rel=1e-12)
    assert rigid.bulk_modulus == pytest.approx(hashin_bulk_modulus(1e30, KM, GM, PHI), rel=1e-12)
    with pytest.raises(CaseError, match="rigid-interphase limit"):
        CompositeSpheres(KP, KM, GM, PHI, A_MICRO, 0.5 * limit)


# ---- 002 Eq 52 -------------------------------------------------------------------
def test_interphase_to_interface_eq52():
    t_i, Ei, Gi, E1, E2, G1, G2 = 0.01, 500.0, 200.0, 10000.0, 2000.0, 800.0, 700.0
    Dn, Dt = interphase_to_interface(t_i, Ei, Gi, E1, E2, G1, G2)
    assert 1 / Dn == pytest.approx(t_i * (1 / Ei - 0.5 * (1 / E1 + 1 / E2)), rel=1e-14)
    assert 1 / Dt == pytest.approx(t_i * (1 / Gi - 0.5 * (1 / G1 + 1 / G2)), rel=1e-14)
    assert Dn > 0 and Dt > 0
    # stiff interphase: negative, down to the rigid limit
    Dn_s, Dt_s = interphase_to_interface(t_i, 1e5, 1e4, E1, E2, G1, G2)
    assert Dn_s < 0 and Dt_s < 0
    Dn_r, Dt_r = interphase_to_interface(t_i, math.inf, math.inf, E1, E2, G1, G2)
    assert 1 / Dn_r == pytest.approx(-t_i / 2 * (1 / E1 + 1 / E2), rel=1e-15)
    assert 1 / Dt_r == pytest.approx(-t_i / 2 * (1 / G1 + 1 / G2), rel=1e-15)
    assert Dn_s < Dn_r < 0  # negative D runs from -inf (1/D = 0-) up to the rigid limit
    # 1/D = 0: no interphase or an interphase matching the substrates
    assert interphase_to_interface(0.0, Ei, Gi, E1, E2, G1, G2) == (math.inf, math.inf)
    assert interphase_to_interface(t_i, 3000.0, 500.0, 3000.0, 3000.0, 500.0, 500.0) == (math.inf, math.inf)
    for bad, name in ((0.0, "E_i"), (-5.0, "E_i")):
        with pytest.raises(CaseError, match=name):
            interphase_to_interface(t_i, bad, Gi, E1, E2, G1, G2)
    with pytest.raises(CaseError, match="G_i must be > 0"):
        interphase_to_interface(t_i, Ei, 0.0, E1, E2, G1, G2)
    with pytest.raises(CaseError, match="t_i must be >= 0"):
        interphase_to_interface(-1.0, Ei, Gi, E1, E2, G1, G2)


def test_interphase_matches_the_interface_law_constructor():
    from interfaces.laws import LinearInterface
    args = (0.02, 1e5, 300.0, 10000.0, 2000.0, 800.0, 700.0)
    law = LinearInterface.from_interphase(*args)
    Dn, Dt = interphase_to_interface(*args)
    assert law.Dn == pytest.approx(Dn, rel=1e-15) and law.Dt == pytest.approx(Dt, rel=1e-15)
