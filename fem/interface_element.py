"""Imperfect interface elements for static FEA (002 Sec 2.1-2.2), numpy only.

A 2n-node element joins two initially coincident surfaces (002 Fig 3): nodes
1..n lie on side 1, node i and node 2n+1-i start at the same position. Only the
side-1 coordinates ``xy`` (shape (n, 2)) are needed: n = 2 is the linear 4-node
element (002 Eq 20-25), n = 3 the quadratic 6-node element ordered end, middle,
end (002 Eq 26-29, with the corrected derivative of ERRATA 1,
x'(xi) = (x3 - x1)/2 + xi (x1 + x3 - 2 x2); curved elements are allowed).

The displacement jump is [u] = u^(1) - u^(2) (002 Eq 8-11) and its components are
taken on the side-1 frame (002 Eq 6)::

    n1 = (y', -x') / |x'|   (normal),   t1 = (x', y') / |x'|   (tangent).

With side-1 nodes ordered so that side 1 lies to the right of the direction
node 1 -> node n, n1 points into side 1 and ``jump_n > 0`` is an opening.
The element energy is 002 Eq 4 / Eq 7, phi = (t/2) int (Dn [u_n]^2 + Dt [u_t]^2) dl,
and the stiffness matrix (002 Eq 15-19) is, with the extended shape functions
N_{n+1..2n} = -N_{2n+1-i} of 002 Eq 10 and 2x2 node blocks,

    K_ij = t int_{-1}^{1} N_i N_j (Dn n1 n1^T + Dt t1 t1^T) dl/dxi dxi,

in the DOF order (u1, v1, u2, v2, ..., u2n, v2n) of 002 Eq 9. For axisymmetric
analyses t is replaced by r(xi) (the x coordinate), giving a matrix per radian.

Dn, Dt may be 0 (debonded) or negative (stiff interphase, 002 Eq 52). A perfect
direction (D = inf) has no finite stiffness matrix: ``fem.solve`` imposes it
exactly as a constraint on the nodal jumps, so ``inf`` is rejected here.

Example: a straight 4-node element of length 2 along x, side 2 shifted by a
uniform tangential slip of 0.1 (Dt = 5, t = 1): energy = 1/2 * 5 * 0.1^2 * 2.

>>> import numpy as np
>>> from fem.interface_element import stiffness, interface_energy, jumps
>>> xy = np.array([[0.0, 0.0], [2.0, 0.0]])
>>> K = stiffness(xy, Dn=100.0, Dt=5.0)
>>> K.shape
(8, 8)
>>> u = np.zeros(8); u[0::2][2:] = -0.1          # side 2 (nodes 3, 4) moves by -0.1 in x
>>> round(float(interface_energy(xy, u, Dn=100.0, Dt=5.0)), 12)
0.05
>>> jn, jt = jumps(xy, u, xi=[0.0])
>>> float(jn[0]), float(jt[0])
(0.0, 0.1)
"""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np

__all__ = [
    "shape_functions",
    "stiffness",
    "stiffness_batch",
    "jump_stiffness_batch",
    "interface_energy",
    "jumps",
    "frame",
    "DEFAULT_GAUSS_POINTS",
]

#: Gauss points per element: 2 integrates the 4-node element exactly (002 Sec 2.2);
#: the 6-node element uses 4 points as in 002 (exact for straight elements, also
#: axisymmetric ones; a curved element converges with more points).
DEFAULT_GAUSS_POINTS = {2: 2, 3: 4}


def shape_functions(n: int, xi) -> tuple[np.ndarray, np.ndarray]:
    """Side-1 shape functions N_1..N_n and derivatives dN/dxi at ``xi`` (002 Eq 20, 26).

    Returns ``(N, dN)`` each of shape (len(xi), n).
    """
    xi = np.atleast_1d(np.asarray(xi, dtype=float))
    if n == 2:
        N = np.stack([(1.0 - xi) / 2.0, (1.0 + xi) / 2.0], axis=-1)
        dN = np.stack([np.full_like(xi, -0.5), np.full_like(xi, 0.5)], axis=-1)
    elif n == 3:
        N = np.stack([-xi * (1.0 - xi) / 2.0, 1.0 - xi**2, xi * (1.0 + xi) / 2.0], axis=-1)
        dN = np.stack([xi - 0.5, -2.0 * xi, xi + 0.5], axis=-1)
    else:
        raise ValueError(f"interface element: n (nodes per side) must be 2 or 3, got {n}")
    return N, dN


def _extended(N: np.ndarray) -> np.ndarray:
    """All 2n shape functions of 002 Eq 10: N_{n+k} = -N_{n+1-k} (side 2, reversed)."""
    return np.concatenate([N, -N[:, ::-1]], axis=1)


