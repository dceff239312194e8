"""DCB beam on an elastic foundation (002 Eq 46-47, Appendix B; ERRATA 5)."""
import math

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.integrate import quad

from interfaces.analytic import (DoubleCantileverBeam, dcb_compliance, dcb_deflection,
                                 dcb_kb_from_stiffness, dcb_stiffness)
from interfaces.errors import CaseError

# 002 Sec 3.2: wood strand arms, grain along x
A, H, W, EXX, KB = 25.0, 0.6, 10.0, 10000.0, 7808.0


def _hermite_beam_fe(m: DoubleCantileverBeam, n_free=40, n_bond=600, bond_length=None):
    """Independent Euler-Bernoulli beam FE (cubic Hermite) of one arm: free from x = -a to 0,
    on a Winkler foundation k1 (consistent foundation matrix) from 0 to bond_length, unit load
    at x = -a. Returns the load-point deflection."""
    EI = m.E_xx * m.I
    k1 = 1.0 / m.foundation_compliance
    Lb = bond_length or 30.0 * m.Delta
    x = np.concatenate([np.linspace(-m.a, 0.0, n_free + 1), np.linspace(0.0, Lb, n_bond + 1)[1:]])
    L = np.diff(x)[:, None, None]
    one = np.ones_like(L)
    kb = EI / L ** 3 * np.block([[12 * one, 6 * L, -12 * one, 6 * L], [6 * L, 4 * L * L, -6 * L, 2 * L * L],
                                 [-12 * one, -6 * L, 12 * one, -6 * L], [6 * L, 2 * L * L, -6 * L, 4 * L * L]])
    kf = k1 * L / 420 * np.block([[156 * one, 22 * L, 54 * one, -13 * L], [22 * L, 4 * L * L, 13 * L, -3 * L * L],
                                  [54 * one, 13 * L, 156 * one, -22 * L], [-13 * L, -3 * L * L, -22 * L, 4 * L * L]])
    ke = kb + kf * (x[:-1] >= 0.0)[:, None, None]
    idx = 2 * np.arange(x.size - 1)[:, None] + np.arange(4)[None, :]
    rows = np.repeat(idx, 4, axis=1).ravel()
    cols = np.tile(idx, (1, 4)).ravel()
    K = sp.csc_matrix((ke.ravel(), (rows, cols)), shape=(2 * x.size, 2 * x.size))
    F = np.zeros(2 * x.size)
    F[0] = 1.0
    return spla.spsolve(K, F)[0]


@pytest.mark.parametrize("Dn", [math.inf, 1e3, 10.0, 1.0, 0.1])
def test_eq46_against_independent_beam_on_foundation_fe(Dn):
    m = DoubleCantileverBeam(A, H, W, EXX, Dn, KB)
    v_tip = _hermite_beam_fe(m)
    assert m.compliance == pytest.approx(2.0 * v_tip, rel=2e-7)


def test_perfect_and_rigid_limit_is_simple_beam_theory():
    m = DoubleCantileverBeam(A, H, W, EXX)
    assert m.Delta == 0.0
    assert m.compliance == m.C0 == pytest.approx(8 * A ** 3 / (W * EXX * H ** 3), rel=1e-15)
    assert DoubleCantileverBeam(A, H, W, EXX, 1e14, 1e14).compliance == pytest.approx(m.C0, rel=1e-3)
    assert DoubleCantileverBeam(A, H, W, EXX, 1e20, 1e20).compliance == pytest.approx(m.C0, rel=1e-4)
    # clamped arm: v = P/(6EI)(x^3 + 3 a x^2), zero along the bond
    x = np.linspace(-A, 5, 31)
    v = m.deflection(x, 2.0)
    EI = EXX * m.I
    np.testing.assert_allclose(v, np.where(x <= 0, 2.0 / (6 * EI) * (x ** 3 + 3 * A * x ** 2), 0.0), rtol=1e-13,
                               atol=1e-15)


def test_eq47_and_b2():
    m = DoubleCantileverBeam(A, H, W, EXX, 2.0, KB)
    assert m.foundation_compliance == pytest.approx(1 / (2 * W * 2.0) + 1 / KB, rel=1e-15)
    assert m.Delta ** 4 == pytest.approx(W * EXX * H ** 3 / 3 * (1 / (2 * W * 2.0) + 1 / KB), rel=1e-13)
    # Delta^4 = 4 E I / k1: the decay length of B.1
    assert m.Delta ** 4 == pytest.approx(4 * EXX * m.I * m.foundation_compliance, rel=1e-13)
    assert KB / (2 * W) == pytest.approx(390.4)  # 002 Sec 3.2


