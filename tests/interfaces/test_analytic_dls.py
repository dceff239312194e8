"""Double lap shear shear-lag model (002 Eq 40-42, 50, 51, Appendix A; ERRATA 3-4)."""
import math

import numpy as np
import pytest
from scipy.integrate import quad, solve_bvp

from interfaces.analytic import (DoubleLapShear, dls_axial_stress, dls_beta_l_max, dls_compliance,
                                 dls_identical_beta, dls_identical_compliance, dls_identical_stiffness,
                                 dls_long_bond_stiffness, dls_shear_stress, dls_stiffness)
from interfaces.errors import CaseError

# 002 Sec 3.1 wood strand specimen
T, E, G, L_BOND, L_ARM, W = 0.6, 10000.0, 500.0, 25.0, 5.0, 10.0
DTS = [math.inf, 1e6, 1e4, 1000.0, 100.0, 50.0, 10.0, 5.0, 2.0, 1.0, 0.1, 1e-3]
# a dissimilar specimen (thicker, softer central strip)
DISSIMILAR = dict(t1=0.6, E1=10000.0, G1=500.0, t2=1.1, E2=4000.0, G2=250.0, l=12.0, W=10.0)


def identical(l=L_BOND, Dt=math.inf, L=0.0, **kw):
    return DoubleLapShear(T, E, G, T, E, G, l, W, L, Dt, **kw)


@pytest.mark.parametrize("Dt", DTS)
@pytest.mark.parametrize("l", [0.3, 2.0, 25.0, 400.0, 5000.0])
def test_general_solution_equals_eq40_for_identical_strips(l, Dt):
    general = identical(l, Dt).compliance
    closed = dls_identical_compliance(T, E, G, l, W, Dt)
    assert general == pytest.approx(closed, rel=1e-10)
    assert identical(l, Dt).beta == pytest.approx(dls_identical_beta(T, E, G, Dt), rel=1e-13)


@pytest.mark.parametrize("Dt", DTS)
def test_stiffness_with_arms_equals_eq42(Dt):
    m = identical(Dt=Dt, L=L_ARM)
    assert m.arm_compliance == pytest.approx(3 * L_ARM / (2 * T * W * E), rel=1e-15)
    assert m.stiffness == pytest.approx(dls_identical_stiffness(T, E, G, L_BOND, W, L_ARM, Dt), rel=1e-10)
    assert dls_stiffness(T, E, G, T, E, G, L_BOND, W, L_ARM, Dt) == m.stiffness


def test_beta_l_of_the_002_wood_strand_is_22_8():
    m = identical()
    assert round(m.beta_l, 1) == 22.8
    assert m.beta_l == pytest.approx(dls_beta_l_max(T, E, G, L_BOND), rel=1e-14)  # Eq 51
    # beta*l is largest for the perfect interface (002 Sec 3.4)
    assert all(identical(Dt=d).beta_l < m.beta_l for d in DTS[1:])


def test_long_bond_limit_eq50():
    # C/C_inf -> 1 with the end effect decaying as 1/l: l (C/C_inf - 1) -> 10/(4 beta) (Eq 40)
    for Dt in (math.inf, 10.0):
        m = identical(l=1e4, Dt=Dt)
        assert m.compliance_long_bond == pytest.approx(1e4 / (3 * T * W * E), rel=1e-15)
        assert 1e4 * (m.compliance / m.compliance_long_bond - 1) == pytest.approx(10 / (4 * m.beta), rel=1e-9)
    k_long = identical(l=1e7).stiffness  # arms excluded
    assert k_long == pytest.approx(dls_long_bond_stiffness(T, E, 1e7, W), rel=1e-6)
    # dissimilar strips: the bond becomes the parallel bar l / (W (2 t1 E1 + t2 E2))
    d = dict(DISSIMILAR)
    d["l"] = 1e4
    c1 = DoubleLapShear(**d).compliance
    d["l"] = 2e4
    c2 = DoubleLapShear(**d).compliance
    cinf = 1e4 / (10.0 * (2 * 0.6 * 10000.0 + 1.1 * 4000.0))
    # C = C_inf + const for a long bond: the constant end term is the same at 1e4 and 2e4
    assert c2 - 2 * cinf == pytest.approx(c1 - cinf, rel=1e-8)