def _check_xy(xy) -> np.ndarray:
    xy = np.asarray(xy, dtype=float)
    if xy.ndim != 3 or xy.shape[-1] != 2 or xy.shape[1] not in (2, 3):
        raise ValueError("interface element: xy must have shape (m, n, 2) with n = 2 or 3 "
                         f"side-1 nodes per element, got {xy.shape}")
    if not np.all(np.isfinite(xy)):
        raise ValueError("interface element: xy (node coordinates) must be finite")
    return xy


def _check_D(name: str, D, m: int) -> np.ndarray:
    D = np.asarray(D, dtype=float)
    if D.ndim == 0:
        D = np.full(m, float(D))
    if D.shape != (m,):
        raise ValueError(f"interface element: {name} must be a scalar or an array of shape "
                         f"({m},), got shape {D.shape}")
    if np.any(np.isnan(D)):
        raise ValueError(f"interface element: {name} must be a number, got NaN")
    if np.any(np.isinf(D)):
        raise ValueError(f"interface element: {name} = inf (perfect direction) has no finite "
                         "stiffness matrix; use fem.solve, which imposes perfect directions "
                         "exactly as constraints on the nodal jumps (or pass a finite value)")
    return D


def _quadrature(n: int, n_gauss: int | None):
    q = DEFAULT_GAUSS_POINTS[n] if n_gauss is None else int(n_gauss)
    if q < 1:
        raise ValueError(f"interface element: n_gauss must be >= 1, got {n_gauss}")
    return np.polynomial.legendre.leggauss(q)


