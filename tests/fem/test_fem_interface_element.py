"""Checks of the imperfect interface element (002 Eq 7-29, ERRATA 1-2) against
closed forms, invariances and an independent integration of the energy of 002 Eq 7."""
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.integrate import quad

from fem.interface_element import (interface_energy, jumps, stiffness, stiffness_batch)


def rot(theta):
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s], [s, c]])


def block_rotation(theta, nodes):
    return np.kron(np.eye(nodes), rot(theta))


def eq22_25_first_rows(xy, Dn, Dt, t):
    """Rows 1 and 2 of the 4-node matrix written out from 002 Eq 22-25 (row 2 from Eq 17-19)."""
    dx, dy = xy[1] - xy[0]
    dl = math.hypot(dx, dy)
    a = Dt * dx**2 + Dn * dy**2
    b = (Dt - Dn) * dx * dy
    c = Dn * dx**2 + Dt * dy**2
    row1 = t / dl * np.array([a / 3, b / 3, a / 6, b / 6, -a / 6, -b / 6, -a / 3, -b / 3])
    row2 = t / dl * np.array([b / 3, c / 3, b / 6, c / 6, -b / 6, -c / 6, -b / 3, -c / 3])
    return row1, row2, a, b, c, dl


@pytest.mark.parametrize("xy", [[[0.0, 0.0], [2.0, 0.0]], [[0.3, -1.0], [1.7, 2.5]],
                                [[1.0, 1.0], [1.0, -3.0]]])
@pytest.mark.parametrize("Dn,Dt", [(7.0, 2.0), (0.0, 3.0), (150.0, 0.0), (-2.0, 4.0)])
def test_linear_element_reproduces_eq22_25(xy, Dn, Dt):
    xy = np.array(xy)
    t = 2.5
    K = stiffness(xy, Dn, Dt, thickness=t)
    row1, row2, a, b, c, dl = eq22_25_first_rows(xy, Dn, Dt, t)
    np.testing.assert_allclose(K[0], row1, rtol=1e-13, atol=1e-13 * abs(row1).max())
    np.testing.assert_allclose(K[1], row2, rtol=1e-13, atol=1e-13 * abs(row1).max())
    # the whole matrix: node pattern of 002 Eq 20 (N3 = -N2, N4 = -N1) times the 2x2 block
    S = np.array([[2, 1, -1, -2], [1, 2, -2, -1], [-1, -2, 2, 1], [-2, -1, 1, 2]]) / 6.0
    B = t / dl * np.array([[a, b], [b, c]])
    np.testing.assert_allclose(K, np.kron(S, B), rtol=1e-13, atol=1e-13 * abs(B).max())


def test_quadratic_straight_element_equals_linear_on_linear_fields():
    """A straight 6-node element restricted to linear displacement fields on each side is
    the 4-node element: P^T K6 P = K4 (same energy and same resultant forces)."""
    rng = np.random.default_rng(1)
    p0, p1 = np.array([0.2, -0.4]), np.array([3.0, 1.1])
    xy4 = np.array([p0, p1])
    xy6 = np.array([p0, 0.5 * (p0 + p1), p1])
    Dn, Dt, t = 13.0, 4.0, 0.7
    K4 = stiffness(xy4, Dn, Dt, thickness=t)
    K6 = stiffness(xy6, Dn, Dt, thickness=t)
    # 6-node DOFs from 4-node DOFs: side 1 nodes (1, 2, 3) <- (1, mid, 2); side 2 nodes
    # (4, 5, 6) <- (3, mid, 4); node i coincides with node 2n+1-i
    P_nodes = np.array([[1, 0, 0, 0], [0.5, 0.5, 0, 0], [0, 1, 0, 0],
                        [0, 0, 1, 0], [0, 0, 0.5, 0.5], [0, 0, 0, 1]])
    P = np.kron(P_nodes, np.eye(2))
    np.testing.assert_allclose(P.T @ K6 @ P, K4, rtol=1e-12, atol=1e-12 * abs(K4).max())
    for _ in range(5):
        u4 = rng.normal(size=8)
        u6 = P @ u4
        e4 = interface_energy(xy4, u4, Dn, Dt, thickness=t)
        e6 = interface_energy(xy6, u6, Dn, Dt, thickness=t)
        assert e6 == pytest.approx(e4, rel=1e-12)
        f4, f6 = K4 @ u4, K6 @ u6
        for side4, side6 in (([0, 1], [0, 1, 2]), ([2, 3], [3, 4, 5])):
            np.testing.assert_allclose(f6.reshape(-1, 2)[side6].sum(0),
                                       f4.reshape(-1, 2)[side4].sum(0), rtol=1e-11, atol=1e-12)


coords = st.floats(-5.0, 5.0, allow_nan=False)