def test_far_field_stress_is_erratum_3():
    m = DoubleLapShear(**DISSIMILAR)
    P = 7.0
    assert m.sigma_inf(P) == pytest.approx(10000.0 * P / ((2 * 0.6 * 10000.0 + 1.1 * 4000.0) * 10.0), rel=1e-15)
    assert identical().sigma_inf(P) == pytest.approx(P / (3 * T * W), rel=1e-15)
    # far field: equal strains in both layers
    s1, s2 = m.sigma_inf(P), (P / m.W - 2 * m.t1 * m.sigma_inf(P)) / m.t2
    assert s1 / m.E1 == pytest.approx(s2 / m.E2, rel=1e-13)


def _numerical_bvp(m: DoubleLapShear, P: float = 1.0):
    """Independent shear-lag solve in displacements (layer averages u1, u2).

    t1 E1 u1'' = -tau, (t2/2) E2 u2'' = tau, tau = (u2 - u1)/R (traction on layer 1),
    E1 u1'(0) = 0, E2 u2'(0) = P/(t2 W), E1 u1'(l) = P/(2 t1 W), u2(0) = 0.
    """
    R = m.strip_shear_compliance + m.slip_compliance
    t1, t2, E1, E2 = m.t1, m.t2, m.E1, m.E2

    def rhs(y, z):
        u1, d1, u2, d2 = z
        tau = (u2 - u1) / R
        return np.vstack([d1, -tau / (t1 * E1), d2, 2 * tau / (t2 * E2)])

    def bc(za, zb):
        return np.array([za[1], za[3] - P / (t2 * m.W * E2), zb[1] - P / (2 * t1 * m.W * E1), za[2]])

    y = np.linspace(0.0, m.l, 2001)
    z0 = np.zeros((4, y.size))
    sol = solve_bvp(rhs, bc, y, z0, tol=1e-10, max_nodes=200000)
    assert sol.success, sol.message
    return sol, R


@pytest.mark.parametrize("Dt", [math.inf, 100.0, 5.0, 0.5])
@pytest.mark.parametrize("geom", ["identical", "dissimilar"])
def test_closed_form_against_numerical_shear_lag_bvp(Dt, geom):
    kw = dict(DISSIMILAR) if geom == "dissimilar" else dict(t1=T, E1=E, G1=G, t2=T, E2=E, G2=G, l=6.0, W=W)
    kw["Dt"] = Dt
    m_avg = DoubleLapShear(**kw, layer_shear=True)
    m_paper = DoubleLapShear(**kw)
    sol, R = _numerical_bvp(m_avg)
    # layer-average displacement between the two loaded ends
    u1_l = sol.sol(m_avg.l)[0]
    assert m_avg.compliance == pytest.approx(u1_l, rel=1e-7)  # u2(0) = 0
    # shear traction at mid-bond from the numerical solution and A.9 (interface slip only)
    u1m, _, u2m, _ = sol.sol(m_avg.l / 2)
    tau_mid = (u2m - u1m) / R
    assert tau_mid == pytest.approx(float(m_paper.shear_stress(m_avg.l / 2)), rel=1e-7)
    assert m_paper.compliance == pytest.approx(u1_l - abs(tau_mid) * m_paper.strip_shear_compliance, rel=1e-7)
    # profiles
    y = np.linspace(0, m_avg.l, 37)
    s1, s2 = m_paper.axial_stress(y)
    np.testing.assert_allclose(s1, m_avg.E1 * sol.sol(y)[1], rtol=1e-6, atol=1e-9 * m_paper.sigma0())
    np.testing.assert_allclose(s2, m_avg.E2 * sol.sol(y)[3], rtol=1e-6, atol=1e-9 * m_paper.sigma0())


