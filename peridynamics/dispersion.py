"""Plane waves on the infinite CPD lattice: the stiffness of the linearised energy per wave vector.

The discrete CPD energy of one material (003 Eq 7, 10; the forms of :mod:`peridynamics.kernels`)
on an infinite square / simple cubic lattice of spacing h, linearised about the reference
configuration, is a quadratic form in the displacements. A plane wave
u(X) = a cos(q . X) stores on average 1/2 a . D(q) a per lattice point, with

    D(q) = V_p [ sum_i 1/4 C1 V_i |s_i|^2 n_i n_i^T / L_i
               + sum_{i<j} 1/3 C2 A V_i V_j conj(g_ij) g_ij^T
               + sum_{i<j<k} 3/4 C3 |V| V_i V_j V_k conj(g_ijk) g_ijk^T ]

where s_i = exp(i q . xi_i) - 1, and g_ij, g_ijk are the linearised a/A - 1 and v/V - 1 of
the tuple per unit wave amplitude (degenerate tuples, A = 0 or V = 0, carry no energy, as in
the kernels). D(q) is the lattice counterpart of the acoustic tensor: as q -> 0 it tends
to V_p q^2 / 2 times the moduli the tuples give a uniform strain
(:func:`peridynamics.parameters.lattice_ratios` measures the same on the kernels), and
(K u)_p = 2 D(q) a cos(q . X_p) for the exact tangent K of the kernels. An eigenvalue of
D(q) below zero is a wave of negative energy: the material is unstable at that wavelength,
and every body large enough to hold such a wave away from its supports has a tangent with
negative eigenvalues (003 Sec 4.5 material A, nu = 0.1, C3 < 0: docs/cpd_stability.md).

Written from 003 Eq 7, 10 with numpy alone (of the kernels only their horizon and
degeneracy thresholds), so it checks the kernels' tangent at finite wavelengths
independently (tests/peridynamics/test_peridynamics_dispersion.py).
"""
from __future__ import annotations

import itertools
import math
from functools import lru_cache

import numpy as np

from interfaces.errors import CaseError

from .kernels import DEGENERATE_TOL, horizon_radius2


def lattice_horizon(h: float, delta: float, dim: int) -> np.ndarray:
    """Bond vectors xi of one lattice point to its neighbours within the horizon (|xi| <= delta)."""
    if dim not in (2, 3):
        raise CaseError(f"dim must be 2 or 3, got {dim}")
    if not (h > 0 and delta > h):
        raise CaseError(f"need 0 < h < delta, got h = {h:g}, delta = {delta:g}")
    m = int(math.ceil(delta / h))
    r2 = horizon_radius2(delta) / (h * h)       # the kernels' horizon membership
    off = [o for o in itertools.product(range(-m, m + 1), repeat=dim) if 0 < np.dot(o, o) <= r2]
    return np.array(off, dtype=float) * h


def _cross2(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _rot(v: np.ndarray) -> np.ndarray:
    """R(v) with w x v = w . R(v) for the 2D scalar cross product."""
    return np.stack([v[..., 1], -v[..., 0]], axis=-1)


def _pairs(xi: np.ndarray, s: np.ndarray, C1: float, Vp: float) -> np.ndarray:
    L = np.linalg.norm(xi, axis=1)
    n = xi / L[:, None]
    return np.einsum("i,ij,ik->jk", 0.25 * C1 * Vp * Vp * np.abs(s) ** 2 / L, n, n)


def _triples(xi: np.ndarray, s: np.ndarray, C2: float, Vp: float) -> np.ndarray:
    dim = xi.shape[1]
    i, j = np.triu_indices(len(xi), 1)
    a, b = xi[i], xi[j]
    scale = np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1)
    if dim == 2:
        c = _cross2(a, b)
        keep = np.abs(c) > DEGENERATE_TOL * scale
        A = np.abs(c[keep])
        g = (s[i][keep, None] * _rot(b[keep]) - s[j][keep, None] * _rot(a[keep])) / c[keep, None]
    else:
        c = np.cross(a, b)
        A = np.linalg.norm(c, axis=1)
        keep = A > DEGENERATE_TOL * scale
        A, c, a, b = A[keep], c[keep], a[keep], b[keep]
        g = (s[i][keep, None] * np.cross(b, c) + s[j][keep, None] * np.cross(c, a)) / (A * A)[:, None]
    w = (1.0 / 3.0) * C2 * A * Vp ** 3
    return np.einsum("t,tj,tk->jk", w, np.conj(g), g).real