@pytest.mark.parametrize("Dn", [math.inf, 100.0, 1.0])
def test_deflection_appendix_b(Dn):
    m = DoubleCantileverBeam(A, H, W, EXX, Dn, KB)
    P = 0.7
    EI, D = EXX * m.I, m.Delta
    # load-point compliance is 2 v(-a)/P (Appendix B -> Eq 46)
    assert 2 * float(m.deflection(-A, P)) / P == pytest.approx(m.compliance, rel=1e-13)
    # B.4 crack-tip values
    assert float(m.deflection(0.0, P)) == pytest.approx(P * D * D * (A + D) / (2 * EI), rel=1e-13)
    h = 1e-3 * D

    def d(fun, x0, k, side, h=h):
        # one-sided 6-point finite-difference derivative of order k at x0
        s = np.arange(6) * h * side
        V = np.vander(s, 6, increasing=True)
        coeff = np.linalg.solve(V.T, np.eye(6)[k] * math.factorial(k))
        return coeff @ fun(x0 + s)

    v = lambda x: m.deflection(x, P)  # noqa: E731
    assert d(v, 0.0, 1, +1) == pytest.approx(-P * D * (2 * A + D) / (2 * EI), rel=1e-6)  # B.4
    for k in (1, 2, 3):  # slope, moment, shear continuous at the crack tip
        assert d(v, 0.0, k, -1) == pytest.approx(d(v, 0.0, k, +1), rel=2e-4)
    # B.5 on the free arm: EI v'' = P (a + x) (v is a cubic there: the stencil is exact)
    for x0 in (-20.0, -7.0):
        assert EI * d(v, x0, 2, 1, h=0.5) == pytest.approx(P * (A + x0), rel=1e-9)
    # equilibrium of one arm: the foundation reactions carry P with no moment about the load point
    k1 = 1.0 / m.foundation_compliance
    force = quad(lambda x: k1 * float(m.deflection(x, P)), 0, 60 * D, limit=400, epsabs=1e-14 * P)[0]
    moment = quad(lambda x: k1 * float(m.deflection(x, P)) * (x + A), 0, 60 * D, limit=400,
                  epsabs=1e-11 * P * A)[0]
    assert force == pytest.approx(P, rel=1e-9)
    assert moment == pytest.approx(0.0, abs=1e-9 * P * A)
    np.testing.assert_allclose(dcb_deflection([-A, 0, 1], A, H, W, EXX, Dn, KB, P), m.deflection([-A, 0, 1], P),
                               rtol=1e-15)


def test_kb_round_trip():
    k = dcb_stiffness(A, H, W, EXX, math.inf, KB)
    assert dcb_kb_from_stiffness(k, A, H, W, EXX) == pytest.approx(KB, rel=1e-12)
    for kb in (1.0, 50.0, 1e5, 1e8):
        k = dcb_stiffness(A, H, W, EXX, kb=kb)
        assert dcb_kb_from_stiffness(k, A, H, W, EXX) == pytest.approx(kb, rel=1e-9)
    k0 = 1.0 / DoubleCantileverBeam(A, H, W, EXX).C0
    with pytest.raises(CaseError, match="k_perfect"):
        dcb_kb_from_stiffness(k0, A, H, W, EXX)
    with pytest.raises(CaseError, match="k_perfect"):
        dcb_kb_from_stiffness(-1.0, A, H, W, EXX)


def test_dn_effect_and_debonded_limit():
    ks = [dcb_stiffness(A, H, W, EXX, d, KB) for d in (1e-3, 0.01, 0.1, 1.0, 10.0, 100.0, math.inf)]
    assert np.all(np.diff(ks) > 0)
    assert ks[-2] / ks[-1] > 0.94 and ks[0] / ks[-1] < 0.2
    assert dcb_stiffness(A, H, W, EXX, 0.0, KB) == 0.0
    assert math.isinf(dcb_compliance(A, H, W, EXX, 0.0, KB))
    with pytest.raises(CaseError, match="debonded"):
        DoubleCantileverBeam(A, H, W, EXX, 0.0, KB).deflection(0.0)


def test_negative_dn_down_to_the_rigid_limit():
    limit = -KB / (2 * W)
    stiff = DoubleCantileverBeam(A, H, W, EXX, 2 * limit, KB)
    assert stiff.stiffness > DoubleCantileverBeam(A, H, W, EXX, math.inf, KB).stiffness
    assert DoubleCantileverBeam(A, H, W, EXX, limit, KB).compliance == pytest.approx(
        DoubleCantileverBeam(A, H, W, EXX).C0, rel=1e-12)
    with pytest.raises(CaseError, match="rigid-interphase limit"):
        DoubleCantileverBeam(A, H, W, EXX, 0.5 * limit, KB)
    with pytest.raises(CaseError, match="negative Dn needs a finite foundation"):
        DoubleCantileverBeam(A, H, W, EXX, -5.0)
    with pytest.raises(CaseError, match=r"x must lie in \[-25"):
        DoubleCantileverBeam(A, H, W, EXX, 1.0, KB).deflection(-26.0)
