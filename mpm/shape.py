"""MPM shape functions S_ip and gradients G_ip (004 Eq 2), compiled with numba.

Three tensor-product kinds, selected by an integer code so that one compiled kernel
serves all (the codes ``CPDI`` and ``B2CPDI`` name the domain-based shapes of
mpm/cpdi.py, which have their own kernels):

* ``LINEAR`` (0): classic MPM, S_ip = N_i(x_p) with bilinear (trilinear) N_i;
  2 nodes per axis.
* ``UGIMP`` (1): undeformed GIMP (Bardenhagen and Kober 2004; 004 Eq 2 with a
  box particle function chi_p of fixed half-width l_p); 3 nodes per axis.
* ``B2`` (2): the quadratic B-spline on the grid nodes (004 Sec 5; Steffen, Kirby and
  Berzins 2008), C1 across cell faces (no cell-crossing noise); 3 nodes per axis. With
  r = (x_p - x_c) / h, x_c the nearest node, the weights of the nodes c - 1, c, c + 1
  are (1/2 - r)^2 / 2, 3/4 - r^2, (1/2 + r)^2 / 2. The uniform spline is used up to
  the grid's edge (the grid keeps empty padding cells around the bodies).

All factorise into 1D functions, S_ip = S_x(x_p - x_i) S_y(y_p - y_i) (S_z), and
G_ip = (S_x' S_y, S_x S_y'). The 1D uGIMP function for cell size h and particle
half-width l_p <= h/2, with r = x_p - x_i, is

    |r| < l_p:                 1 - (r^2 + l_p^2) / (2 h l_p)
    l_p <= |r| < h - l_p:      1 - |r| / h
    h - l_p <= |r| < h + l_p:  (h + l_p - |r|)^2 / (4 h l_p)
    otherwise                  0

Ties. A particle that fills its cells (2 per cell per axis) has its uGIMP support end
and its CPDI domain corners exactly on node lines, and B2-CPDI corners on cell
midpoints, where the node beyond has weight 0 in exact arithmetic. Computed positions
land there or 1e-16 cell to either side, so round-off alone (the compiler's flags, an
input moved by 1e-15 mm) would give that node a weight of ~1e-16 or none, and a field
of any mass is present at a node for contact: in the ellipse compaction of 004 Fig 6
that lottery moved the stress at 20 % compression by 46 % for particles moved by
1e-15 mm. A point within ``SNAP`` cells of the tie is therefore put on it
(:func:`snapped`, linear and B2 weights: the point moves by at most 1e-9 cell, the same
for every node of its stencil, so the partitions of unity hold exactly), and round-off
no longer decides which nodes a particle reaches at t = 0 (later in a run a packing can
still amplify round-off: docs/mpm.md). A uGIMP support end within SNAP cells of a node
line gets the weights of the tie (:func:`ugimp_weights`): the node beyond 0, the other
two the limits l_p / h and 1 - l_p / h with slopes -+1/h, as if the whole stencil had
moved by the support end's distance to the line (both partitions of unity exact),
instead of a tail weight ~(1e-16)^2 of the particle's or none.
"""
from __future__ import annotations

import numpy as np

from interfaces.jit import FMA, njit

LINEAR = 0
UGIMP = 1
B2 = 2
#: CPDI on linear / B2 grid functions (corner-based, non tensor-product: mpm/cpdi.py)
CPDI = 3
B2CPDI = 4
SHAPE_CODES = {"linear": LINEAR, "ugimp": UGIMP, "gimp": UGIMP, "b2": B2, "cpdi": CPDI,
               "b2cpdi": B2CPDI}
#: nodes per axis touched by one particle (CPDI: by one domain corner), by shape code
NODES_PER_AXIS = (2, 3, 3, 2, 3)
#: distance (in cells) within which a point is put on a node line (linear) or a cell
#: midpoint (B2) (module docstring, "Ties")
SNAP = 1e-9


@njit(cache=True, inline="always")
def snapped(xi: float, offset: float = 0.0) -> float:
    """xi (a position in cells) put on the nearest tie k + ``offset`` (k an integer: node
    lines; ``offset`` 0.5: cell midpoints) when within SNAP of it; else xi unchanged."""
    r = np.floor(xi - offset + 0.5) + offset
    return r if abs(xi - r) < SNAP else xi


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def b2_weights(x: float, o: float, h: float):
    """Quadratic B-spline weights and d/dx of the 3 nodes i0, i0 + 1, i0 + 2 around x
    (node i0 + 1 nearest): (i0, w0, w1, w2, dw0, dw1, dw2)."""
    xi = snapped((x - o) / h, 0.5)     # ties on cell midpoints
    c = int(np.floor(xi + 0.5))
    r = xi - c                      # in [-1/2, 1/2)
    a = 0.5 - r
    b = 0.5 + r
    inv = 1.0 / h
    return c - 1, 0.5 * a * a, 0.75 - r * r, 0.5 * b * b, -a * inv, -2.0 * r * inv, b * inv


