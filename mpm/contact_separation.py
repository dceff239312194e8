"""Edge distance of a material domain from its extrapolated position, d(x), 004 Fig 1B.

A material alpha occupies the half-line x <= x_edge; node i sits at x_i = 0. The node
sees the extrapolated particle centre x^alpha_i = sum_p S_ip m_p x_p / sum_p S_ip m_p
(004 Eq 11), which lies inside the material, not at its edge. For undeformed particles
(``ppc`` per cell, half-width l_p = h / (2 ppc), equal masses) the signed distance
d = x_edge - x_i from the node to the edge is a function of s = x^alpha_i - x_i alone:
computed here exactly, by sweeping the edge across the node's support. Material beta,
approaching from the other side, has d_beta(s) = -d(-s). Then (004 Eq 15)

    touching  <=>  d_beta((x^beta_i - x_i) . n) - d((x^alpha_i - x_i) . n) < 0

("DF", d(x) fitting: here the curve itself, not a fit). A straight-line fit
d = a s + b turns this into the critical offset of Eq 16-17, delta_c = 2 b / a
(004: 0.92 for GIMP, 0.96 for CPDI at two particles per cell).

Lengths are in cells (h = 1). Shapes: the MPM shape codes of ``mpm.shape``: linear,
uGIMP, B2, and the undeformed CPDI shapes (mpm/cpdi.py; in 1D the mean of N_i at the
two particle corners x_p +- l_p), ``cpdi`` on linear and ``b2cpdi`` on quadratic B-spline
grid functions.
"""
from __future__ import annotations

import numpy as np

from interfaces.errors import CaseError
from interfaces.jit import njit

from .shape import B2, B2CPDI, CPDI, LINEAR, SHAPE_CODES, UGIMP, gimp_1d

CURVE_SHAPES = SHAPE_CODES
#: samples of the tabulated curve handed to the contact kernels
TABLE_POINTS = 513


@njit(cache=True)
def _grid_weight(r: float, kind: int) -> float:
    """Grid function N_i at distance r (cells): linear hat or quadratic B-spline."""
    a = abs(r)
    if kind == B2:
        if a < 0.5:
            return 0.75 - a * a
        return 0.5 * (1.5 - a) ** 2 if a < 1.5 else 0.0
    return max(0.0, 1.0 - a)


@njit(cache=True)
def _node_weight(r: float, kind: int, lp: float) -> float:
    """S_ip of node i at distance r = x_p - x_i (cells) for one particle."""
    if kind == LINEAR or kind == B2:
        return _grid_weight(r, kind)
    if kind == UGIMP:
        return gimp_1d(r, 1.0, lp)[0]
    corner = B2 if kind == B2CPDI else LINEAR      # CPDI: mean over the two corners
    return 0.5 * (_grid_weight(r - lp, corner) + _grid_weight(r + lp, corner))


@njit(cache=True)
def _sweep(edges: np.ndarray, kind: int, ppc: int):
    """x^alpha_i - x_i and the node's mass share for each edge position."""
    lp = 0.5 / ppc
    s = np.full(edges.shape[0], np.nan)
    w = np.zeros(edges.shape[0])
    for e in range(edges.shape[0]):
        sm, sx = 0.0, 0.0
        for k in range(8 * ppc):              # particles within 4 cells of the edge
            xp = edges[e] - lp - 2.0 * lp * k
            S = _node_weight(xp, kind, lp)
            sm += S
            sx += S * xp
        w[e] = sm
        if sm > 1e-14:
            s[e] = sx / sm
    return s, w


def edge_distance_curve(shape: str = "ugimp", ppc: int = 2, samples: int = 4001):
    """(s, d): the extrapolated position of material alpha relative to the node and the
    node's distance to alpha's edge, both in cells, over the range where s rises
    (from the first particle touching the node's support to full cover, s -> 0)."""
    if shape not in CURVE_SHAPES:
        raise CaseError(f"shape must be one of {sorted(CURVE_SHAPES)}, got {shape!r}")
    if not isinstance(ppc, (int, np.integer)) or not 1 <= ppc <= 8:
        raise CaseError(f"ppc must be an integer in [1, 8], got {ppc!r}")
    kind = CURVE_SHAPES[shape]
    lp = 0.5 / ppc if kind != LINEAR else 0.0
    reach = 1.5 if kind in (B2, B2CPDI) else 1.0
    edges = np.linspace(-reach - lp, reach + lp + 0.5, samples)
    s, w = _sweep(edges, kind, ppc)
    ok = w > 1e-14
    s, d = s[ok], edges[ok]
    rising = np.concatenate([[True], np.diff(s) > 1e-12])
    return s[rising], d[rising]


def critical_separation(shape: str = "ugimp", ppc: int = 2) -> float:
    """delta_c = 2 b / a of the least-squares line d = a s + b through the whole curve,
    sampled uniformly in d (004 Eq 17, the "CP = delta_c" of Fig 1B)."""
    s, d = edge_distance_curve(shape, ppc)
    dd = np.linspace(d[0], d[-1], 2001)
    a, b = np.polyfit(np.interp(dd, d, s), dd, 1)
    return float(2.0 * b / a)


def separation_table(shape: str, ppc: int) -> tuple[float, float, np.ndarray]:
    """The curve d(s) on a uniform grid of s for the kernels: (s0, ds, d values).
    Beyond the ends the kernel holds the end values (s below s0: the node is past the
    edge by at least the support; s above the top: the node is inside the material)."""
    s, d = edge_distance_curve(shape, ppc)
    grid = np.linspace(s[0], s[-1], TABLE_POINTS)
    return float(grid[0]), float(grid[1] - grid[0]), np.interp(grid, s, d)