def _quadruples(xi: np.ndarray, s: np.ndarray, C3: float, Vp: float) -> np.ndarray:
    out = np.zeros((3, 3))
    L = np.linalg.norm(xi, axis=1)
    N = len(xi)
    for i in range(N - 2):                       # i < j < k, one first vertex at a time
        j, k = np.triu_indices(N - i - 1, 1)
        j += i + 1
        k += i + 1
        a, b, c = xi[i], xi[j], xi[k]
        bc = np.cross(b, c)
        V = bc @ a
        keep = np.abs(V) > DEGENERATE_TOL * L[i] * L[j] * L[k]
        j, k, V, b, c, bc = j[keep], k[keep], V[keep], b[keep], c[keep], bc[keep]
        g = (s[i] * bc + s[j, None] * np.cross(c, a) + s[k, None] * np.cross(a, b)) / V[:, None]
        out += np.einsum("t,tj,tk->jk", 0.75 * C3 * np.abs(V) * Vp ** 4, np.conj(g), g).real
    return out


def _parts(q: np.ndarray, C, xi: np.ndarray, Vp: float) -> tuple[np.ndarray, np.ndarray]:
    """(pair part D_1(q), whole D(q)) on the horizon ``xi``."""
    C1, C2, C3 = (float(c) for c in C)
    s = np.exp(1j * (xi @ q)) - 1.0
    pairs = _pairs(xi, s, C1, Vp)
    D = pairs
    if C2 != 0.0:
        D = D + _triples(xi, s, C2, Vp)
    if C3 != 0.0:
        if xi.shape[1] != 3:
            raise CaseError("C3 (three-neighbour interactions) needs a 3D lattice")
        D = D + _quadruples(xi, s, C3, Vp)
    return pairs, D


def wave_stiffness(q, C, h: float, delta: float) -> np.ndarray:
    """D(q) (dim x dim) of the material with constants C = (C1, C2, C3) on the lattice of
    spacing ``h`` with horizon ``delta``; q the wave vector (1/mm). Point volumes h^dim."""
    q = np.asarray(q, dtype=float)
    return _parts(q, C, lattice_horizon(h, delta, q.size), h ** q.size)[1]


def softest_wave(C, h: float, delta: float, dim: int, samples: int = 9) -> tuple[float, np.ndarray]:
    """Smallest eigenvalue of D(q) over the irreducible zone of the lattice (``samples`` wave
    numbers per axis up to pi / h), divided by the largest eigenvalue of the pair part D_1(q)
    there (a dimensionless margin: negative = a wave of negative energy), and its q."""
    xi = lattice_horizon(h, delta, dim)
    best = (math.inf, np.zeros(dim))
    for idx in itertools.product(range(samples + 1), repeat=dim):
        if idx[0] == 0 or any(idx[k] > idx[k - 1] for k in range(1, dim)):
            continue                              # q_x >= q_y (>= q_z) > 0: the cubic wedge
        q = np.array(idx, dtype=float) * math.pi / (h * samples)
        pairs, D = _parts(q, C, xi, h ** dim)
        margin = np.linalg.eigvalsh(D)[0] / np.linalg.eigvalsh(pairs)[-1]
        if margin < best[0]:
            best = (margin, q)
    return best


@lru_cache(maxsize=64)
def _margin(C: tuple, h: float, delta: float, dim: int) -> tuple[float, tuple]:
    margin, q = softest_wave(C, h, delta, dim, samples=3 if dim == 3 else 8)
    return margin, tuple(q)


def unstable_materials(constants: dict, h: float, delta: float, dim: int) -> list[str]:
    """One message per material (``constants``: name -> {"C1", "C2", "C3"}) whose negative
    C2 or C3 lets a wave on this lattice store negative energy (:func:`softest_wave`, coarse
    zone sampling); materials with C2, C3 >= 0 are stable and not scanned."""
    out = []
    for name, c in constants.items():
        C = (float(c["C1"]), float(c["C2"]), float(c["C3"]))
        if C[1] >= 0.0 and C[2] >= 0.0:
            continue
        margin, q = _margin(C, float(h), float(delta), dim)
        if margin < 0.0:
            wavelength = 2.0 * math.pi / float(np.linalg.norm(q))
            out.append(f"CPD: material of body {name} (C1 = {C[0]:.4g}, C2 = {C[1]:.4g}, C3 = {C[2]:.4g}) "
                       f"stores negative energy in waves of wavelength {wavelength:.3g} mm on this lattice "
                       f"(margin {margin:+.3f}): a body a few wavelengths across has negative tangent "
                       "eigenvalues and Newton may not converge; raise its Poisson ratio (3D: C3 >= 0 "
                       "at nu >= 0.25) or keep the body small (docs/cpd_stability.md)")
    return out
