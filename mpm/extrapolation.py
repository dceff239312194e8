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
neighbouring node on the material's side, (u_k,i - u_k,j) / (X_k,i - X_k,j)_d, and
the field is extrapolated from its centroid to the node,

    u_k(x_i) = u_k,i + sum_d slope_d (x_i - X_k,i)_d,

exact for a displacement field linear along d. For a node whose neighbour does not
hold the material (thin layers, corners) the Eq 13 average is kept. Nodes where a
contact pair (stick, friction) meets keep the Eq 13 average too: contact is detected
from the sign of the normal separation, and the centroid gap (negative in compression,
like the offset of Eq 14) decides it robustly, where the node value is zero to
round-off for bodies in contact. The option ``nodal_displacement = "average"``
restores 000 Eq 13 everywhere.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from .multimaterial_constants import LAW_IMPERFECT, LAW_NONE, LAW_PERFECT
from .multimaterial_kernels import _pair_law

#: nodal displacement estimates at multimaterial nodes: 000 Eq 13 (centroid average)
#: or its first-order extrapolation to the node
NODAL_DISPLACEMENT_CODES = {"average": 0, "linear": 1}


@njit(cache=True, fastmath=True, error_model="numpy")
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
            corrected = False
            for d in range(D):
                xn = origin[d] + idx[d] * cell[d]
                cen = position[n, f, d] - displacement[n, f, d]
                off = cen - xn
                if abs(off) < 1e-6 * cell[d]:
                    continue
                step = 1 if off > 0.0 else -1
                k = idx[d] + step
                if k < 0 or k >= nn[d]:
                    continue
                stride = 1
                for e in range(d):
                    stride *= nn[e]
                m = n + step * stride
                if mass[m, f] <= 0.0:
                    continue
                dX = cen - (position[m, f, d] - displacement[m, f, d])
                if abs(dX) < 0.25 * cell[d]:
                    continue  # the neighbour holds only the material's edge
                for c in range(D):
                    slope = (displacement[n, f, c] - displacement[m, f, c]) / dX
                    work[a, f, c] -= slope * off
                corrected = True
            if corrected:
                count += 1
    for a in range(nodes.size):
        n = nodes[a]
        for f in range(M):
            for c in range(D):
                displacement[n, f, c] += work[a, f, c]
    return count
