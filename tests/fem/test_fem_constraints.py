"""Exact constraint elimination u = T q + g (fem.constraints): every path checked on random q."""
import math

import numpy as np
import pytest

from fem.constraints import build_elimination
from fem.interface_mesh import NodePairs
from interfaces.errors import CaseError


def pairs_of(a, b, angle_deg, perfect_n, perfect_t, straight=True):
    th = math.radians(angle_deg)
    n = np.tile([math.cos(th), math.sin(th)], (len(a), 1))
    t = np.stack([-n[:, 1], n[:, 0]], axis=1)
    k = len(a)
    return NodePairs(np.asarray(a), np.asarray(b), n, t, np.full(k, straight),
                     np.full(k, perfect_n), np.full(k, perfect_t))


def jumps(u, p):
    d = u.reshape(-1, 2)[p.b // 2] - u.reshape(-1, 2)[p.a // 2]
    return np.einsum("ka,ka->k", d, p.n), np.einsum("ka,ka->k", d, p.t)


@pytest.mark.parametrize("perfect_n,perfect_t", [(True, True), (True, False), (False, True), (False, False)])
@pytest.mark.parametrize("prescribe_b", [False, True])
def test_perfect_directions_hold_exactly_for_any_unknowns(perfect_n, perfect_t, prescribe_b):
    """Jump-unknown path (free pairs) and general path (a pair touching a support)."""
    rng = np.random.default_rng(0)
    ndof = 24
    p = pairs_of([0, 2, 4], [12, 14, 16], 37.0, perfect_n, perfect_t)
    presc, vals = ([13], [0.25]) if prescribe_b else ([], [])      # y-DOF of the first body-b node
    el = build_elimination(ndof, p, prescribed=presc, values=vals, scale=1.0)
    for _ in range(3):
        u = el.expand(rng.normal(size=el.T.shape[1]))
        jn, jt = jumps(u, p)
        if perfect_n:
            np.testing.assert_allclose(jn, 0.0, atol=1e-15)
        if perfect_t:
            np.testing.assert_allclose(jt, 0.0, atol=1e-15)
        if prescribe_b:
            assert u[13] == pytest.approx(0.25, abs=1e-15)
    # unknowns: 2 per node minus constrained directions minus prescribed values
    expected = ndof - 3 * (perfect_n + perfect_t) - len(presc)
    assert el.T.shape[1] == expected
    # finite directions keep their freedom: the jump map G has full rank on them
    if not perfect_n and not perfect_t and not prescribe_b:
        assert np.linalg.matrix_rank(el.T.toarray()) == ndof


def test_ties_propagate_supports_and_conflicts_are_rejected():
    p = pairs_of([0], [2], 0.0, True, True)
    el = build_elimination(4, p, prescribed=[0, 1], values=[0.1, -0.2], scale=1.0)
    u = el.expand(np.zeros(el.T.shape[1]))
    np.testing.assert_allclose(u, [0.1, -0.2, 0.1, -0.2])
    with pytest.raises(CaseError, match="conflicting"):
        build_elimination(4, p, prescribed=[0, 2], values=[0.1, 0.3], scale=1.0)
    pn = pairs_of([0], [2], 90.0, True, False)      # normal along y, both nodes fixed in y differently
    with pytest.raises(CaseError, match="perfect interface"):
        build_elimination(4, pn, prescribed=[0, 1, 2, 3], values=[0, 0, 0, 0.5], scale=1.0)


def test_one_direction_constraints_at_a_shared_node():
    """Node 0 faces node 1 across a y-normal interface and node 2 across an x-normal one (a
    corner shared by two one-direction perfect interfaces): both hold exactly."""
    n = np.array([[0.0, 1.0], [1.0, 0.0]])
    t = np.array([[-1.0, 0.0], [0.0, 1.0]])
    p = NodePairs(np.array([0, 0]), np.array([2, 4]), n, t, np.array([True, True]), np.array([True, True]),
                  np.array([False, False]))
    el = build_elimination(6, p, prescribed=[], values=[], scale=1.0)
    u = el.expand(np.random.default_rng(1).normal(size=el.T.shape[1]))
    jn, _ = jumps(u, p)
    np.testing.assert_allclose(jn, 0.0, atol=1e-15)
    assert el.T.shape[1] == 4


def test_chained_one_direction_constraints_are_refused():
    n = np.array([[1.0, 0.0], [1.0, 0.0]])
    t = np.array([[0.0, 1.0], [0.0, 1.0]])
    p = NodePairs(np.array([0, 2]), np.array([2, 4]), n, t, np.array([True, True]), np.array([True, True]),
                  np.array([False, False]))
    with pytest.raises(CaseError, match="chained"):
        build_elimination(6, p, prescribed=[], values=[], scale=1.0)
