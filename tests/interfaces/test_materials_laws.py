"""Materials, interface laws and geometry against closed forms."""
import math

import numpy as np
import pytest

from interfaces import (BilinearNormalInterface, CaseError, Circle, IsotropicElastic, LinearInterface, Polygon,
                        Rectangle, TransverselyIsotropicElastic, isotropic_from_KG)
from interfaces.materials import MieGruneisen


def test_isotropic_plane_stress_and_strain():
    m = IsotropicElastic(E=2400.0, nu=0.33)
    E, nu = 2400.0, 0.33
    ps = E / (1 - nu**2) * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])
    np.testing.assert_allclose(m.stiffness("plane_stress"), ps, rtol=1e-12)
    lam, mu = m.lame
    pe = np.array([[lam + 2 * mu, lam, 0], [lam, lam + 2 * mu, 0], [0, 0, mu]])
    np.testing.assert_allclose(m.stiffness("plane_strain"), pe, rtol=1e-12)
    assert m.stiffness("axisymmetric").shape == (4, 4)
    # dilatational wave speeds: plane strain sqrt((lam+2mu)/rho), plane stress sqrt(E/((1-nu^2) rho))
    assert m.wave_speed("plane_strain") == pytest.approx(math.sqrt((lam + 2 * mu) / m.rho), rel=1e-9)
    assert m.wave_speed("plane_stress") == pytest.approx(math.sqrt(E / (1 - nu**2) / m.rho), rel=1e-9)


def test_wood_strand_compliance_in_plane_stress():
    """002 Sec 3.1 strand: plane-stress compliance is the engineering-constant matrix."""
    w = TransverselyIsotropicElastic(E_A=10000, E_T=1000, G_A=500, nu_A=0.2, fiber=(0, 1))
    S = np.linalg.inv(w.stiffness("plane_stress"))
    expect = np.array([[1 / 1000, -0.2 / 10000, 0], [-0.2 / 10000, 1 / 10000, 0], [0, 0, 1 / 500]])
    np.testing.assert_allclose(S, expect, rtol=1e-12, atol=1e-16)


def test_fibre_rotation_rotates_the_stiffness():
    """C(theta) from the fibre direction equals the tensor rotation of C(0)."""
    a = math.radians(30)
    w0 = TransverselyIsotropicElastic(E_A=10000, E_T=1000, G_A=500, nu_A=0.2, fiber=(1, 0))
    w = TransverselyIsotropicElastic(E_A=10000, E_T=1000, G_A=500, nu_A=0.2, fiber=(math.cos(a), math.sin(a)))
    c, s = math.cos(a), math.sin(a)
    # strain transformation for engineering shear (global -> fibre frame)
    T = np.array([[c * c, s * s, c * s], [s * s, c * c, -c * s], [-2 * c * s, 2 * c * s, c * c - s * s]])
    for an in ("plane_stress", "plane_strain"):
        np.testing.assert_allclose(w.stiffness(an), T.T @ w0.stiffness(an) @ T, rtol=1e-10, atol=1e-8)


def test_transversely_isotropic_reduces_to_isotropic():
    E, nu = 1000.0, 0.25
    w = TransverselyIsotropicElastic(E_A=E, E_T=E, G_A=E / (2 * (1 + nu)), nu_A=nu, nu_T=nu, fiber=(0.3, 0.4, 0.5))
    np.testing.assert_allclose(w.stiffness3d(), IsotropicElastic(E, nu).stiffness3d(), rtol=1e-10, atol=1e-8)


def test_bad_constants_are_rejected_naming_the_field():
    with pytest.raises(CaseError, match="^E must be > 0"):
        IsotropicElastic(E=-1, nu=0.3)
    with pytest.raises(CaseError, match="^nu must be in"):
        IsotropicElastic(E=1, nu=0.5)
    with pytest.raises(CaseError, match="^nu_A must satisfy"):
        TransverselyIsotropicElastic(E_A=1000, E_T=1000, G_A=500, nu_A=0.9)
    with pytest.raises(CaseError, match="^fiber"):
        TransverselyIsotropicElastic(E_A=1000, E_T=1000, G_A=500, nu_A=0.2, fiber=(0, 0))


def test_K_G_round_trip_and_mie_gruneisen_small_strain():
    m = isotropic_from_KG(5000.0, 2000.0)
    assert m.K == pytest.approx(5000.0) and m.G == pytest.approx(2000.0)
    ni = MieGruneisen(C0=4.6e6, S1=1.44, gamma0=1.93, G=76000.0, rho=8.9e-9)
    eta = 1e-7
    assert ni.pressure(1 - eta) / eta == pytest.approx(ni.K, rel=1e-5)


def test_linear_interface_traction_energy_and_limits():
    law = LinearInterface(Dn=2.0, Dt=5.0)
    tn, tt = law.traction(0.1, -0.2)
    assert tn == pytest.approx(0.2) and tt == pytest.approx(-1.0)
    assert law.energy_density(0.1, -0.2) == pytest.approx(0.5 * (2 * 0.01 + 5 * 0.04))
    perfect = LinearInterface(math.inf, math.inf)
    assert perfect.perfect and perfect.energy_density(0.0, 0.0) == 0.0
    with pytest.raises(CaseError, match="^Dn must be >= 0"):
        LinearInterface(-1.0, 1.0)


def test_bilinear_normal_law_branches():
    law = BilinearNormalInterface(Dn_tension=1.0, Dt=3.0, Dn_compression=100.0)
    tn, _ = law.traction(np.array([0.1, -0.1]), np.zeros(2))
    np.testing.assert_allclose(tn, [0.1, -10.0])
    assert law.normal_stiffness(-1.0) == 100.0


def test_interphase_conversion_eq52_and_rigid_limit():
    """002 Eq 52: soft interphase -> positive D; as stiff as substrates -> 1/D = t/E_i - t/E."""
    E1 = E2 = 1000.0
    G1 = G2 = 400.0
    law = LinearInterface.from_interphase(0.01, 100.0, 40.0, E1, E2, G1, G2)
    assert law.Dn == pytest.approx(1 / (0.01 * (1 / 100 - 1 / 1000)))
    same = LinearInterface.from_interphase(0.01, 1000.0, 400.0, E1, E2, G1, G2)
    assert math.isinf(same.Dn) and math.isinf(same.Dt)
    rigid = LinearInterface.from_interphase(0.01, math.inf, math.inf, E1, E2, G1, G2)
    assert rigid.Dn == pytest.approx(-1 / (0.01 / 1000))
    with pytest.raises(CaseError, match="^E_i must be > 0"):
        LinearInterface.from_interphase(0.01, -5.0, 400.0, E1, E2, G1, G2)


def test_shapes_contain_and_sides():
    r = Rectangle(1.0, 2.0, 4.0, 2.0, angle=90.0)
    assert r.contains([[0.0, 4.0]])[0] and not r.contains([[2.0, 3.0]])[0]
    np.testing.assert_allclose(r.edge_normal("ymax"), [-1.0, 0.0], atol=1e-12)
    assert r.edge_length("ymin") == 4.0
    assert Circle(0, 0, 1).contains([[0.7, 0.7]])[0]
    tri = Polygon([[0, 0], [1, 0], [1, 1]])
    np.testing.assert_array_equal(tri.contains([[0.6, 0.2], [0.2, 0.6]]), [True, False])
