"""Interface normals and the tilt length h_perp on one multimaterial node.

All functions are numba ``njit(cache=True)`` and callable from Python or from other
kernels.  Conventions: material a is the field being processed, b the other field
(or the virtual lump of all others, 000 Sec 2.2); the normal is a unit vector from a
to b (000 Fig 1).  ``g_a`` = sum_p G_ip V_p (000 Eq 33) equals -grad Omega_a, so it
points out of material a.  Each function writes the unit normal into ``out`` (length
D) and returns False when the data give no direction (zero gradient).
"""
from __future__ import annotations

import math

from interfaces.jit import njit


@njit(cache=True, refcount=False)
def _normalise_inplace(out) -> bool:
    s = 0.0
    for k in range(out.shape[0]):
        s += out[k] * out[k]
    if not (s > 0.0):
        for k in range(out.shape[0]):
            out[k] = 0.0
        return False
    inv = 1.0 / math.sqrt(s)
    for k in range(out.shape[0]):
        out[k] *= inv
    return True


@njit(cache=True, refcount=False)
def normal_sn(sn_vector, a, b, out) -> bool:
    """Specified normal (SN, 000 Sec 2.5). ``sn_vector`` points from the lower to the
    higher field index, so it is negated when a > b."""
    sign = 1.0 if a < b else -1.0
    for k in range(out.shape[0]):
        out[k] = sign * sn_vector[k]
    return _normalise_inplace(out)


@njit(cache=True, refcount=False)
def normal_mvg(g_a, g_b, out) -> bool:
    """Maximum volume gradient (MVG, 000 Sec 2.5): the normal of whichever material has
    the larger |g|; a's outward normal g_a, or -g_b (b's outward normal reversed)."""
    sa = 0.0
    sb = 0.0
    for k in range(out.shape[0]):
        sa += g_a[k] * g_a[k]
        sb += g_b[k] * g_b[k]
    if sa >= sb:
        for k in range(out.shape[0]):
            out[k] = g_a[k]
    else:
        for k in range(out.shape[0]):
            out[k] = -g_b[k]
    return _normalise_inplace(out)


@njit(cache=True, refcount=False)
def normal_avg(omega_a, g_a, omega_b, g_b, out) -> bool:
    """Average volume gradient (AVG, 000 Sec 2.5): (Omega_a g_a - Omega_b g_b) / (2 Omega)
    normalised (the 1/(2 Omega) factor drops out)."""
    for k in range(out.shape[0]):
        out[k] = omega_a * g_a[k] - omega_b * g_b[k]
    return _normalise_inplace(out)


@njit(cache=True, refcount=False)
def normal_ag(g_a, g_b, out) -> bool:
    """Average gradient (AG, 004 Eq 13): (g_a - g_b) / |g_a - g_b|."""
    for k in range(out.shape[0]):
        out[k] = g_a[k] - g_b[k]
    return _normalise_inplace(out)


@njit(cache=True, refcount=False)
def normal_rmvg(g_a, g_b, a_rigid, b_rigid, out) -> bool:
    """Rigid material volume gradient (RMVG, 000 Sec 2.5): the rigid material's own
    normal (g_a if a is rigid, -g_b if b is rigid), MVG when neither is rigid."""
    if b_rigid:
        for k in range(out.shape[0]):
            out[k] = -g_b[k]
        return _normalise_inplace(out)
    if a_rigid:
        for k in range(out.shape[0]):
            out[k] = g_a[k]
        return _normalise_inplace(out)
    return normal_mvg(g_a, g_b, out)


@njit(cache=True, refcount=False)
def any_tangent(n, out) -> None:
    """A unit vector perpendicular to the unit vector ``n`` (2D: (-n_y, n_x))."""
    if n.shape[0] == 2:
        out[0] = -n[1]
        out[1] = n[0]
        return
    # 3D: cross n with the axis least aligned with it
    ax = 0
    if abs(n[1]) < abs(n[ax]):
        ax = 1
    if abs(n[2]) < abs(n[ax]):
        ax = 2
    e0 = 1.0 if ax == 0 else 0.0
    e1 = 1.0 if ax == 1 else 0.0
    e2 = 1.0 if ax == 2 else 0.0
    out[0] = n[1] * e2 - n[2] * e1
    out[1] = n[2] * e0 - n[0] * e2
    out[2] = n[0] * e1 - n[1] * e0
    _normalise_inplace(out)


@njit(cache=True, refcount=False)
def h_perp(n, t, cell, method) -> float:
    """Effective thickness h_perp of the contact volume (000 Eq 21-22).

    ``method`` 0: no tilt correction (h = dx).  1: method 1 of 000, Eq 22 (ERRATA 9):
    2D h = sqrt(n_x^2 dx^2 + n_y^2 dy^2); 3D h = dx dy dz sqrt((sum t_i^2/dx_i^2)
    (sum s_i^2/dx_i^2)) with s = n x t.  2: method 2 of 000, the distance along n to
    the ellipse(oid) with semi-axes dx_i, h = 1 / sqrt(sum n_i^2 / dx_i^2).
    For dx = dy (= dz) every method gives dx.  ``t`` is a unit tangent (3D only).
    """
    d = n.shape[0]
    if method == 0:
        return cell[0]
    if method == 2:
        s = 0.0
        for k in range(d):
            s += n[k] * n[k] / (cell[k] * cell[k])
        return 1.0 / math.sqrt(s)
    if d == 2:
        return math.sqrt(n[0] * n[0] * cell[0] * cell[0] + n[1] * n[1] * cell[1] * cell[1])
    s0 = n[1] * t[2] - n[2] * t[1]
    s1 = n[2] * t[0] - n[0] * t[2]
    s2 = n[0] * t[1] - n[1] * t[0]
    aa = (t[0] * t[0] / (cell[0] * cell[0]) + t[1] * t[1] / (cell[1] * cell[1])
          + t[2] * t[2] / (cell[2] * cell[2]))
    bb = s0 * s0 / (cell[0] * cell[0]) + s1 * s1 / (cell[1] * cell[1]) + s2 * s2 / (cell[2] * cell[2])
    return cell[0] * cell[1] * cell[2] * math.sqrt(aa * bb)