@njit(cache=True, inline="always")
def edge_kind(kind: int) -> int:
    """Shape of a surface point (where a traction acts): linear for linear and uGIMP
    (the GIMP particle function integrated over the particle's loaded edge gives the
    linear weights at the edge), the spline itself for B2 (consistent with the B2
    internal force, which integrates the spline over the body)."""
    return B2 if kind == B2 else LINEAR


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def gimp_1d(r: float, h: float, lp: float):
    """1D uGIMP weight and derivative d/dx_p for r = x_p - x_i."""
    a = abs(r)
    s = 1.0 if r >= 0.0 else -1.0
    if a < lp:
        return 1.0 - (r * r + lp * lp) / (2.0 * h * lp), -r / (h * lp)
    if a < h - lp:
        return 1.0 - a / h, -s / h
    if a < h + lp:
        d = h + lp - a
        return d * d / (4.0 * h * lp), -s * d / (2.0 * h * lp)
    return 0.0, 0.0


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def _gimp_near(r: float, h: float, lp: float):
    """:func:`gimp_1d` for the nearest node (|r| <= h/2: the inner two pieces), written
    with selects instead of branches (40 % faster weights in the hot loops)."""
    a = abs(r)
    inner = a < lp
    w = 1.0 - (r * r + lp * lp) / (2.0 * h * lp) if inner else 1.0 - a / h
    s = 1.0 if r >= 0.0 else -1.0
    dw = -r / (h * lp) if inner else -s / h
    return w, dw


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def _gimp_far(r: float, h: float, lp: float):
    """:func:`gimp_1d` for the two outer nodes of a particle (h/2 <= |r| <= 3h/2: the
    linear piece, the quadratic tail, zero), with selects."""
    a = abs(r)
    d = max(h + lp - a, 0.0)
    linear = a < h - lp
    w = 1.0 - a / h if linear else d * d / (4.0 * h * lp)
    s = 1.0 if r >= 0.0 else -1.0
    dw = -s / h if linear else -s * d / (2.0 * h * lp)
    return w, dw


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def ugimp_weights(x: float, o: float, h: float, lp: float):
    """uGIMP weights and d/dx of the 3 nodes i0, i0 + 1, i0 + 2 around x (node i0 + 1
    nearest): (i0, w0, w1, w2, dw0, dw1, dw2). A support end within SNAP cells of the
    node i0 (r0 = h + l_p) or i0 + 2 (r0 = h - l_p) gets the weights of the tie exactly
    (module docstring, "Ties"): the node beyond has w = dw = 0, the other two
    l_p / h, 1 - l_p / h and slopes -+1/h, the limits of the tail and the linear piece.
    The tie is one compare after the usual weights, selecting constants (0-6 % of a
    particle step measured, docs/mpm.md "uGIMP ties"; snapping r0 first cost 5-12 %)."""
    i0 = int(np.floor((x - o) / h + 0.5)) - 1
    r0 = x - (o + i0 * h)          # in [h/2, 3h/2): node i0 + 1 is the nearest
    w0, d0 = _gimp_far(r0, h, lp)
    w1, d1 = _gimp_near(r0 - h, h, lp)
    w2, d2 = _gimp_far(r0 - 2.0 * h, h, lp)
    if abs(abs(r0 - h) - lp) < SNAP * h:
        a = lp / h
        g = 1.0 / h
        if r0 > h:                 # left support end on node i0
            return i0, 0.0, 1.0 - a, a, 0.0, -g, g
        return i0, a, 1.0 - a, 0.0, -g, g, 0.0
    return i0, w0, w1, w2, d0, d1, d2


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def axis_weights_tuple(x: float, o: float, h: float, lp: float, kind: int):
    """1D weights of one particle along one axis as scalars:
    (i0, count, w0, w1, w2, dw0, dw1, dw2) for the nodes i0 + k, k < count.

    Linear: i0 = floor((x - o)/h), nodes i0, i0+1. uGIMP: the nodes within h + l_p of x
    (l_p <= h/2): nearest node +- 1, trimmed to 2 when an end node has zero weight
    and gradient (undeformed particles of a 2-per-cell lattice touch 2 nodes per axis).
    Unused slots are 0. Returning scalars (not filling arrays) keeps the hot particle
    loops free of numba reference-count calls on the work arrays (2x faster P2G).
    """
    if kind == LINEAR:
        xi = snapped((x - o) / h)
        i0 = int(np.floor(xi))
        r = xi - i0  # in [0, 1): the gradient is the one of the cell containing x
        return i0, 2, 1.0 - r, r, 0.0, -1.0 / h, 1.0 / h, 0.0
    if kind == B2:
        i0, w0, w1, w2, d0, d1, d2 = b2_weights(x, o, h)
        return i0, 3, w0, w1, w2, d0, d1, d2
    i0, w0, w1, w2, d0, d1, d2 = ugimp_weights(x, o, h, lp)
    if w0 == 0.0 and d0 == 0.0:
        return i0 + 1, 2, w1, w2, 0.0, d1, d2, 0.0
    if w2 == 0.0 and d2 == 0.0:
        return i0, 2, w0, w1, 0.0, d0, d1, 0.0
    return i0, 3, w0, w1, w2, d0, d1, d2


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def axis_weights3(x: float, o: float, h: float, lp: float, kind: int):
    """1D weights on a fixed 3-node stencil: (i0, w0, w1, w2, dw0, dw1, dw2) for the
    nodes i0, i0 + 1, i0 + 2, untrimmed (a node outside the support has w = dw = 0;
    linear: i0 = floor((x - o)/h) and the third node is 0). The gathers of G2P run
    over this fixed 3 x 3 stencil: a loop of constant trip count that the compiler
    unrolls is ~2x faster than the 2-or-3 node loop of :func:`axis_weights_tuple`,
    even with the zero weights; scatters keep the trimmed count (fewer stores)."""
    if kind == LINEAR:
        xi = snapped((x - o) / h)
        i0 = int(np.floor(xi))
        r = xi - i0
        return i0, 1.0 - r, r, 0.0, -1.0 / h, 1.0 / h, 0.0
    if kind == B2:
        return b2_weights(x, o, h)
    return ugimp_weights(x, o, h, lp)


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def axis_weights(x: float, o: float, h: float, lp: float, kind: int,
                 w: np.ndarray, dw: np.ndarray):
    """:func:`axis_weights_tuple` written into w[k], dw[k]; returns (i0, count)."""
    i0, c, w[0], w[1], w[2], dw[0], dw[1], dw[2] = axis_weights_tuple(x, o, h, lp, kind)
    return i0, c


