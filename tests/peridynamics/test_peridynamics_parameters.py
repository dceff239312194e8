"""CPD constants <-> linear elasticity (003 Eq 25, Table 2, Sec 4.5; ERRATA 12)."""
import math

import numpy as np
import pytest

from interfaces.errors import CaseError
from peridynamics.parameters import (_interior_energy_density, calibrate, cpd_from_elastic, cpd_from_lame,
                                     elastic_from_cpd, lame_from_cpd, lattice_ratios, nu2d_from_nu3d,
                                     nu3d_from_nu2d, poisson_2d)

DELTA = 0.0301
# Table 2 of 003: (nu_2D, C2 delta^3 / C1)
TABLE2 = [(0.1, -7 / 64), (1 / 3, 0.0), (0.4, 3 / 64), (0.7, 33 / 64), (0.2, -9 / 128), (0.6, 9 / 32)]


@pytest.mark.parametrize("nu, ratio", TABLE2)
def test_eq25_and_the_plane_constants_reproduce_table2(nu, ratio):
    C2 = ratio / DELTA ** 3
    assert poisson_2d(1.0, C2, DELTA) == pytest.approx(nu, rel=1e-12)
    lam, mu = lame_from_cpd(1.0, C2, 0.0, DELTA, 2)
    assert lam / (lam + 2 * mu) == pytest.approx(nu, rel=1e-12)
    # plane strain: nu_3D = nu_2D / (1 + nu_2D) and back
    E, nu3 = elastic_from_cpd(1.0, C2, 0.0, DELTA, 2)
    assert nu3 == pytest.approx(nu3d_from_nu2d(nu), rel=1e-12)
    assert nu2d_from_nu3d(nu3) == pytest.approx(nu, rel=1e-12)


def test_printed_C2_values_of_sec41():
    """003 Sec 4.1 prints C2 at delta = 0.0301: -4e3, 1.9e4, 1.7e3, -129 (C1^B = 1/20)."""
    assert -7 / 64 / DELTA ** 3 == pytest.approx(-4e3, rel=0.01)
    assert 33 / 64 / DELTA ** 3 == pytest.approx(1.9e4, rel=0.01)
    assert 3 / 64 / DELTA ** 3 == pytest.approx(1.7e3, rel=0.02)
    assert (1 / 20) * (-9 / 128) / DELTA ** 3 == pytest.approx(-129, rel=0.005)


def test_3d_conversion_reproduces_printed_C3_of_sec45():
    """003 Sec 4.5: nu = 0.1 -> C3^A(0.105) = -1.7e6, nu = 0.4, C1^B = 20 -> C3^B = 1.4e8."""
    d = 0.105
    for C1, nu, printed in ((1.0, 0.1, -1.7e6), (20.0, 0.4, 1.4e8)):
        mu = math.pi * C1 * d ** 4 / 30
        E = 2 * mu * (1 + nu)
        c1, c2, c3 = cpd_from_elastic(E, nu, d, 3)
        assert c1 == pytest.approx(C1, rel=1e-12) and c2 == 0.0
        assert c3 == pytest.approx(printed, rel=0.03)


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("E,nu", [(210.0, 0.3), (3.0, -0.2), (1e4, 0.45)])
def test_round_trip(dim, E, nu):
    C = cpd_from_elastic(E, nu, 0.07, dim)
    assert np.allclose(elastic_from_cpd(*C, 0.07, dim), (E, nu), rtol=1e-12)
    lam, mu = lame_from_cpd(*C, 0.07, dim)
    assert np.allclose(cpd_from_lame(lam, mu, 0.07, dim), C, rtol=1e-12)


def test_bad_input_names_the_field():
    with pytest.raises(CaseError, match="nu"):
        cpd_from_elastic(1.0, 0.5, 0.1, 2)
    with pytest.raises(CaseError, match="C2"):
        lame_from_cpd(1.0, 2.0, 0.0, 0.1, 3)
    with pytest.raises(CaseError, match="calibration"):
        calibrate((1.0, 0.0, 0.0), 0.01, 0.0301, 2, "magic")