@pytest.mark.parametrize("split", [0.1, 0.37, 0.5, 0.8])
def test_layer_average_compliance_is_independent_of_the_split_point(split):
    m = DoubleLapShear(**DISSIMILAR, Dt=3.0, layer_shear=True)
    ys = split * m.l
    s1 = lambda y: float(m.axial_stress(y)[0])  # noqa: E731
    s2 = lambda y: float(m.axial_stress(y)[1])  # noqa: E731
    du = (quad(s2, 0, ys, epsabs=0, epsrel=1e-13)[0] / m.E2 + quad(s1, ys, m.l, epsabs=0, epsrel=1e-13)[0] / m.E1
          + abs(float(m.shear_stress(ys))) * (m.strip_shear_compliance + m.slip_compliance))
    assert du == pytest.approx(m.compliance, rel=1e-11)


@pytest.mark.parametrize("Dt", [math.inf, 50.0, 2.0])
def test_paper_compliance_is_a9_evaluated_by_quadrature(Dt):
    m = DoubleLapShear(**DISSIMILAR, Dt=Dt)
    s1 = lambda y: float(m.axial_stress(y)[0])  # noqa: E731
    s2 = lambda y: float(m.axial_stress(y)[1])  # noqa: E731
    du = (quad(s2, 0, m.l / 2, epsabs=0, epsrel=1e-13)[0] / m.E2
          + quad(s1, m.l / 2, m.l, epsabs=0, epsrel=1e-13)[0] / m.E1
          + abs(float(m.shear_stress(m.l / 2))) * m.slip_compliance)
    assert du == pytest.approx(m.compliance, rel=1e-11)
    assert dls_compliance(*[DISSIMILAR[k] for k in ("t1", "E1", "G1", "t2", "E2", "G2", "l", "W")], Dt) == m.compliance


@pytest.mark.parametrize("Dt", [math.inf, 20.0, 1.0])
def test_shear_stress_profile(Dt):
    m = DoubleLapShear(**DISSIMILAR, Dt=Dt)
    P = 3.0
    s1, s2 = m.axial_stress([0.0, m.l], P)
    assert s1[0] == pytest.approx(0.0, abs=1e-14 * m.sigma0(P))
    assert s1[1] == pytest.approx(m.sigma0(P), rel=1e-13)                    # A.5
    assert s2[0] == pytest.approx(P / (m.t2 * m.W), rel=1e-13)
    assert s2[1] == pytest.approx(0.0, abs=1e-13 * P / (m.t2 * m.W))
    # the interface carries P/2 per outer strip: int tau dy = -P/(2W)
    total = quad(lambda y: float(m.shear_stress(y, P)), 0, m.l, epsabs=0, epsrel=1e-13)[0]
    assert total == pytest.approx(-P / (2 * m.W), rel=1e-11)
    # tau = -t1 d<s1>/dy (A.8) and d tau/dy = (s2/E2 - s1/E1)/R (shear-lag kinematics)
    y = np.linspace(0.5, m.l - 0.5, 9)
    h = 1e-4
    ds1 = (m.axial_stress(y + h, P)[0] - m.axial_stress(y - h, P)[0]) / (2 * h)
    np.testing.assert_allclose(m.shear_stress(y, P), -m.t1 * ds1, rtol=1e-7)
    dtau = (m.shear_stress(y + h, P) - m.shear_stress(y - h, P)) / (2 * h)
    s1, s2 = m.axial_stress(y, P)
    R = m.strip_shear_compliance + m.slip_compliance
    np.testing.assert_allclose(dtau, (s2 / m.E2 - s1 / m.E1) / R, rtol=1e-6, atol=1e-9 * np.abs(dtau).max())
    # A.10 as printed (signed): t1 beta s0 e^{beta l/2}/(1 - e^{beta l})
    bl = m.beta * m.l
    a10 = m.t1 * m.beta * m.sigma0(P) * math.exp(bl / 2) / (1 - math.exp(bl))
    assert float(m.shear_stress(m.l / 2, P)) == pytest.approx(a10, rel=1e-12)
    assert np.all(m.shear_stress(np.linspace(0, m.l, 50), P) < 0)
    np.testing.assert_allclose(dls_shear_stress(y, **DISSIMILAR, Dt=Dt, P=P), m.shear_stress(y, P), rtol=1e-15)
    np.testing.assert_allclose(dls_axial_stress(y, **DISSIMILAR, Dt=Dt, P=P)[0], s1, rtol=1e-15)
    slip = m.interface_slip(y, P)
    np.testing.assert_allclose(slip, 0.0 if math.isinf(Dt) else m.shear_stress(y, P) / Dt, rtol=1e-15)


