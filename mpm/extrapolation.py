"""Nodal displacement of each material at its multimaterial nodes, to first order.

000 Eq 13 takes the separation of two materials at a node as the difference of their
extrapolated displacements u_k,i = sum_p S_ip m_p u_p / m_k,i. That is a Shepard
average: for a displacement field that is linear near the node it equals the field at
the material's mass centroid X_k,i (= position - displacement, reference frame), which
lies about 0.4 cell inside the material (uGIMP, 2 particles per cell), not at the
node. The two centroids of an interface node are about one cell apart, so any
continuous displacement gradient enters the jump: a rigid rotation theta of the
specimen adds theta x 0.8 h to the tangential jump, and the shear strain adds
2 c tau / G. On the two-layer shear block (000 Fig 4A, 0.25 mm cells) the bending
rotation makes the interfacial energy 8-9 % too high at Dt = 100 MPa/mm, while the
strain energy is right to 0.2 % (evaluating the converged FEM field at the
centroids gives the same bias).

:func:`displacement_to_nodes` removes that first-order error: along every axis d on
which the centroid is off the node, the slope of the field is taken from the
neighbouring node on the material's side; with one neighbour per axis the gradient G
solves (X_k,i - X_k,j) G^T = (u_k,i - u_k,j) over those neighbours j, and the field is
extrapolated from its centroid to the node,

    u_k(x_i) = u_k,i + G (x_i - X_k,i),

exact for a displacement field linear near the node (with fewer neighbours, the
slopes along the available axes). For a node whose neighbour does not
hold the material (thin layers, corners) the Eq 13 average is kept. Nodes where a
contact pair (stick, friction) meets keep the Eq 13 average too: contact is detected
from the sign of the normal separation, and the centroid gap (negative in compression,
like the offset of Eq 14) decides it robustly, where the node value is zero to
round-off for bodies in contact. The option ``nodal_displacement = "average"``
restores 000 Eq 13 everywhere.
"""
from __future__ import annotations

import numpy as np

from interfaces.jit import FMA, njit

from .multimaterial_constants import LAW_IMPERFECT, LAW_NONE, LAW_PERFECT
from .multimaterial_kernels import _pair_law
from .shape import SHAPE_CODES, shape_2d

#: nodal displacement estimates at multimaterial nodes: 000 Eq 13 (centroid average)
#: or its first-order extrapolation to the node
NODAL_DISPLACEMENT_CODES = {"average": 0, "linear": 1}


@njit(cache=True, inline="always")
def _solve_in_place(A, B, D) -> bool:
    """Solve A X = B for the leading D x D block (D <= 3) by Gaussian elimination with
    partial pivoting, X written into B (A is destroyed). No allocation: np.linalg.solve
    per node and material was most of this kernel's time. False if A is singular."""
    for c in range(D):
        piv = c
        for r in range(c + 1, D):
            if abs(A[r, c]) > abs(A[piv, c]):
                piv = r
        if A[piv, c] == 0.0:
            return False
        if piv != c:
            for e in range(D):
                A[c, e], A[piv, e] = A[piv, e], A[c, e]
                B[c, e], B[piv, e] = B[piv, e], B[c, e]
        for r in range(c + 1, D):
            fac = A[r, c] / A[c, c]
            for e in range(c, D):
                A[r, e] -= fac * A[c, e]
            for e in range(D):
                B[r, e] -= fac * B[c, e]
    for c in range(D - 1, -1, -1):
        for e in range(D):
            acc = B[c, e]
            for r in range(c + 1, D):
                acc -= A[c, r] * B[r, e]
            B[c, e] = acc / A[c, c]
    return True