def random_element(data, n):
    p0 = np.array([data.draw(coords), data.draw(coords)])
    ang = data.draw(st.floats(0.0, 2 * math.pi))
    length = data.draw(st.floats(0.2, 4.0))
    p2 = p0 + length * np.array([math.cos(ang), math.sin(ang)])
    if n == 2:
        return np.array([p0, p2])
    bow = data.draw(st.floats(-0.3, 0.3)) * length          # curved: middle node off the chord
    mid = 0.5 * (p0 + p2) + bow * np.array([-math.sin(ang), math.cos(ang)])
    return np.array([p0, mid, p2])


@settings(max_examples=40, deadline=None)
@given(data=st.data(), n=st.sampled_from([2, 3]), Dn=st.floats(0.0, 1e3), Dt=st.floats(0.0, 1e3))
def test_symmetric_psd_and_rigid_motion_free(data, n, Dn, Dt):
    xy = random_element(data, n)
    K = stiffness(xy, Dn, Dt, thickness=1.3)
    scale = max(abs(K).max(), 1e-300)
    np.testing.assert_allclose(K, K.T, atol=1e-13 * scale)
    assert np.linalg.eigvalsh(K).min() >= -1e-12 * scale
    # rigid translation of both sides together: no force (ERRATA 2)
    a, b = data.draw(coords), data.draw(coords)
    u = np.tile([a, b], 2 * n)
    np.testing.assert_allclose(K @ u, 0.0, atol=1e-12 * scale * (abs(a) + abs(b) + 1))
    # a rigid rotation moves coincident nodes identically: no jump, no force
    pts = np.concatenate([xy, xy[::-1]])
    u_rot = 1e-3 * np.stack([-pts[:, 1], pts[:, 0]], axis=1).ravel()
    np.testing.assert_allclose(K @ u_rot, 0.0, atol=1e-12 * scale)


@settings(max_examples=30, deadline=None)
@given(data=st.data(), n=st.sampled_from([2, 3]), theta=st.floats(-math.pi, math.pi))
def test_rotating_the_element_rotates_the_matrix(data, n, theta):
    xy = random_element(data, n)
    Dn, Dt = 40.0, 3.0
    K = stiffness(xy, Dn, Dt)
    Kr = stiffness(xy @ rot(theta).T, Dn, Dt)
    R = block_rotation(theta, 2 * n)
    np.testing.assert_allclose(Kr, R @ K @ R.T, atol=1e-12 * abs(K).max())


def energy_eq7(xy, u, Dn, Dt, t, axisymmetric=False):
    """Independent energy of 002 Eq 7 along the curve through the three side-1 nodes,
    integrated adaptively (scipy quad) in the curve parameter; the curve and both sides'
    displacements are the quadratics through the nodal values (side 2 node 6 sits on node 1)."""
    s_nodes = np.array([-1.0, 0.0, 1.0])
    cx, cy = (np.polyfit(s_nodes, xy[:, k], 2) for k in (0, 1))
    U = u.reshape(6, 2)
    side1 = [np.polyfit(s_nodes, U[:3, k], 2) for k in (0, 1)]
    side2 = [np.polyfit(s_nodes, U[3:][::-1, k], 2) for k in (0, 1)]

    def integrand(s):
        dx, dy = np.polyval(np.polyder(cx), s), np.polyval(np.polyder(cy), s)
        dl = math.hypot(dx, dy)
        lx, ly = dx / dl, dy / dl
        M = np.array([[Dn * ly**2 + Dt * lx**2, (Dt - Dn) * lx * ly],
                      [(Dt - Dn) * lx * ly, Dn * lx**2 + Dt * ly**2]])
        jump = np.array([np.polyval(side1[k], s) - np.polyval(side2[k], s) for k in (0, 1)])
        thick = np.polyval(cx, s) if axisymmetric else t
        return 0.5 * thick * jump @ M @ jump * dl

    return quad(integrand, -1.0, 1.0, epsabs=0, epsrel=1e-13, limit=200)[0]


@pytest.mark.parametrize("axisymmetric", [False, True])
def test_curved_quadratic_element_against_independent_energy_of_eq7(axisymmetric):
    xy = np.array([[1.0, 0.0], [1.6, 0.9], [1.2, 2.0]])     # clearly curved
    rng = np.random.default_rng(7)
    Dn, Dt, t = 30.0, 4.0, 1.7
    for _ in range(4):
        u = rng.normal(size=12)
        ref = energy_eq7(xy, u, Dn, Dt, t, axisymmetric)
        e = interface_energy(xy, u, Dn, Dt, thickness=t, axisymmetric=axisymmetric, n_gauss=40)
        assert e == pytest.approx(ref, rel=1e-10)
        # the default 4-point rule of 002 is an approximation for curved elements only
        e4 = interface_energy(xy, u, Dn, Dt, thickness=t, axisymmetric=axisymmetric)
        assert e4 == pytest.approx(ref, rel=1e-2)   # 0.25 % here