def test_no_overflow_for_very_long_bonds():
    m = identical(l=1e5)  # beta l ~ 9e4
    assert m.beta_l > 5e4
    s1, _ = m.axial_stress(np.linspace(0, m.l, 11))
    tau = m.shear_stress(np.linspace(0, m.l, 11))
    assert np.all(np.isfinite(s1)) and np.all(np.isfinite(tau)) and math.isfinite(m.compliance)
    assert s1[5] == pytest.approx(m.sigma_inf(), rel=1e-14)


def test_stiffness_monotone_in_dt_and_limits():
    ks = [identical(Dt=d, L=L_ARM).stiffness for d in sorted(DTS[1:])] + [identical(L=L_ARM).stiffness]
    assert np.all(np.diff(ks) > 0)
    assert identical(Dt=1e12, L=L_ARM).stiffness == pytest.approx(ks[-1], rel=1e-9)
    deb = identical(Dt=0.0, L=L_ARM)
    assert deb.stiffness == 0.0 and math.isinf(deb.compliance) and deb.beta == 0.0
    assert dls_identical_stiffness(T, E, G, L_BOND, W, L_ARM, 0.0) == 0.0
    with pytest.raises(CaseError, match="debonded"):
        deb.shear_stress(1.0)


def test_negative_dt_of_a_stiff_interphase():
    limit = -1.0 / identical().strip_shear_compliance  # -1666.7 MPa/mm
    stiff = identical(Dt=2 * limit, L=L_ARM)
    assert stiff.stiffness > identical(L=L_ARM).stiffness
    with pytest.raises(CaseError, match="rigid-interphase limit"):
        identical(Dt=0.5 * limit)
    with pytest.raises(CaseError, match="Dt"):
        dls_identical_compliance(T, E, G, L_BOND, W, -10.0)  # the printed Eq 40 needs Dt >= 0
    with pytest.raises(CaseError, match="negative Dt needs strips of finite shear modulus"):
        DoubleLapShear(T, E, math.inf, T, E, math.inf, L_BOND, W, 0.0, -5.0)


def test_rigid_strips_and_perfect_interface():
    m = DoubleLapShear(T, E, math.inf, T, E, math.inf, L_BOND, W)
    assert math.isinf(m.beta)
    assert m.compliance == pytest.approx(m.compliance_long_bond, rel=1e-15)
    # G -> inf approaches it continuously
    assert DoubleLapShear(T, E, 1e12, T, E, 1e12, L_BOND, W).compliance == pytest.approx(m.compliance, rel=1e-5)


def test_profile_positions_are_validated():
    m = identical()
    with pytest.raises(CaseError, match=r"y must lie in \[0, 25\]"):
        m.shear_stress([-1.0, 3.0])
    with pytest.raises(CaseError, match="y must be finite"):
        m.axial_stress(np.nan)