@njit(cache=True, fastmath=FMA, error_model="numpy")
def displacement_to_nodes(mass, displacement, position, nodes, origin, cell, nn, law_kind,
                          law_params, node_zone, zone_pairs, zone_kind, zone_params, work):
    """Replace ``displacement[i, k]`` at the multimaterial ``nodes`` by the first-order
    extrapolation of material k's field from its mass centroid to node i (module doc).

    ``mass[N, M]``, ``displacement``/``position[N, M, D]`` as extrapolated by P2G (000
    Eq 10, 13; mpm/LAYOUT.md), node n at ``origin + index * cell`` with the flattened
    index n = i + nn[0] (j + nn[1] k). The pair laws (``law_kind``, ``law_params`` and
    the zone arrays of :class:`mpm.multimaterial.MultimaterialTables`) exclude contact
    nodes. ``work[len(nodes), M, D]`` receives the corrections (all are computed from the
    uncorrected averages before any is applied). Returns the number of (node,
    material) pairs corrected.
    """
    N, M, D = displacement.shape
    count = 0
    idx = np.empty(D, np.int64)
    law = np.empty(4)
    off = np.empty(D)
    A = np.empty((D, D))      # rows: centroid differences to the neighbours (reference)
    B = np.empty((D, D))      # rows: displacement differences
    axis = np.empty(D, np.int64)
    for a in range(nodes.size):
        n = nodes[a]
        for f in range(M):
            for c in range(D):
                work[a, f, c] = 0.0
        contact = False
        for f in range(M):
            for g in range(f + 1, M):
                if mass[n, f] > 0.0 and mass[n, g] > 0.0:
                    code = _pair_law(n, f, g, law_kind, law_params, node_zone, zone_pairs,
                                     zone_kind, zone_params, law)
                    if code != LAW_IMPERFECT and code != LAW_PERFECT and code != LAW_NONE:
                        contact = True
        if contact:
            continue
        rest = n
        for d in range(D):
            idx[d] = rest % nn[d]
            rest //= nn[d]
        for f in range(M):
            if mass[n, f] <= 0.0:
                continue
            needed = False
            for d in range(D):
                off[d] = position[n, f, d] - displacement[n, f, d] - (origin[d] + idx[d] * cell[d])
                if abs(off[d]) >= 1e-6 * cell[d]:
                    needed = True
            if not needed:
                continue
            # one neighbour per axis holding the material's interior: on the centroid's
            # side (towards the particles) or, for an axis the centroid is not off, either
            rows = 0
            stride = 1
            for d in range(D):
                first = 1 if off[d] > 0.0 else -1
                for attempt in range(2):
                    step = first if attempt == 0 else -first
                    if attempt == 1 and abs(off[d]) >= 1e-6 * cell[d]:
                        break
                    k = idx[d] + step
                    if k < 0 or k >= nn[d]:
                        continue
                    m = n + step * stride
                    if mass[m, f] <= 0.0:
                        continue
                    skew = 0.0
                    for e in range(D):
                        A[rows, e] = position[n, f, e] - displacement[n, f, e] \
                            - (position[m, f, e] - displacement[m, f, e])
                        B[rows, e] = displacement[n, f, e] - displacement[m, f, e]
                        if e != d:
                            skew = max(skew, abs(A[rows, e]) / cell[e])
                    if abs(A[rows, d]) < 0.25 * cell[d] or skew > 0.25:
                        continue  # the neighbour holds only the material's edge
                    axis[rows] = d
                    rows += 1
                    break
                stride *= nn[d]
            if rows == D:
                # full gradient: A G^T = B (B then holds G^T), exact for a linear field;
                # A cannot be singular (each row is dominated by its own axis, above)
                if _solve_in_place(A, B, D):
                    for c in range(D):
                        s = 0.0
                        for e in range(D):
                            s += off[e] * B[e, c]
                        work[a, f, c] = -s
                    count += 1
            elif rows > 0:
                # slopes along the available axes only
                for r in range(rows):
                    d = axis[r]
                    for c in range(D):
                        work[a, f, c] -= B[r, c] / A[r, d] * off[d]
                count += 1
    for a in range(nodes.size):
        n = nodes[a]
        for f in range(M):
            for c in range(D):
                displacement[n, f, c] += work[a, f, c]
    return count


@njit(cache=True)
def _p2g_volume(x, field, V, origin, cell, nn, lp, kind, volume, gradient):
    idx = np.empty(9, dtype=np.int64)
    S = np.empty(9)
    G = np.empty((9, 2))
    for p in range(x.shape[0]):
        c = shape_2d(x[p, 0], x[p, 1], origin, cell, nn, lp, kind, idx, S, G)
        if c < 0:
            return p
        f = field[p]
        for q in range(c):
            volume[idx[q], f] += S[q] * V
            gradient[idx[q], f, 0] += G[q, 0] * V
            gradient[idx[q], f, 1] += G[q, 1] * V
    return -1


def field_volumes(x: np.ndarray, field: np.ndarray, n_fields: int, origin, cell, nn,
                  spacing, shape: str = "ugimp") -> tuple[np.ndarray, np.ndarray]:
    """Nodal volume Omega_i = sum_p S_ip V_p (000 Eq 19) and volume gradient
    sum_p G_ip V_p (000 Eq 33) of each material field, for a 2D particle set of
    spacing ``spacing`` (V_p = spacing_x spacing_y, unit thickness, uGIMP half-width
    spacing / 2), with the solver's shape functions (:mod:`mpm.shape`).

    The inputs of the normals of 000 Sec 2.6 (MVG, AVG, RMVG) and of the contact-area
    of Eq 20, e.g. to study normals on a particle cloud without running the solver.
    Returns ``(volume[N, M], gradient[N, M, 2])``; raises ValueError if a particle's
    support leaves the grid.
    """
    spacing = np.broadcast_to(np.asarray(spacing, float), (2,))
    nn = np.asarray(nn, np.int64)
    N = int(np.prod(nn))
    volume = np.zeros((N, n_fields))
    gradient = np.zeros((N, n_fields, 2))
    lost = _p2g_volume(np.ascontiguousarray(x, dtype=float), np.asarray(field, dtype=np.int64),
                       float(spacing[0] * spacing[1]), np.asarray(origin, float),
                       np.asarray(cell, float), nn, 0.5 * spacing, SHAPE_CODES[shape],
                       volume, gradient)
    if lost >= 0:
        raise ValueError(f"particle {lost} at {x[lost]} has shape-function support outside "
                         f"the grid (origin {origin}, {nn.tolist()} nodes of {cell})")
    return volume, gradient