@njit(cache=True)
def shape_2d(x: float, y: float, origin: np.ndarray, cell: np.ndarray, nn: np.ndarray,
             lp: np.ndarray, kind: int, idx: np.ndarray, S: np.ndarray, G: np.ndarray) -> int:
    """Nodes, S_ip and grad S_ip of one 2D particle; returns the number of nodes.

    ``idx`` (int64, >= 9), ``S`` (>= 9) and ``G`` (>= 9 x 2) are work arrays filled
    in place. Returns -1 if the particle's support leaves the grid.
    """
    wx = np.empty(3)
    dwx = np.empty(3)
    wy = np.empty(3)
    dwy = np.empty(3)
    return shape_2d_work(x, y, origin, cell, nn, lp, kind, idx, S, G, wx, dwx, wy, dwy)


@njit(cache=True, inline="always")
def stencil_work():
    """Work arrays of :func:`shape_2d_work` for a particle loop: node indices, S_ip and
    grad S_ip (9 each) and the 1D weights and gradients (wx, dwx, wy, dwy)."""
    return (np.empty(9, np.int64), np.empty(9), np.empty((9, 2)), np.empty(3), np.empty(3),
            np.empty(3), np.empty(3))


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def shape_2d_work(x, y, origin, cell, nn, lp, kind, idx, S, G, wx, dwx, wy, dwy) -> int:
    """:func:`shape_2d` with caller-provided 1D work arrays (no allocation; hot loops)."""
    i0, nax = axis_weights(x, origin[0], cell[0], lp[0], kind, wx, dwx)
    j0, nay = axis_weights(y, origin[1], cell[1], lp[1], kind, wy, dwy)
    if i0 < 0 or j0 < 0 or i0 + nax > nn[0] or j0 + nay > nn[1]:
        return -1
    c = 0
    for b in range(nay):
        row = (j0 + b) * nn[0]
        for a in range(nax):
            s = wx[a] * wy[b]
            if s == 0.0 and dwx[a] == 0.0 and dwy[b] == 0.0:
                continue
            idx[c] = row + i0 + a
            S[c] = s
            G[c, 0] = dwx[a] * wy[b]
            G[c, 1] = wx[a] * dwy[b]
            c += 1
    return c
