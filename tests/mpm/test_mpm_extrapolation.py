"""Nodal displacements of each material at multimaterial nodes (mpm/extrapolation.py).

Reference: a displacement field that is linear on each side of a straight interface
(a jump plus a common gradient, e.g. a rigid rotation). 000 Eq 13 (mass-weighted
average of the particles) returns the field at the material's centroid, so the nodal
jump picks up grad u x (centroid gap); the first-order extrapolation must return the
exact field at the node.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from mpm.extrapolation import displacement_to_nodes, field_volumes
from mpm.kernels import multimaterial_nodes
from mpm.multimaterial_constants import LAW_IMPERFECT, LAW_STICK, N_PARAMS
from mpm.shape import SHAPE_CODES, shape_2d

CELL = 0.5
NN = np.array([17, 13], np.int64)
ORIGIN = np.array([-1.5, -1.5])


def _particles(ppc: int = 2):
    """Two blocks [0, 3] x [0, 3] and [3, 6] x [0, 3], interface on the node line x = 3."""
    h = CELL / ppc
    xs = np.arange(h / 2, 6.0, h)
    ys = np.arange(h / 2, 3.0, h)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    x0 = np.column_stack([X.ravel(), Y.ravel()])
    field = (x0[:, 0] > 3.0).astype(np.int64)
    return x0, field, h


def _extrapolate(x0, u, field, h):
    """P2G of mass, displacement and position per field (000 Eq 10, 13), unit density."""
    N = int(NN.prod())
    mass = np.zeros((N, 2))
    disp = np.zeros((N, 2, 2))
    pos = np.zeros((N, 2, 2))
    idx, S, G = np.empty(9, np.int64), np.empty(9), np.empty((9, 2))
    lp = np.full(2, h / 2)
    x = x0 + u
    for p in range(len(x)):
        c = shape_2d(x[p, 0], x[p, 1], ORIGIN, np.full(2, CELL), NN, lp, SHAPE_CODES["ugimp"],
                     idx, S, G)
        f = field[p]
        for q in range(c):
            mass[idx[q], f] += S[q]
            disp[idx[q], f] += S[q] * u[p]
            pos[idx[q], f] += S[q] * x[p]
    has = mass > 0
    disp[has] /= mass[has][:, None]
    pos[has] /= mass[has][:, None]
    return mass, disp, pos


def _tables(kind: int):
    law_kind = np.array([[0, kind], [kind, 0]], np.int64)
    return (law_kind, np.zeros((2, 2, N_PARAMS)), np.zeros(0, np.int64),
            np.zeros((0, 2), np.int64), np.zeros(0, np.int64), np.zeros((0, N_PARAMS)))


def _field(x0, field, jump, grad):
    """u = grad x (common to both materials) + jump on material 1."""
    return x0 @ np.asarray(grad).T + np.where(field[:, None] == 1, jump, 0.0)


@pytest.mark.parametrize("grad", [[[0.0, -2e-3], [2e-3, 0.0]],     # rigid rotation
                                  [[1e-3, 4e-3], [-3e-3, 2e-3]]])    # general gradient
def test_linear_fields_give_the_exact_jump_at_interface_nodes(grad):
    x0, field, h = _particles()
    jump = np.array([0.0, 1e-3])
    u = _field(x0, field, jump, grad)
    mass, disp, pos = _extrapolate(x0, u, field, h)
    nodes = multimaterial_nodes(mass)
    node_x = ORIGIN + np.column_stack([nodes % NN[0], nodes // NN[0]]) * CELL
    # the interface node line (a displaced particle can also put a tail on x = 2.5 / 3.5)
    line = np.isclose(node_x[:, 0], 3.0)
    inside = line & (node_x[:, 1] > 0.25) & (node_x[:, 1] < 2.75)   # not the free corners
    assert line.sum() >= 7 and inside.sum() == 5
    average = (disp[nodes, 1] - disp[nodes, 0])[inside]
    # 000 Eq 13: the centroids are ~0.19 mm either side of the node -> grad x 0.375
    centroid = pos[nodes] - disp[nodes]                         # reference centroids
    gap = (centroid[:, 1] - centroid[:, 0])[inside]
    assert np.allclose(gap[:, 0], 0.375, atol=1e-3)
    np.testing.assert_allclose(average, jump + gap @ np.asarray(grad).T, rtol=1e-9, atol=1e-15)
    assert np.abs(average - jump).max() > 0.3 * np.abs(jump).max() * (np.abs(grad).max() / 5e-3)
    count = displacement_to_nodes(mass, disp, pos, nodes, ORIGIN, np.full(2, CELL), NN,
                                  *_tables(LAW_IMPERFECT), np.empty((nodes.size, 2, 2)))
    assert count >= 2 * line.sum()
    exact = np.asarray(grad) @ node_x.T
    for f in (0, 1):
        want = exact.T + (jump if f == 1 else 0.0)
        np.testing.assert_allclose(disp[nodes, f][inside], want[inside], atol=1e-12)
    # at the free corners (y = 0, 3) the field is extrapolated along y as well
    np.testing.assert_allclose((disp[nodes, 1] - disp[nodes, 0])[line],
                               np.broadcast_to(jump, (line.sum(), 2)), atol=1e-12)


def test_contact_nodes_keep_the_centroid_gap():
    """Stick/friction pairs detect contact from the sign of the normal separation; the
    centroid gap (negative in compression) must reach them unchanged."""
    x0, field, h = _particles()
    u = _field(x0, field, np.zeros(2), [[-1e-3, 0.0], [0.0, 0.0]])   # uniform compression
    mass, disp, pos = _extrapolate(x0, u, field, h)
    nodes = multimaterial_nodes(mass)
    before = disp.copy()
    count = displacement_to_nodes(mass, disp, pos, nodes, ORIGIN, np.full(2, CELL), NN,
                                  *_tables(LAW_STICK), np.empty((nodes.size, 2, 2)))
    assert count == 0 and np.array_equal(disp, before)
    node_x = ORIGIN + np.column_stack([nodes % NN[0], nodes // NN[0]]) * CELL
    line = np.isclose(node_x[:, 0], 3.0)
    assert np.all((disp[nodes, 1, 0] - disp[nodes, 0, 0])[line] < 0)


def test_field_volumes_sum_to_the_particle_volume_and_gradients_to_zero():
    """Partition of unity: sum_i Omega_i = total particle volume per field; the volume
    gradients of a closed body sum to zero (sum_i G_ip = 0)."""
    x0, field, h = _particles()
    vol, grad = field_volumes(x0, field, 2, ORIGIN, np.full(2, CELL), NN, h)
    assert vol[:, 0].sum() == pytest.approx(9.0, rel=1e-12)
    assert vol[:, 1].sum() == pytest.approx(9.0, rel=1e-12)
    np.testing.assert_allclose(grad.sum(axis=0), 0.0, atol=1e-12)
    with pytest.raises(ValueError, match="outside the grid"):
        field_volumes(x0 + 10.0, field, 2, ORIGIN, np.full(2, CELL), NN, h)
    assert math.isfinite(vol.max())