def test_paper_misprinted_derivative_would_fail():
    """ERRATA 1: the printed dm_x = x1 + x2 - 2 x3 gives a different (wrong) element; ours
    matches the straight-line limit exactly, where x'(xi) must be constant = (x3 - x1)/2."""
    xy = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    K6 = stiffness(xy, 5.0, 2.0)
    # a uniform slip of side 2 in x: energy = 1/2 Dt slip^2 L t exactly
    u = np.zeros(12)
    u[6::2] = 0.25
    assert 0.5 * u @ K6 @ u == pytest.approx(0.5 * 2.0 * 0.25**2 * 2.0, rel=1e-13)


def test_axisymmetric_replaces_thickness_by_radius():
    # vertical element at r = 3: the per-radian matrix equals the planar one with t = 3
    xy = np.array([[3.0, 0.0], [3.0, 1.0], [3.0, 2.0]])
    np.testing.assert_allclose(stiffness(xy, 9.0, 2.0, axisymmetric=True),
                               stiffness(xy, 9.0, 2.0, thickness=3.0), rtol=1e-13)
    # radial 4-node element from r = 1 to 3, uniform opening jump 0.1 in z:
    # phi = 1/2 Dn 0.1^2 int_1^3 r dr = 1/2 Dn 0.01 * 4
    xy2 = np.array([[1.0, 0.0], [3.0, 0.0]])
    u = np.zeros(8)
    u[1::2][2:] = 0.1                                        # side 2 moves +z
    assert interface_energy(xy2, u, 9.0, 2.0, axisymmetric=True) == pytest.approx(0.18, rel=1e-13)


def test_batch_matches_single_and_accepts_per_element_parameters():
    rng = np.random.default_rng(3)
    m = 7
    xy = rng.normal(size=(m, 3, 2))
    xy[:, 2] = xy[:, 0] + rng.uniform(1, 2, size=(m, 2))
    xy[:, 1] = 0.5 * (xy[:, 0] + xy[:, 2]) + 0.1 * rng.normal(size=(m, 2))
    Dn, Dt = rng.uniform(0, 10, m), rng.uniform(-1, 10, m)
    Kb = stiffness_batch(xy, Dn, Dt, thickness=2.0)
    u = rng.normal(size=(m, 12))
    eb = interface_energy(xy, u, Dn, Dt, thickness=2.0)
    jn_b, jt_b = jumps(xy, u, xi=[-0.3, 0.8])
    for k in range(m):
        np.testing.assert_allclose(Kb[k], stiffness(xy[k], Dn[k], Dt[k], thickness=2.0), rtol=1e-14)
        assert eb[k] == pytest.approx(interface_energy(xy[k], u[k], Dn[k], Dt[k], thickness=2.0))
        jn, jt = jumps(xy[k], u[k], xi=[-0.3, 0.8])
        np.testing.assert_allclose(jn, jn_b[k])
        np.testing.assert_allclose(jt, jt_b[k])


def test_jumps_sign_convention_and_energy_density():
    """Side 1 to the right of node 1 -> node n: n1 points into side 1, opening is positive,
    and the element energy equals the integral of 1/2 (Dn jn^2 + Dt jt^2) (002 Eq 4)."""
    xy = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])   # side 1 below (n1 = (0, -1))
    u = np.zeros(12)
    u[1:6:2] = -0.2                                          # side 1 moves down: opening
    u[6::2] = -0.05                                          # side 2 moves -x: slip +0.05
    jn, jt = jumps(xy, u, xi=[-1.0, 0.2, 1.0])
    np.testing.assert_allclose(jn, 0.2)
    np.testing.assert_allclose(jt, 0.05)
    Dn, Dt = 6.0, 10.0
    assert interface_energy(xy, u, Dn, Dt) == pytest.approx(0.5 * (Dn * 0.04 + Dt * 0.0025) * 2.0)


def test_negative_and_zero_parameters_and_rejections():
    xy = np.array([[0.0, 0.0], [1.0, 1.0]])
    np.testing.assert_allclose(stiffness(xy, -3.0, -3.0), -stiffness(xy, 3.0, 3.0))
    assert not np.any(stiffness(xy, 0.0, 0.0))
    with pytest.raises(ValueError, match="fem.solve"):
        stiffness(xy, math.inf, 1.0)
    with pytest.raises(ValueError, match="Dt"):
        stiffness(xy, 1.0, float("nan"))
    with pytest.raises(ValueError, match="n = 2 or 3"):
        stiffness(np.zeros((4, 2)), 1.0, 1.0)
    with pytest.raises(ValueError, match="degenerate"):
        stiffness(np.zeros((2, 2)), 1.0, 1.0)
    with pytest.raises(ValueError, match="thickness"):
        stiffness(xy, 1.0, 1.0, thickness=-1.0)
    with pytest.raises(ValueError, match="shape"):
        stiffness_batch(np.ones((3, 2, 2)) * [[0, 0], [1, 0]], np.ones(2), 1.0)