def frame(xy, xi) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Geometry at ``xi``: position (m, q, 2), unit normal n1 and tangent t1 (m, q, 2)
    and the arc-length derivative dl/dxi (m, q) (002 Eq 12-14, ERRATA 1)."""
    xy = _check_xy(xy)
    N, dN = shape_functions(xy.shape[1], xi)
    pos = np.einsum("qi,mia->mqa", N, xy)
    d = np.einsum("qi,mia->mqa", dN, xy)                    # (x'(xi), y'(xi))
    J = np.hypot(d[..., 0], d[..., 1])
    if np.any(J <= 1e-300 * (1.0 + np.abs(xy).max())):
        raise ValueError("interface element: degenerate element (zero length, dl/dxi = 0); "
                         "check that the side-1 nodes are distinct and ordered end, middle, end")
    t1 = d / J[..., None]
    n1 = np.stack([t1[..., 1], -t1[..., 0]], axis=-1)
    return pos, n1, t1, J


def _thickness_weight(pos: np.ndarray, thickness: float, axisymmetric: bool) -> np.ndarray:
    if axisymmetric:
        r = pos[..., 0]
        if np.any(r < -1e-12 * (1.0 + np.abs(r).max())):
            raise ValueError("interface element: axisymmetric elements need r = x >= 0")
        return r
    t = float(thickness)
    if not math.isfinite(t) or t <= 0:
        raise ValueError(f"interface element: thickness must be > 0 and finite, got {thickness}")
    return np.full(pos.shape[:-1], t)


def jump_stiffness_batch(xy, Dn, Dt, thickness: float = 1.0, axisymmetric: bool = False,
                         n_gauss: int | None = None, node_frames=None) -> np.ndarray:
    """Element stiffness on the nodal jumps J_i = u_i - u_(2n+1-i), i = 1..n: (m, 2n, 2n).

    Since [u] = sum_i N_i J_i (002 Eq 8-11), phi = 1/2 J^T K_J J with
    K_J[i, j] = t int N_i N_j (Dn a_i a_j^T + Dt b_i b_j^T) dl/dxi dxi,
    a_i = R_i^T n1, b_i = R_i^T t1, where R_i = [n_i t_i] is an optional frame per node
    (``node_frames`` (m, n, 2, 2), columns normal and tangent) and the identity otherwise.
    In the interface frame of a straight element K_J is diagonal in (normal, tangential)
    parts, so a huge Dn never mixes with Dt through round-off.
    """
    xy = _check_xy(xy)
    m, n = xy.shape[:2]
    Dn = _check_D("Dn", Dn, m)
    Dt = _check_D("Dt", Dt, m)
    xi, w = _quadrature(n, n_gauss)
    N, _ = shape_functions(n, xi)
    pos, n1, t1, J = frame(xy, xi)
    weight = w[None, :] * J * _thickness_weight(pos, thickness, axisymmetric)   # (m, q)
    if node_frames is None:
        a = np.broadcast_to(n1[:, :, None, :], (m, len(xi), n, 2))
        b = np.broadcast_to(t1[:, :, None, :], (m, len(xi), n, 2))
    else:
        R = np.asarray(node_frames, dtype=float)
        if R.shape != (m, n, 2, 2):
            raise ValueError(f"interface element: node_frames must have shape {(m, n, 2, 2)}, got {R.shape}")
        a = np.einsum("miab,mqa->mqib", R, n1)                 # components of n1 in node frames
        b = np.einsum("miab,mqa->mqib", R, t1)
    K = (np.einsum("m,mq,qi,qj,mqia,mqjb->miajb", Dn, weight, N, N, a, a, optimize=True)
         + np.einsum("m,mq,qi,qj,mqia,mqjb->miajb", Dt, weight, N, N, b, b, optimize=True))
    return K.reshape(m, 2 * n, 2 * n)


def stiffness_batch(xy, Dn, Dt, thickness: float = 1.0, axisymmetric: bool = False,
                    n_gauss: int | None = None) -> np.ndarray:
    """Stiffness matrices of m interface elements at once (002 Eq 15-19).

    ``xy``: (m, n, 2) side-1 node coordinates; ``Dn``, ``Dt``: scalars or (m,) arrays
    (MPa/mm, finite, may be 0 or negative). Returns (m, 4n, 4n) in the DOF order
    (u1, v1, ..., u2n, v2n); thickness in mm (ignored when ``axisymmetric``, where
    t -> r(xi) and the matrix is per radian). With the extended shape functions of
    002 Eq 10, [N, -N P] (P reverses the node order), the matrix is
    [[K_J, -K_J P], [-P K_J, P K_J P]] with K_J from :func:`jump_stiffness_batch`.
    """
    KJ = jump_stiffness_batch(xy, Dn, Dt, thickness, axisymmetric, n_gauss)
    m, n2 = KJ.shape[:2]
    n = n2 // 2
    rev = np.arange(n)[::-1]
    P = np.stack([2 * rev, 2 * rev + 1], axis=1).ravel()      # node reversal on (x, y) DOFs
    KP = KJ[:, :, P]
    return np.concatenate([np.concatenate([KJ, -KP], axis=2),
                           np.concatenate([-KP.transpose(0, 2, 1), KJ[:, P][:, :, P]], axis=2)], axis=1)


def stiffness(xy, Dn: float, Dt: float, thickness: float = 1.0, axisymmetric: bool = False,
              n_gauss: int | None = None) -> np.ndarray:
    """Stiffness matrix (4n, 4n) of one element with side-1 nodes ``xy`` (n, 2).

    See :func:`stiffness_batch`; for n = 2 this equals the closed form 002 Eq 22-25.
    """
    xy = np.asarray(xy, dtype=float)
    if xy.ndim != 2:
        raise ValueError(f"interface element: xy must have shape (n, 2), got {xy.shape}")
    return stiffness_batch(xy[None], Dn, Dt, thickness, axisymmetric, n_gauss)[0]


def _as_batch(xy, u):
    xy = np.asarray(xy, dtype=float)
    u = np.asarray(u, dtype=float)
    single = xy.ndim == 2
    if single:
        xy = xy[None]
        u = u[None]
    xy = _check_xy(xy)
    m, n = xy.shape[:2]
    if u.shape != (m, 4 * n):
        raise ValueError(f"interface element: u must have shape {(4 * n,) if single else (m, 4 * n)}"
                         f" (u1, v1, ..., u2n, v2n), got {np.asarray(u).shape}")
    return xy, u, single


def interface_energy(xy, u, Dn, Dt, thickness: float = 1.0, axisymmetric: bool = False,
                     n_gauss: int | None = None):
    """Interface energy phi = 1/2 u^T K_I u (002 Eq 15) of each element, in N mm
    (per radian when axisymmetric). ``xy`` (n, 2) with ``u`` (4n,) gives a float;
    ``xy`` (m, n, 2) with ``u`` (m, 4n) gives an (m,) array."""
    xy, u, single = _as_batch(xy, u)
    K = stiffness_batch(xy, Dn, Dt, thickness, axisymmetric, n_gauss)
    e = 0.5 * np.einsum("mi,mij,mj->m", u, K, u)
    return float(e[0]) if single else e


def jumps(xy, u, xi: Sequence[float] | np.ndarray = (-1.0, 0.0, 1.0)):
    """Normal and tangential displacement jumps [u].n1, [u].t1 (002 Eq 6, 9) at ``xi``.

    Returns ``(jump_n, jump_t)``, each (len(xi),) for one element or (m, len(xi))
    for a batch.
    """
    xy, u, single = _as_batch(xy, u)
    n = xy.shape[1]
    xi = np.atleast_1d(np.asarray(xi, dtype=float))
    N, _ = shape_functions(n, xi)
    Ne = _extended(N)                                       # (q, 2n)
    jump = np.einsum("qi,mia->mqa", Ne, u.reshape(u.shape[0], 2 * n, 2))
    _, n1, t1, _ = frame(xy, xi)
    jn = np.einsum("mqa,mqa->mq", jump, n1)
    jt = np.einsum("mqa,mqa->mq", jump, t1)
    return (jn[0], jt[0]) if single else (jn, jt)