def _ball(rng, n, dim, delta):
    v = rng.standard_normal((n, dim))
    v /= np.linalg.norm(v, axis=1)[:, None]
    r = delta * rng.random(n) ** (1.0 / dim)
    return v * r[:, None]


def test_continuum_constants_by_monte_carlo():
    """Independent check of ERRATA 12: sample the horizon integrals of 003 Eq 7 at random."""
    rng = np.random.default_rng(0)
    n, delta = 400_000, 1.3
    eps = np.array([[0.3, 0.1], [0.1, -0.2]])
    # 2D pairs: W1 = 1/4 C1 int L (n.eps.n)^2 dA  vs  1/2 lam tr^2 + mu eps:eps (C2 = 0)
    X = _ball(rng, n, 2, delta)
    L = np.linalg.norm(X, axis=1)
    nn = X / L[:, None]
    area = math.pi * delta ** 2
    W1 = 0.25 * np.mean(L * np.einsum("pi,ij,pj->p", nn, eps, nn) ** 2) * area
    lam, mu = lame_from_cpd(1.0, 0.0, 0.0, delta, 2)
    assert W1 == pytest.approx(0.5 * lam * np.trace(eps) ** 2 + mu * np.sum(eps * eps), rel=0.01)
    # 2D triples: int int |Xi x Xj| = 8 pi delta^6 / 9
    Y = _ball(rng, n, 2, delta)
    I2 = np.mean(np.abs(X[:, 0] * Y[:, 1] - X[:, 1] * Y[:, 0])) * area ** 2
    assert I2 == pytest.approx(8 * math.pi * delta ** 6 / 9, rel=0.01)
    # 3D quadruples: int int int |det| = pi^4 delta^12 / 8
    A, B, C = (_ball(rng, n, 3, delta) for _ in range(3))
    vol = 4 / 3 * math.pi * delta ** 3
    I3 = np.mean(np.abs(np.einsum("pi,pi->p", np.cross(A, B), C))) * vol ** 3
    assert I3 == pytest.approx(math.pi ** 4 * delta ** 12 / 8, rel=0.01)
    # 3D pairs under a general strain
    eps3 = np.array([[0.2, 0.05, -0.1], [0.05, -0.3, 0.07], [-0.1, 0.07, 0.15]])
    L3 = np.linalg.norm(A, axis=1)
    n3 = A / L3[:, None]
    W13 = 0.25 * np.mean(L3 * np.einsum("pi,ij,pj->p", n3, eps3, n3) ** 2) * vol
    lam3, mu3 = lame_from_cpd(1.0, 0.0, 0.0, delta, 3)
    assert lam3 == pytest.approx(mu3, rel=1e-12)
    assert W13 == pytest.approx(0.5 * lam3 * np.trace(eps3) ** 2 + mu3 * np.sum(eps3 * eps3), rel=0.01)


def test_lattice_energy_density_against_direct_sum():
    """The kernel's interior energy density equals an independent numpy lattice sum."""
    h, delta, e = 0.01, 0.0301, 1e-4
    H = np.array([[e, 0.3 * e], [0.3 * e, -0.5 * e]])
    m = 4
    ax = h * np.arange(-m, m + 1)
    off = np.stack(np.meshgrid(ax, ax, indexing="ij"), axis=-1).reshape(-1, 2)
    off = off[(np.linalg.norm(off, axis=1) <= delta) & (np.linalg.norm(off, axis=1) > 0)]
    V = h * h
    L = np.linalg.norm(off, axis=1)
    l = np.linalg.norm(off + off @ H.T, axis=1)
    w1 = np.sum(0.5 * 0.5 * L * (l / L - 1) ** 2 * V)            # C1 = 1, per unit volume of p
    assert _interior_energy_density(h, delta, 2, (1.0, 0.0, 0.0), H) == pytest.approx(w1, rel=1e-10, abs=0.0)
    i, j = np.triu_indices(len(off), 1)
    A = np.abs(off[i, 0] * off[j, 1] - off[i, 1] * off[j, 0])
    keep = A > 1e-8 * L[i] * L[j]
    J = np.linalg.det(np.eye(2) + H)
    w2 = np.sum((2 / 3) * 0.5 * A[keep] * (J - 1) ** 2 * V * V)   # a/A = J exactly, C2 = 1
    assert _interior_energy_density(h, delta, 2, (0.0, 1.0, 0.0), H) == pytest.approx(w2, rel=1e-8, abs=0.0)


def test_lattice_energy_density_3d_against_direct_sum():
    """3D: the kernel's interior energy density of pairs and quadruples equals an
    independent numpy sum over the centre's neighbour tuples (each unordered triple of
    neighbours once, weight 3/2 = multiplicity 6 x 1/4, 003 Eq 7-10). A wrong tuple
    multiplicity in the kernels (e.g. 1 in place of the number of vertices whose horizon
    holds the tetrahedron) changes the quadruple part by that factor."""
    h, delta, e = 0.01, 0.0201, 1e-4
    H = np.array([[e, 0.2 * e, 0.0], [0.2 * e, -0.4 * e, 0.1 * e], [0.0, 0.1 * e, 0.3 * e]])
    m = 3
    ax = h * np.arange(-m, m + 1)
    off = np.stack(np.meshgrid(ax, ax, ax, indexing="ij"), axis=-1).reshape(-1, 3)
    L = np.linalg.norm(off, axis=1)
    off = off[(L <= delta) & (L > 0)]
    L = np.linalg.norm(off, axis=1)
    V = h ** 3
    l = np.linalg.norm(off + off @ H.T, axis=1)
    w1 = np.sum(0.5 * 0.5 * L * (l / L - 1) ** 2 * V)
    assert _interior_energy_density(h, delta, 3, (1.0, 0.0, 0.0), H) == pytest.approx(w1, rel=1e-10, abs=0.0)
    from itertools import combinations
    idx = np.array(list(combinations(range(len(off)), 3)))
    Vt = np.abs(np.einsum("ij,ij->i", np.cross(off[idx[:, 0]], off[idx[:, 1]]), off[idx[:, 2]]))
    keep = Vt > 1e-8 * L[idx].prod(axis=1)
    J = np.linalg.det(np.eye(3) + H)
    w3 = np.sum(1.5 * 0.5 * Vt[keep] * (J - 1) ** 2 * V ** 3)    # v/V = J exactly, C3 = 1
    assert _interior_energy_density(h, delta, 3, (0.0, 0.0, 1.0), H) == pytest.approx(w3, rel=1e-8, abs=0.0)


@pytest.mark.parametrize("dim,C", [(2, (0.7, 0.0, 0.0)), (2, (0.0, 1.3, 0.0)),
                                   (3, (0.7, 0.0, 0.0)), (3, (0.0, 0.0, 1.9))])
def test_patch_energy_against_direct_sum_over_every_central_point(dim, C):
    """Total energy W = sum_p V_p w_p of a small lattice patch under u = H X (003 Eq 7):
    the kernel (which evaluates a triangle / tetrahedron once, weighted by the number of
    its vertices whose horizon holds it) against a numpy sum over every central point
    and every pair / unordered pair / triple of its neighbours (weights 1/2, 2/3, 3/2).
    Catches a wrong tuple multiplicity, which the per-point energies cannot see."""
    from itertools import combinations

    from peridynamics.assembly import neighbour_lists
    from peridynamics.kernels import assemble, horizon_radius2

    h, delta, e = 0.01, 2.01 * 0.01, 1e-4
    H = (np.array([[e, 0.2 * e], [0.2 * e, -0.4 * e]]) if dim == 2 else
         np.array([[e, 0.2 * e, 0.0], [0.2 * e, -0.4 * e, 0.1 * e], [0.0, 0.1 * e, 0.3 * e]]))
    ax = h * np.arange(-2, 3)
    X = np.stack(np.meshgrid(*([ax] * dim), indexing="ij"), axis=-1).reshape(-1, dim)
    V = h ** dim
    J = np.linalg.det(np.eye(dim) + H)
    expected = 0.0      # one interaction type at a time: their energies differ by powers of V
    for p in range(len(X)):
        off = X - X[p]
        L = np.linalg.norm(off, axis=1)
        nb = off[(L > 0) & (L <= delta * (1 + 1e-9))]
        Ln = np.linalg.norm(nb, axis=1)
        ln = np.linalg.norm(nb + nb @ H.T, axis=1)
        expected += V * np.sum(0.5 * 0.5 * C[0] * Ln * (ln / Ln - 1) ** 2 * V)
        if dim == 2:
            for i, j in combinations(range(len(nb)), 2):
                A = abs(nb[i, 0] * nb[j, 1] - nb[i, 1] * nb[j, 0])
                if A > 1e-8 * Ln[i] * Ln[j]:
                    expected += V * (2 / 3) * 0.5 * C[1] * A * (J - 1) ** 2 * V * V
        else:
            for i, j, k in combinations(range(len(nb)), 3):
                Vt = abs(np.cross(nb[i], nb[j]) @ nb[k])
                if Vt > 1e-8 * Ln[i] * Ln[j] * Ln[k]:
                    expected += V * 1.5 * 0.5 * C[2] * Vt * (J - 1) ** 2 * V ** 3
    members = np.arange(len(X), dtype=np.int64)
    nptr, nidx = neighbour_lists(X, members, delta)
    f = np.zeros_like(X)
    e_node = np.zeros(len(X))
    Cs = [np.full(len(X), C[k]) for k in range(3)]
    out = assemble(X, X @ H.T, members, nptr, nidx, Cs[0], Cs[1], Cs[2], np.full(len(X), V), False,
                   np.zeros(1, np.int64), np.zeros(1, np.int64), np.zeros(0), f, e_node,
                   horizon_radius2(delta))
    assert out[0] == pytest.approx(expected, rel=1e-9, abs=0.0)
    assert e_node.sum() == pytest.approx(expected, rel=1e-9, abs=0.0)


@pytest.mark.parametrize("dim,h,dfac", [(2, 0.01, 3.01), (2, 0.01, 5.01), (3, 0.035, 3.01)])
def test_lattice_ratios_and_calibration(dim, h, dfac):
    """Report the discrete/continuum ratios; the lattice calibration makes them 1 for any strain size."""
    delta = dfac * h
    r = lattice_ratios(h, delta, dim)
    # a grid horizon sums close to, but not exactly like, the continuum (ERRATA 12)
    for v in (r.pairs_dilatation, r.pairs_uniaxial, r.pairs_shear):
        assert 0.8 < v < 1.3
    assert 0.8 < (r.triples if dim == 2 else r.quadruples) < 1.5
    C = (2.0, 5.0, 0.0) if dim == 2 else (2.0, 0.0, 7.0)
    Cl = calibrate(C, h, delta, dim, "lattice")
    e = 3e-6
    for k in range(3):
        if C[k] == 0:
            continue
        c_one = [0.0, 0.0, 0.0]
        c_one[k] = Cl[k]
        cont = [0.0, 0.0, 0.0]
        cont[k] = C[k]
        lam, mu = lame_from_cpd(*cont, delta, dim)
        dil = e * np.eye(dim)
        W = _interior_energy_density(h, delta, dim, tuple(c_one), dil)
        if k == 0:  # pairs alone: the continuum pair moduli (lam = mu + 0 C2)
            ref = 0.5 * lam * (dim * e) ** 2 + mu * dim * e * e
        else:       # triples / quadruples alone contribute only to lambda
            lam_k = lam - mu
            ref = 0.5 * lam_k * (dim * e) ** 2
        assert W == pytest.approx(ref, rel=1e-4)
