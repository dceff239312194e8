"""Numba kernels: CPD energy, exact residual and exact tangent (003 Eq 7, 10).

The total discrete energy of one material is (003 Eq 7 with point volumes V)

    W = sum_p V_p [ sum_i 1/2 psi1(p,i) V_i
                    + sum_{i != j} 1/3 psi2(p,i,j) V_i V_j
                    + sum_{i,j,k distinct} 1/4 psi3(p,i,j,k) V_i V_j V_k ]

over central points p and neighbours i, j, k in the horizon of p (same material),
with the harmonic potentials of 003 Eq 10

    psi1 = 1/2 C1 L (l/L - 1)^2,  psi2 = 1/2 C2 A (a/A - 1)^2,  psi3 = 1/2 C3 V (v/V - 1)^2,

l = |xi_i|, a = |xi_i x xi_j| (2D: scalar cross product), v = |(xi_i x xi_j) . xi_k|.
Ordered neighbour tuples are enumerated once as i < j (< k); the multiplicities 2 and 6
combine with 1/3 and 1/4 into the weights 2/3 and 3/2. Tuples with a vanishing reference
area / volume (collinear / coplanar neighbours) carry no energy (they have measure zero
in the continuum and psi2, psi3 are undefined for A = 0, V = 0) and are skipped.

The residual is the exact gradient dW/dx and the tangent the exact Hessian; the printed
Eq 16-18 and Appendix A of 003 are garbled (ERRATA 11) and are not used. Tuples are not
stored: they are enumerated from the neighbour lists inside the kernel (a 3D horizon of
3.01 h holds ~1.8e5 quadruples per point, far too many to keep in memory). The tangent of
one central point is accumulated in a dense local matrix over {p} + horizon(p), then
added once into a target (:func:`_scatter`): the fixed block-structured CSR pattern, or
the tangent over the free DOFs directly (``assembly.reduced_target``: no full tangent
and no second pass to reduce it). The pair (psi1) blocks are kept apart, so the pair
part of the tangent, which preconditions the Newton steps, can be added into its own
target in the same pass (:func:`_scatter_pairs`).

The helpers called once per tuple (or per pair of neighbours) are inlined into the
kernels by numba (``inline='always'``): as separate functions every call passed its arrays
with their reference counts, which took a third of the time of the 2D residual (100 x 100
points, delta = 3.01 h, set 3: residual 0.15-0.17 -> 0.11 s, tangent 0.30-0.33 ->
0.23-0.24 s on one core under load, bit-identical results).
"""
from __future__ import annotations

import numpy as np
from numba import prange

from interfaces.jit import njit

#: relative threshold below which a reference area (volume) counts as degenerate
DEGENERATE_TOL = 1e-8


def horizon_radius2(delta: float) -> float:
    """Squared radius deciding horizon membership (a relative 1e-12 keeps grid points that
    lie on the horizon radius inside it); used by the neighbour search and the kernels."""
    return (delta * (1.0 + 1e-12)) ** 2


@njit(cache=True, inline='always')
def _dist2(X, i, j):
    """Squared reference distance of nodes i and j (one compiled formula for every test)."""
    s = 0.0
    for al in range(X.shape[1]):
        t = X[i, al] - X[j, al]
        s += t * t
    return s


@njit(cache=True)
def within(X, a, b, r2):
    """Mask of the node pairs (a[k], b[k]) with |X_a - X_b|^2 <= r2."""
    out = np.empty(a.shape[0], np.bool_)
    for k in range(a.shape[0]):
        out[k] = _dist2(X, a[k], b[k]) <= r2
    return out


@njit(cache=True, inline='always')
def _find(cols, lo, hi, key):
    """Binary search of ``key`` in the sorted slice ``cols[lo:hi]``; -1 if absent."""
    while lo < hi:
        mid = (lo + hi) // 2
        v = cols[mid]
        if v < key:
            lo = mid + 1
        elif v > key:
            hi = mid
        else:
            return mid
    return -1


@njit(cache=True, inline='always')
def _add_tuple(Kloc, f_loc, slots, k, d, g, H):
    """Add a tuple's derivatives w.r.t. its relative vectors xi_m = x_m - x_p.

    ``slots[m]`` is the local node index (>= 1) of neighbour m of the tuple; local node 0
    is the central point p. ``g`` (k, d) is dpsi/dxi_m, ``H`` (k, k, d, d) the second
    derivatives. Only the neighbour rows/columns are accumulated here; since
    dxi_m/dx_p = -I for every tuple of p, the central rows and columns follow once per
    central point in :func:`_close_central`.
    """
    for m in range(k):
        a = slots[m] * d
        for al in range(d):
            f_loc[a + al] += g[m, al]
    if Kloc.shape[0] == 0:
        return
    for m in range(k):
        a = slots[m] * d
        for n in range(k):
            b = slots[n] * d
            for al in range(d):
                for be in range(d):
                    Kloc[a + al, b + be] += H[m, n, al, be]


@njit(cache=True, inline='always')
def _add_outer_2d(Kloc, i, d2, g0, g1):
    """Diagonal block d2 g g^T of a 2D triple at local rows/columns i, i + 1."""
    Kloc[i, i] += d2 * g0 * g0
    Kloc[i, i + 1] += d2 * g0 * g1
    Kloc[i + 1, i] += d2 * g0 * g1
    Kloc[i + 1, i + 1] += d2 * g1 * g1


@njit(cache=True, inline='always')
def _triple_multiplicity(D2ab, r2, qa, qb, p):
    """How often the triple (p, a, b) counts at central point p: 3 when all three vertices
    are central points of each other and p is the lowest-numbered (it is evaluated there
    only), 0 at the other two, 1 otherwise (see :func:`assemble`)."""
    if D2ab <= r2:
        if qa < p or qb < p:
            return 0.0
        return 3.0
    return 1.0


@njit(cache=True)
def _triples_2d(Kloc, f_loc, e_loc, xi, Xi, Ln, D2, nodes, vol, Vp, C2, p, r2, energy):
    """psi2 of the 2D triples (p, a, b), a < b local neighbours, with s = xi_a x xi_b: energy
    (added to the running total ``energy``, returned with the number of triples), gradient
    (into f_loc) and, unless ``Kloc`` is None, Hessian (into Kloc, neighbour slots a + 1,
    b + 1). The weights and skipped tuples are those of :func:`assemble`.

    ds/dxi_a = (xb1, -xb0), ds/dxi_b = (-xa1, xa0); block (a, b) of the Hessian is
    d2 g_a g_b^T + d1 [[0, 1], [-1, 0]]. The quantities of neighbour a (its vectors, its force
    and its diagonal block) stay in registers over the loop on b and are written back once:
    the same additions in the same order as updates in memory, but the compiler no longer
    reloads them after every store into Kloc; ``Kloc`` None (the residual alone) compiles
    without the Hessian. At 100 x 100 points, set 3, one core: residual 0.084 -> 0.032 s,
    tangent 0.16 -> 0.11 s, bit-identical.
    """
    n = xi.shape[0]
    count = 0
    e0 = e_loc[0]
    for a in range(n):
        qa = nodes[a + 1]
        wa = (2.0 / 3.0) * Vp * vol[qa] * C2
        xa0 = xi[a, 0]
        xa1 = xi[a, 1]
        Xa0 = Xi[a, 0]
        Xa1 = Xi[a, 1]
        La2 = Ln[a] * Ln[a]
        ia = 2 * (a + 1)
        fa0 = f_loc[ia]
        fa1 = f_loc[ia + 1]
        if Kloc is not None:
            kaa00 = Kloc[ia, ia]
            kaa01 = Kloc[ia, ia + 1]
            kaa10 = Kloc[ia + 1, ia]
            kaa11 = Kloc[ia + 1, ia + 1]
        for b in range(a + 1, n):
            qb = nodes[b + 1]
            mult = _triple_multiplicity(D2[a, b], r2, qa, qb, p)
            if mult == 0.0:
                continue
            w = mult * wa * vol[qb]
            tol2 = DEGENERATE_TOL * (La2 + Ln[b] * Ln[b] + D2[a, b])
            A = abs(Xa0 * Xi[b, 1] - Xa1 * Xi[b, 0])
            if A <= tol2:
                continue
            xb0 = xi[b, 0]
            xb1 = xi[b, 1]
            s = xa0 * xb1 - xa1 * xb0
            sg = 1.0 if s >= 0.0 else -1.0
            aa = abs(s)
            d2 = w / A                          # d2psi/ds2 (one division per triple)
            d1 = d2 * (aa - A) * sg             # dpsi/ds
            ib = 2 * (b + 1)
            fa0 += d1 * xb1
            fa1 -= d1 * xb0
            f_loc[ib] -= d1 * xa1
            f_loc[ib + 1] += d1 * xa0
            e_t = 0.5 * d2 * (aa - A) ** 2
            energy += e_t
            share = e_t / mult
            e0 += share
            if mult > 1.0:
                e_loc[a + 1] += share
                e_loc[b + 1] += share
            count += 1
            if Kloc is None:
                continue
            g1 = -xb0
            kaa00 += d2 * xb1 * xb1
            kaa01 += d2 * xb1 * g1
            kaa10 += d2 * xb1 * g1
            kaa11 += d2 * g1 * g1
            _add_outer_2d(Kloc, ib, d2, -xa1, xa0)
            t0 = d2 * xb1
            t1 = d2 * xb0
            k00 = -t0 * xa1
            k01 = t0 * xa0 + d1
            k10 = t1 * xa1 - d1
            k11 = -t1 * xa0
            Kloc[ia, ib] += k00
            Kloc[ia, ib + 1] += k01
            Kloc[ia + 1, ib] += k10
            Kloc[ia + 1, ib + 1] += k11
            Kloc[ib, ia] += k00
            Kloc[ib + 1, ia] += k01
            Kloc[ib, ia + 1] += k10
            Kloc[ib + 1, ia + 1] += k11
        f_loc[ia] = fa0
        f_loc[ia + 1] = fa1
        if Kloc is not None:
            Kloc[ia, ia] = kaa00
            Kloc[ia, ia + 1] = kaa01
            Kloc[ia + 1, ia] = kaa10
            Kloc[ia + 1, ia + 1] = kaa11
    e_loc[0] = e0
    return energy, count


@njit(cache=True, inline='always')
def _add_sandwich(Kloc, r0, c0, sgn, M, u, v):
    """Kloc[r0:r0+3, c0:c0+3] += sgn [u]x M [v]x^T for the symmetric 3 x 3 ``M`` ([u]x w = u x w):
    T = [u]x M column by column, then row i of the result is v x (row i of T)."""
    T = np.empty((3, 3))
    for j in range(3):
        T[0, j] = u[1] * M[2, j] - u[2] * M[1, j]
        T[1, j] = u[2] * M[0, j] - u[0] * M[2, j]
        T[2, j] = u[0] * M[1, j] - u[1] * M[0, j]
    for i in range(3):
        Kloc[r0 + i, c0] += sgn * (v[1] * T[i, 2] - v[2] * T[i, 1])
        Kloc[r0 + i, c0 + 1] += sgn * (v[2] * T[i, 0] - v[0] * T[i, 2])
        Kloc[r0 + i, c0 + 2] += sgn * (v[0] * T[i, 1] - v[1] * T[i, 0])


@njit(cache=True, inline='always')
def _add_outer_cross(Kloc, r, c, g0, g1, g2, t0, t1, t2, v0, v1, v2):
    """Kloc[r:r+3, c:c+3] += g t^T + [v]x (one off-diagonal block of a quadruple)."""
    Kloc[r, c] += g0 * t0
    Kloc[r, c + 1] += g0 * t1 - v2
    Kloc[r, c + 2] += g0 * t2 + v1
    Kloc[r + 1, c] += g1 * t0 + v2
    Kloc[r + 1, c + 1] += g1 * t1
    Kloc[r + 1, c + 2] += g1 * t2 - v0
    Kloc[r + 2, c] += g2 * t0 - v1
    Kloc[r + 2, c + 1] += g2 * t1 + v0
    Kloc[r + 2, c + 2] += g2 * t2


@njit(cache=True)
def _quadruples_3d(Kloc, f_loc, e_loc, xi, Xi, Ln, D2, nodes, vol, wC, p, r2, kcc):
    """psi3 of the 3D quadruples (p, a, b, c), a < b < c local neighbours: energy, gradient
    (into f_loc) and Hessian (into the upper neighbour blocks of Kloc unless it is empty);
    returns (energy, quadruples evaluated). ``wC`` = V_p C3, ``kcc`` a work array (6 n).

    With s = (xi_a x xi_b) . xi_c, dpsi/ds = d1, d2psi/ds2 = d2, the gradients are
    g_a = xi_b x xi_c, g_b = xi_c x xi_a, g_c = xi_a x xi_b, and block (m, n) of the
    Hessian is d2 g_m g_n^T + d1 d2s/dxi_m dxi_n with d2s/dxi_a dxi_b = -[xi_c]x,
    d2s/dxi_a dxi_c = [xi_b]x, d2s/dxi_b dxi_c = -[xi_a]x ([v]x w = v x w). For fixed
    (a, b) the sums over c of the blocks (a, a), (b, b), (a, b) need only
    M = sum d2 xi_c xi_c^T and m1 = sum d1 xi_c: (a, a) = [xi_b]x M [xi_b]x^T,
    (b, b) = [xi_a]x M [xi_a]x^T, (a, b) = -[xi_b]x M [xi_a]x^T - [m1]x, and the gradients
    sum to xi_b x m1 and m1 x xi_a; they are added once per pair. Per quadruple only the
    blocks (a, c), (b, c) (rows of a and b) and the (c, c) coefficients (on g_c g_c^T,
    fixed per pair, accumulated in ``kcc``) remain. The triple loop skips the tuples of
    vanishing reference volume and those counted at a lower-numbered vertex (see
    :func:`assemble`).
    """
    n = xi.shape[0]
    tangent = Kloc.shape[0] != 0
    energy = 0.0
    count = 0
    M = np.empty((3, 3))
    ua = np.empty(3)
    ub = np.empty(3)
    m1 = np.empty(3)
    for a in range(n):
        qa = nodes[a + 1]
        xa0 = xi[a, 0]
        xa1 = xi[a, 1]
        xa2 = xi[a, 2]
        for b in range(a + 1, n):
            qb = nodes[b + 1]
            xb0 = xi[b, 0]
            xb1 = xi[b, 1]
            xb2 = xi[b, 2]
            cab0 = Xi[a, 1] * Xi[b, 2] - Xi[a, 2] * Xi[b, 1]
            cab1 = Xi[a, 2] * Xi[b, 0] - Xi[a, 0] * Xi[b, 2]
            cab2 = Xi[a, 0] * Xi[b, 1] - Xi[a, 1] * Xi[b, 0]
            # g_c = xi_a x xi_b, fixed for the pair
            gc0 = xa1 * xb2 - xa2 * xb1
            gc1 = xa2 * xb0 - xa0 * xb2
            gc2 = xa0 * xb1 - xa1 * xb0
            ab_in = D2[a, b] <= r2
            wab = wC * vol[qa] * vol[qb]
            s_ab = Ln[a] * Ln[a] + Ln[b] * Ln[b] + D2[a, b]
            M00 = M01 = M02 = M11 = M12 = M22 = 0.0
            s0 = s1 = s2 = 0.0
            any_c = False
            ra = 3 * (a + 1)
            rb = 3 * (b + 1)
            for cc in range(b + 1, n):
                qc = nodes[cc + 1]
                ac_in = D2[a, cc] <= r2
                bc_in = D2[b, cc] <= r2
                # vertices (besides p) whose horizon holds the other three
                a_c = ab_in and ac_in
                b_c = ab_in and bc_in
                c_c = ac_in and bc_in
                if (a_c and qa < p) or (b_c and qb < p) or (c_c and qc < p):
                    continue
                V0 = abs(cab0 * Xi[cc, 0] + cab1 * Xi[cc, 1] + cab2 * Xi[cc, 2])
                S = (s_ab + Ln[cc] * Ln[cc] + D2[a, cc] + D2[b, cc]) / 6.0
                if V0 * V0 <= DEGENERATE_TOL * DEGENERATE_TOL * S * S * S:
                    continue
                any_c = True
                mult = 1.0 + a_c + b_c + c_c
                w = mult * 1.5 * wab * vol[qc]
                xc0 = xi[cc, 0]
                xc1 = xi[cc, 1]
                xc2 = xi[cc, 2]
                s = gc0 * xc0 + gc1 * xc1 + gc2 * xc2
                vv = abs(s)
                d2 = w / V0
                e_t = 0.5 * d2 * (vv - V0) ** 2
                energy += e_t
                share = e_t / mult
                e_loc[0] += share
                if a_c:
                    e_loc[a + 1] += share
                if b_c:
                    e_loc[b + 1] += share
                if c_c:
                    e_loc[cc + 1] += share
                d1 = d2 * (vv - V0) * (1.0 if s >= 0.0 else -1.0)
                rc = 3 * (cc + 1)
                f_loc[rc] += d1 * gc0
                f_loc[rc + 1] += d1 * gc1
                f_loc[rc + 2] += d1 * gc2
                s0 += d1 * xc0
                s1 += d1 * xc1
                s2 += d1 * xc2
                count += 1
                if not tangent:
                    continue
                M00 += d2 * xc0 * xc0
                M01 += d2 * xc0 * xc1
                M02 += d2 * xc0 * xc2
                M11 += d2 * xc1 * xc1
                M12 += d2 * xc1 * xc2
                M22 += d2 * xc2 * xc2
                k = 6 * cc
                kcc[k] += d2 * gc0 * gc0
                kcc[k + 1] += d2 * gc0 * gc1
                kcc[k + 2] += d2 * gc0 * gc2
                kcc[k + 3] += d2 * gc1 * gc1
                kcc[k + 4] += d2 * gc1 * gc2
                kcc[k + 5] += d2 * gc2 * gc2
                t0 = d2 * gc0
                t1 = d2 * gc1
                t2 = d2 * gc2
                # (a, c) = d2 g_a g_c^T + d1 [xi_b]x, g_a = xi_b x xi_c
                _add_outer_cross(Kloc, ra, rc, xb1 * xc2 - xb2 * xc1, xb2 * xc0 - xb0 * xc2,
                                 xb0 * xc1 - xb1 * xc0, t0, t1, t2, d1 * xb0, d1 * xb1, d1 * xb2)
                # (b, c) = d2 g_b g_c^T - d1 [xi_a]x, g_b = xi_c x xi_a
                _add_outer_cross(Kloc, rb, rc, xc1 * xa2 - xc2 * xa1, xc2 * xa0 - xc0 * xa2,
                                 xc0 * xa1 - xc1 * xa0, t0, t1, t2, -d1 * xa0, -d1 * xa1, -d1 * xa2)
            if not any_c:
                continue
            # gradients of the pair: sum_c d1 g_a = xi_b x m1, sum_c d1 g_b = m1 x xi_a
            f_loc[ra] += xb1 * s2 - xb2 * s1
            f_loc[ra + 1] += xb2 * s0 - xb0 * s2
            f_loc[ra + 2] += xb0 * s1 - xb1 * s0
            f_loc[rb] += s1 * xa2 - s2 * xa1
            f_loc[rb + 1] += s2 * xa0 - s0 * xa2
            f_loc[rb + 2] += s0 * xa1 - s1 * xa0
            if not tangent:
                continue
            M[0, 0] = M00
            M[0, 1] = M[1, 0] = M01
            M[0, 2] = M[2, 0] = M02
            M[1, 1] = M11
            M[1, 2] = M[2, 1] = M12
            M[2, 2] = M22
            for al in range(3):
                ua[al] = xi[a, al]
                ub[al] = xi[b, al]
            m1[0] = s0
            m1[1] = s1
            m1[2] = s2
            _add_sandwich(Kloc, ra, ra, 1.0, M, ub, ub)
            _add_sandwich(Kloc, rb, rb, 1.0, M, ua, ua)
            _add_sandwich(Kloc, ra, rb, -1.0, M, ub, ua)
            # - [m1]x at (a, b)
            Kloc[ra, rb + 1] += s2
            Kloc[ra, rb + 2] -= s1
            Kloc[ra + 1, rb] -= s2
            Kloc[ra + 1, rb + 2] += s0
            Kloc[ra + 2, rb] += s1
            Kloc[ra + 2, rb + 1] -= s0
    if tangent:
        for cc in range(n):
            k = 6 * cc
            rc = 3 * (cc + 1)
            Kloc[rc, rc] += kcc[k]
            Kloc[rc, rc + 1] += kcc[k + 1]
            Kloc[rc, rc + 2] += kcc[k + 2]
            Kloc[rc + 1, rc] += kcc[k + 1]
            Kloc[rc + 1, rc + 1] += kcc[k + 3]
            Kloc[rc + 1, rc + 2] += kcc[k + 4]
            Kloc[rc + 2, rc] += kcc[k + 2]
            Kloc[rc + 2, rc + 1] += kcc[k + 4]
            Kloc[rc + 2, rc + 2] += kcc[k + 5]
            for j in range(6):
                kcc[k + j] = 0.0
    return energy, count


@njit(cache=True)
def _mirror_upper(Kloc, nl, d):
    """Neighbour blocks (n, m), n > m, set to the transpose of (m, n): the upper blocks hold
    every contribution (those of :func:`_quadruples_3d` only there), the Hessian is symmetric."""
    for m in range(1, nl):
        for n in range(m + 1, nl):
            for al in range(d):
                for be in range(d):
                    Kloc[n * d + be, m * d + al] = Kloc[m * d + al, n * d + be]


@njit(cache=True)
def _close_central_force(f_loc, nl, d):
    """Central point's force: f_p = -sum_m f_m over the neighbour entries of ``f_loc``."""
    for al in range(d):
        s = 0.0
        for m in range(1, nl):
            s += f_loc[m * d + al]
        f_loc[al] = -s


@njit(cache=True, inline='always')
def _row_sums_2d(Kloc, nl):
    """K_mp = -sum_n K_mn and K_pm = K_mp^T in 2D, the two rows of a neighbour at once: four
    independent sums (each in the order n = 1, 2, ...) instead of one chain of dependent
    additions at a time (the generic loop of :func:`_close_central`, same result bit for bit)."""
    for r in range(2, 2 * nl, 2):
        r0 = Kloc[r]
        r1 = Kloc[r + 1]
        s00 = 0.0
        s01 = 0.0
        s10 = 0.0
        s11 = 0.0
        for n in range(1, nl):
            s00 += r0[2 * n]
            s01 += r0[2 * n + 1]
            s10 += r1[2 * n]
            s11 += r1[2 * n + 1]
        r0[0] = -s00
        r0[1] = -s01
        r1[0] = -s10
        r1[1] = -s11
        Kloc[0, r] = -s00
        Kloc[1, r] = -s01
        Kloc[0, r + 1] = -s10
        Kloc[1, r + 1] = -s11


@njit(cache=True)
def _close_central(Kloc, f_loc, nl, d):
    """Central rows/columns: f_p = -sum_m f_m, K_mp = -sum_n K_mn, K_pp = sum_mn K_mn.

    The neighbour part of Kloc is symmetric, so K_pm = K_mp^T and the column sums are
    the row sums: one contiguous pass over the neighbour rows.
    """
    _close_central_force(f_loc, nl, d)
    if Kloc.shape[0] == 0:
        return
    for al in range(d):
        for be in range(d):
            Kloc[al, be] = 0.0
    if d == 2:
        _row_sums_2d(Kloc, nl)
    else:
        for r in range(d, nl * d):
            row = Kloc[r]
            for be in range(d):
                s = 0.0
                for n in range(1, nl):
                    s += row[n * d + be]
                row[be] = -s
                Kloc[be, r] = -s
    for m in range(1, nl):
        for al in range(d):
            for be in range(d):
                Kloc[al, be] -= Kloc[m * d + al, be]


@njit(cache=True)
def _scatter_2d(Kloc, nodes, nl, rows, coff, slots, s0, data):
    """:func:`_scatter` in 2D through the block slots, the 2 x 2 block written out: the
    compiler then knows the block size (1.2-1.4x faster tangent at 100 x 100 points, set 3,
    bit-identical). Written inline: the same code through an inlined helper with its own
    return and raise ran 2x slower."""
    for m in range(nl):
        a = nodes[m]
        ra0 = rows[a, 0]
        ra1 = rows[a, 1]
        sm = s0 + m * nl
        i0 = 2 * m
        for n in range(nl):
            kk = slots[sm + n]
            j0 = 2 * n
            if kk < 0:                          # a pair no tuple couples: zero block
                if Kloc[i0, j0] != 0.0 or Kloc[i0, j0 + 1] != 0.0 or Kloc[i0 + 1, j0] != 0.0 \
                        or Kloc[i0 + 1, j0 + 1] != 0.0:
                    raise ValueError("tangent block outside the precomputed sparsity pattern")
                continue
            b = nodes[n]
            cb0 = coff[b, 0]
            cb1 = coff[b, 1]
            if ra0 >= 0:
                base = ra0 + kk
                if cb0 >= 0:
                    data[base + cb0] += Kloc[i0, j0]
                if cb1 >= 0:
                    data[base + cb1] += Kloc[i0, j0 + 1]
            if ra1 >= 0:
                base = ra1 + kk
                if cb0 >= 0:
                    data[base + cb0] += Kloc[i0 + 1, j0]
                if cb1 >= 0:
                    data[base + cb1] += Kloc[i0 + 1, j0 + 1]


@njit(cache=True, inline='always')
def _block_offset(target, c, m, n, nl, nodes, d):
    """Offset (entries) of block (nodes[m], nodes[n]) within the rows of node nodes[m] in the
    target's data: from the precomputed block slots of central point ``c`` when there are
    any, by binary search in the block pattern otherwise (full pattern layout); -1 outside."""
    slots = target[3]
    if slots.shape[0] > 0:
        return np.int64(slots[target[4][c] + m * nl + n])
    rowptr = target[5]
    a = nodes[m]
    kk = _find(target[6], rowptr[a], rowptr[a + 1], nodes[n])
    return d * (kk - rowptr[a]) if kk >= 0 else np.int64(-1)


@njit(cache=True, inline='always')
def _add_entry(target, a, al, b, be, kk, v):
    """data[(a, al), (b, be)] += v in the target's layout (block offset ``kk``); entries of
    rows or columns that the target leaves out (Dirichlet DOFs of a reduced matrix) are skipped."""
    r = target[1][a, al]
    cb = target[2][b, be]
    if r >= 0 and cb >= 0:
        target[0][r + kk + cb] += v


@njit(cache=True)
def _scatter(Kloc, nodes, nl, d, c, target):
    """Add the dense local tangent of central point ``c`` into the target's CSR data.

    ``target`` = (data, rows, coff, slots, sptr, rowptr, cols): DOF row (a, al) starts at
    ``rows[a, al]`` in ``data`` (-1: not assembled), column DOF (b, be) sits at ``coff[b, be]``
    within node b's block of a row (-1: not assembled) and block (a, b) at the offset
    :func:`_block_offset` gives (the block slots of :func:`block_slots` from ``sptr[c]`` on, or
    a binary search in the node pattern ``rowptr``, ``cols``). The same layout describes the
    full block-CSR pattern and the tangent reduced to the free DOFs (assembled directly, no
    second pass). A block outside the pattern (neighbours of p coupled only through
    degenerate tuples, see :func:`coupled_blocks`) must be zero and is skipped; a non-zero one
    raises.
    """
    slots = target[3]
    if d == 2 and slots.shape[0] > 0:
        _scatter_2d(Kloc, nodes, nl, target[1], target[2], slots, target[4][c], target[0])
        return
    for m in range(nl):
        a = nodes[m]
        for n in range(nl):
            kk = _block_offset(target, c, m, n, nl, nodes, d)
            if kk < 0:                  # a pair no tuple couples (see coupled_blocks): zero block
                for al in range(d):
                    for be in range(d):
                        if Kloc[m * d + al, n * d + be] != 0.0:
                            raise ValueError("tangent block outside the precomputed sparsity pattern")
                continue
            for al in range(d):
                for be in range(d):
                    _add_entry(target, a, al, nodes[n], be, kk, Kloc[m * d + al, n * d + be])


@njit(cache=True)
def _scatter_pairs_2d(Pd, nodes, nl, rows, coff, slots, s0, data):
    """:func:`_scatter_pairs` in 2D through the block slots, the 2 x 2 blocks written out
    (the same sums in the same order)."""
    p = nodes[0]
    rp0 = rows[p, 0]
    rp1 = rows[p, 1]
    cp0 = coff[p, 0]
    cp1 = coff[p, 1]
    s00 = 0.0
    s01 = 0.0
    s10 = 0.0
    s11 = 0.0
    for m in range(1, nl):
        s00 -= -Pd[m, 0, 0]
        s01 -= -Pd[m, 0, 1]
        s10 -= -Pd[m, 1, 0]
        s11 -= -Pd[m, 1, 1]
    k00 = slots[s0]
    if rp0 >= 0:
        if cp0 >= 0:
            data[rp0 + k00 + cp0] += s00
        if cp1 >= 0:
            data[rp0 + k00 + cp1] += s01
    if rp1 >= 0:
        if cp0 >= 0:
            data[rp1 + k00 + cp0] += s10
        if cp1 >= 0:
            data[rp1 + k00 + cp1] += s11
    for m in range(1, nl):
        q = nodes[m]
        kpm = slots[s0 + m]
        kmp = slots[s0 + m * nl]
        kmm = slots[s0 + m * nl + m]
        if kpm < 0 or kmp < 0 or kmm < 0:
            raise ValueError("pair tangent block outside the precomputed sparsity pattern")
        v00 = Pd[m, 0, 0]
        v01 = Pd[m, 0, 1]
        v10 = Pd[m, 1, 0]
        v11 = Pd[m, 1, 1]
        rq0 = rows[q, 0]
        rq1 = rows[q, 1]
        cq0 = coff[q, 0]
        cq1 = coff[q, 1]
        if rq0 >= 0:                                 # K_mp = -Pd[m], K_mm = Pd[m]
            if cp0 >= 0:
                data[rq0 + kmp + cp0] -= v00
            if cp1 >= 0:
                data[rq0 + kmp + cp1] -= v01
            if cq0 >= 0:
                data[rq0 + kmm + cq0] += v00
            if cq1 >= 0:
                data[rq0 + kmm + cq1] += v01
        if rq1 >= 0:
            if cp0 >= 0:
                data[rq1 + kmp + cp0] -= v10
            if cp1 >= 0:
                data[rq1 + kmp + cp1] -= v11
            if cq0 >= 0:
                data[rq1 + kmm + cq0] += v10
            if cq1 >= 0:
                data[rq1 + kmm + cq1] += v11
        if rp0 >= 0:                                 # K_pm = -Pd[m]^T
            if cq0 >= 0:
                data[rp0 + kpm + cq0] -= v00
            if cq1 >= 0:
                data[rp0 + kpm + cq1] -= v10
        if rp1 >= 0:
            if cq0 >= 0:
                data[rp1 + kpm + cq0] -= v01
            if cq1 >= 0:
                data[rp1 + kpm + cq1] -= v11


@njit(cache=True)
def _scatter_pairs(Pd, nodes, nl, d, c, target):
    """Add the tangent of the one-neighbour (pair) interactions of central point ``c`` into the
    target (layout of :func:`_scatter`). ``Pd[m]`` (d x d) is the pair Hessian block of
    neighbour m (local node m >= 1); the central rows and columns follow from
    dxi_m/dx_p = -I: K_mm = Pd[m], K_mp = -Pd[m], K_pm = -Pd[m]^T, K_pp = sum_m Pd[m]. The
    pair tangent of a pair-only material, and that of the Newton preconditioner
    (:mod:`peridynamics.preconditioner`) evaluated in the pass of the whole tangent."""
    data = target[0]
    rows = target[1]
    coff = target[2]
    if d == 2 and target[3].shape[0] > 0:
        _scatter_pairs_2d(Pd, nodes, nl, rows, coff, target[3], target[4][c], data)
        return
    p = nodes[0]
    k00 = _block_offset(target, c, 0, 0, nl, nodes, d)
    for al in range(d):
        rp = rows[p, al]
        for be in range(d):
            s = 0.0
            for m in range(1, nl):
                s -= -Pd[m, al, be]
            cp = coff[p, be]
            if rp >= 0 and cp >= 0:
                data[rp + k00 + cp] += s
    for m in range(1, nl):
        q = nodes[m]
        kpm = _block_offset(target, c, 0, m, nl, nodes, d)
        kmp = _block_offset(target, c, m, 0, nl, nodes, d)
        kmm = _block_offset(target, c, m, m, nl, nodes, d)
        if kpm < 0 or kmp < 0 or kmm < 0:
            raise ValueError("pair tangent block outside the precomputed sparsity pattern")
        for al in range(d):
            rq = rows[q, al]
            rp = rows[p, al]
            cq = coff[q, al]
            for be in range(d):
                if rq >= 0:
                    cp = coff[p, be]
                    if cp >= 0:
                        data[rq + kmp + cp] -= Pd[m, al, be]     # K_mp = -Pd[m]
                    cqq = coff[q, be]
                    if cqq >= 0:
                        data[rq + kmm + cqq] += Pd[m, al, be]    # K_mm = Pd[m]
                if cq >= 0:
                    rpb = rows[p, be]
                    if rpb >= 0:
                        data[rpb + kpm + cq] -= Pd[m, al, be]    # K_pm = -Pd[m]^T


@njit(cache=True)
def full_layout(rowptr, d):
    """(rows, coff) of the full block-CSR pattern for :func:`_scatter`: DOF row (a, al) starts
    at d*d*rowptr[a] + al*d*nb(a), column DOF (b, be) at offset be of node b's block."""
    n = rowptr.shape[0] - 1
    rows = np.empty((n, d), np.int64)
    coff = np.empty((n, d), np.int64)
    for a in range(n):
        nb = rowptr[a + 1] - rowptr[a]
        for al in range(d):
            rows[a, al] = d * d * rowptr[a] + al * d * nb
            coff[a, al] = al
    return rows, coff


@njit(cache=True)
def coupled_blocks(X, centers, nptr, nidx, multi, rowptr, cols, keep):
    """Mark in ``keep`` the blocks of the candidate pattern (``rowptr``, ``cols``) that the
    central points ``centers`` of one material can make non-zero.

    Central point p couples itself with each neighbour q ((p, q), (q, p), (q, q) blocks); with
    multi-neighbour interactions (``multi``) it also couples two neighbours q_a, q_b, but only
    through tuples containing both, and each such tuple (triple or quadruple) is skipped by
    the kernels when p, q_a, q_b are collinear (a vanishing area A, hence a vanishing volume V
    of every quadruple over them, 003 Eq 10). A pair is kept when its reference area
    |Xi_a x Xi_b| exceeds 1 % of the kernels' degeneracy threshold (so every pair of a triple or
    quadruple that they evaluate is kept). Pairs at exactly 2 delta (p at their midpoint) and
    those whose common central points all lie on their line are dropped: 17 % of the
    candidate entries at 100 x 100 points, delta = 3.01 h, all of them exact zeros.
    """
    d = X.shape[1]
    for c in range(centers.shape[0]):
        p = centers[c]
        s0 = nptr[c]
        n = nptr[c + 1] - s0
        k = _find(cols, rowptr[p], rowptr[p + 1], p)
        keep[k] = True
        for a in range(n):
            qa = nidx[s0 + a]
            keep[_find(cols, rowptr[p], rowptr[p + 1], qa)] = True
            keep[_find(cols, rowptr[qa], rowptr[qa + 1], p)] = True
            keep[_find(cols, rowptr[qa], rowptr[qa + 1], qa)] = True
        if not multi:
            continue
        for a in range(n):
            qa = nidx[s0 + a]
            la = _dist2(X, qa, p)
            for b in range(a + 1, n):
                qb = nidx[s0 + b]
                if d == 2:
                    area2 = ((X[qa, 0] - X[p, 0]) * (X[qb, 1] - X[p, 1])
                             - (X[qa, 1] - X[p, 1]) * (X[qb, 0] - X[p, 0])) ** 2
                else:
                    area2 = 0.0
                    for al in range(3):
                        i1 = (al + 1) % 3
                        i2 = (al + 2) % 3
                        t = ((X[qa, i1] - X[p, i1]) * (X[qb, i2] - X[p, i2])
                             - (X[qa, i2] - X[p, i2]) * (X[qb, i1] - X[p, i1]))
                        area2 += t * t
                tol = 1e-2 * DEGENERATE_TOL * (la + _dist2(X, qb, p) + _dist2(X, qa, qb))
                if area2 <= tol * tol:
                    continue
                ka = _find(cols, rowptr[qa], rowptr[qa + 1], qb)
                kb = _find(cols, rowptr[qb], rowptr[qb + 1], qa)
                if ka < 0 or kb < 0:
                    raise ValueError("coupled neighbour pair outside the candidate pattern")
                keep[ka] = True
                keep[kb] = True


@njit(cache=True)
def dof_columns(rowptr, cols, d, indptr):
    """Column indices (int32) of the DOF-level CSR of the block pattern (``rowptr``, ``cols``
    node-level; ``indptr`` the DOF-level row pointer): DOF row a*d + al holds, for every
    block column b of node row a, the columns b*d .. b*d + d-1."""
    out = np.empty(indptr[-1], np.int32)
    for a in range(rowptr.shape[0] - 1):
        for al in range(d):
            k = indptr[a * d + al]
            for e in range(rowptr[a], rowptr[a + 1]):
                for be in range(d):
                    out[k] = cols[e] * d + be
                    k += 1
    return out


@njit(cache=True)
def block_slots(centers, nptr, nidx, rowptr, cols, boff, multi=True):
    """Where each block of each central point's local tangent goes in the fixed pattern.

    For central point c with local nodes (p, then its neighbours nidx[nptr[c]:nptr[c+1]]),
    ``slots[sptr[c] + m * nl + n]`` is the offset ``boff[kk]`` of block kk = (nodes[m],
    nodes[n]) of the node pattern (``rowptr``, ``cols``) within the rows of node nodes[m] of the
    target of :func:`_scatter` (d (kk - rowptr[nodes[m]]) for the full pattern, the count of
    free column DOFs before it for the tangent reduced to the free DOFs). Built once per
    pattern with the binary searches that :func:`_scatter` would otherwise repeat at every
    tangent evaluation; int32, sum over c of nl^2 entries, -1 for a block outside the pattern
    (neighbour-neighbour blocks of a pair-only material, ``multi`` False: not searched, never
    written; pairs that no tuple couples, see :func:`coupled_blocks`).
    """
    M = centers.shape[0]
    sptr = np.zeros(M + 1, np.int64)
    for c in range(M):
        nl = nptr[c + 1] - nptr[c] + 1
        sptr[c + 1] = sptr[c] + nl * nl
    slots = np.empty(sptr[M], np.int32)
    for c in range(M):
        s0 = nptr[c]
        nl = nptr[c + 1] - s0 + 1
        for m in range(nl):
            a = centers[c] if m == 0 else nidx[s0 + m - 1]
            r0 = rowptr[a]
            for n in range(nl):
                if not multi and m != 0 and n != 0 and m != n:
                    slots[sptr[c] + m * nl + n] = -1        # never written (see _scatter)
                    continue
                b = centers[c] if n == 0 else nidx[s0 + n - 1]
                kk = _find(cols, r0, rowptr[a + 1], b)
                slots[sptr[c] + m * nl + n] = boff[kk] if kk >= 0 else -1
    return slots, sptr


@njit(cache=True)
def assemble(X, u, centers, nptr, nidx, C1, C2, C3, vol, want_tangent,
             rowptr, cols, data, f, e_node, r2):
    """Energy of one material; add its residual to ``f`` and its tangent to ``data``.

    X, u: (N, d) reference positions and displacements of all nodes. ``centers`` (M,)
    central nodes of this material (all points of its point set), their neighbours ``nidx[nptr[c]:nptr[c+1]]`` (same
    material, within the horizon). C1, C2, C3: (M,) constants per central point, vol:
    (N,) point volumes, r2 the squared horizon radius of the neighbour search. The energy
    of the tuples of central point p (V_p times its energy density, 003 Eq 7) is added to
    ``e_node[p]``. Returns (energy, pairs, triples, quadruples) evaluated.

    a = |xi_i x xi_j| and v = |(xi_i x xi_j) . xi_k| are twice the triangle area and six
    times the tetrahedron volume of the tuple: they do not depend on which vertex is the
    central point, and neither do A, V nor psi2, psi3. A triangle (tetrahedron) therefore
    enters W once for every vertex whose horizon holds the other vertices; it is
    evaluated once, at the lowest-numbered such vertex, with that multiplicity as weight,
    and its energy is attributed equally to those vertices.
    """
    rows, coff = full_layout(rowptr, X.shape[1])
    target = (data, rows, coff, np.zeros(0, np.int32), np.zeros(1, np.int64), rowptr, cols)
    no_pairs = (np.zeros(0), rows, coff, np.zeros(0, np.int32), np.zeros(1, np.int64), rowptr, cols)
    return _assemble(X, u, centers, nptr, nidx, C1, C2, C3, vol, want_tangent, f, e_node, r2,
                     0, centers.shape[0], target, no_pairs)


@njit(cache=True)
def _assemble(X, u, centers, nptr, nidx, C1, C2, C3, vol, want_tangent, f, e_node, r2, c0, c1,
              target, pairs):
    """:func:`assemble` over the central points c0 <= c < c1, scattering the tangent into
    ``target`` (layout of :func:`_scatter`: the full pattern or the free-DOF tangent, through
    block slots or by binary search) and, when ``pairs[0]`` (its data) is not empty, the
    tangent of the one-neighbour interactions alone into the target ``pairs`` (the pair part
    that preconditions the Newton steps, evaluated in the same pass)."""
    d = X.shape[1]
    energy = 0.0
    n_pairs = 0
    n_trip = 0
    n_quad = 0
    g = np.zeros((3, d))
    H = np.zeros((3, 3, d, d))
    slots = np.zeros(3, np.int64)
    kcc = np.zeros((nptr[c0 + 1:c1 + 1] - nptr[c0:c1]).max() * 6 if c1 > c0 else 0)
    for c in range(c0, c1):
        p = centers[c]
        s0 = nptr[c]
        n = nptr[c + 1] - s0
        nl = n + 1
        nodes = np.empty(nl, np.int64)
        nodes[0] = p
        Xi = np.empty((n, d))
        xi = np.empty((n, d))
        Ln = np.empty(n)
        for a in range(n):
            q = nidx[s0 + a]
            nodes[a + 1] = q
            s2 = 0.0
            for al in range(d):
                Xi[a, al] = X[q, al] - X[p, al]
                xi[a, al] = Xi[a, al] + u[q, al] - u[p, al]
                s2 += Xi[a, al] * Xi[a, al]
            Ln[a] = np.sqrt(s2)
        f_loc = np.zeros(nl * d)
        e_loc = np.zeros(nl)
        multi = C2[c] != 0.0 or (d == 3 and C3[c] != 0.0)
        if multi:
            D2 = np.empty((n, n))
            for a in range(n):
                D2[a, a] = 0.0
                for b in range(a + 1, n):
                    D2[a, b] = _dist2(X, nodes[a + 1], nodes[b + 1])
                    D2[b, a] = D2[a, b]
        else:
            D2 = np.empty((0, 0))
        full = multi
        Kloc = np.zeros((nl * d, nl * d) if want_tangent and full else (0, 0))
        Pd = np.zeros((nl if want_tangent else 0, d, d))
        Vp = vol[p]
        # ---- one-neighbour interactions, psi1 = 1/2 C1 L (l/L - 1)^2 ----
        if C1[c] != 0.0:
            for a in range(n):
                w = 0.5 * Vp * vol[nodes[a + 1]] * C1[c]
                L = Ln[a]
                l2 = 0.0
                for al in range(d):
                    l2 += xi[a, al] * xi[a, al]
                l = np.sqrt(l2)
                if l == 0.0:
                    raise ValueError("two interacting points coincide (l = 0)")
                e_t = 0.5 * w * L * (l / L - 1.0) ** 2
                energy += e_t
                e_loc[0] += e_t
                coef = w * (1.0 / L - 1.0 / l)
                r = (a + 1) * d
                for al in range(d):
                    f_loc[r + al] += coef * xi[a, al]
                if want_tangent:
                    for al in range(d):
                        for be in range(d):
                            H[0, 0, al, be] = w * xi[a, al] * xi[a, be] / (l2 * l)
                        H[0, 0, al, al] += coef
                        for be in range(d):
                            Pd[a + 1, al, be] += H[0, 0, al, be]
                n_pairs += 1
        if full and want_tangent:        # the pair blocks start the neighbours' diagonal blocks
            for a in range(1, nl):
                for al in range(d):
                    for be in range(d):
                        Kloc[a * d + al, a * d + be] += Pd[a, al, be]
        # ---- two-neighbour interactions, psi2 = 1/2 C2 A (a/A - 1)^2 ----
        if C2[c] != 0.0 and d == 2:
            if want_tangent:
                energy, k2 = _triples_2d(Kloc, f_loc, e_loc, xi, Xi, Ln, D2, nodes, vol, Vp, C2[c], p, r2, energy)
            else:
                energy, k2 = _triples_2d(None, f_loc, e_loc, xi, Xi, Ln, D2, nodes, vol, Vp, C2[c], p, r2, energy)
            n_trip += k2
        elif C2[c] != 0.0:
            for a in range(n):
                qa = nodes[a + 1]
                wa = (2.0 / 3.0) * Vp * vol[qa] * C2[c]
                for b in range(a + 1, n):
                    qb = nodes[b + 1]
                    mult = _triple_multiplicity(D2[a, b], r2, qa, qb, p)
                    if mult == 0.0:
                        continue
                    w = mult * wa * vol[qb]
                    tol2 = DEGENERATE_TOL * (Ln[a] * Ln[a] + Ln[b] * Ln[b] + D2[a, b])
                    slots[0] = a + 1
                    slots[1] = b + 1
                    N0 = np.empty(3)
                    N0[0] = Xi[a, 1] * Xi[b, 2] - Xi[a, 2] * Xi[b, 1]
                    N0[1] = Xi[a, 2] * Xi[b, 0] - Xi[a, 0] * Xi[b, 2]
                    N0[2] = Xi[a, 0] * Xi[b, 1] - Xi[a, 1] * Xi[b, 0]
                    A = np.sqrt(N0[0] ** 2 + N0[1] ** 2 + N0[2] ** 2)
                    if A <= tol2:
                        continue
                    nv = np.empty(3)
                    nv[0] = xi[a, 1] * xi[b, 2] - xi[a, 2] * xi[b, 1]
                    nv[1] = xi[a, 2] * xi[b, 0] - xi[a, 0] * xi[b, 2]
                    nv[2] = xi[a, 0] * xi[b, 1] - xi[a, 1] * xi[b, 0]
                    aa = np.sqrt(nv[0] ** 2 + nv[1] ** 2 + nv[2] ** 2)
                    if aa == 0.0:
                        raise ValueError("a two-neighbour interaction collapsed (a = 0)")
                    e_t = 0.5 * w * (aa - A) ** 2 / A
                    energy += e_t
                    e_loc[0] += e_t / mult
                    if mult > 1.0:
                        e_loc[a + 1] += e_t / mult
                        e_loc[b + 1] += e_t / mult
                    d1 = w * (aa - A) / A            # dpsi/da
                    d2 = w / A                       # d2psi/da2
                    mv = nv / aa
                    # da/dxi_a = xi_b x m, da/dxi_b = m x xi_a
                    ga = np.empty(3)
                    gb = np.empty(3)
                    ga[0] = xi[b, 1] * mv[2] - xi[b, 2] * mv[1]
                    ga[1] = xi[b, 2] * mv[0] - xi[b, 0] * mv[2]
                    ga[2] = xi[b, 0] * mv[1] - xi[b, 1] * mv[0]
                    gb[0] = mv[1] * xi[a, 2] - mv[2] * xi[a, 1]
                    gb[1] = mv[2] * xi[a, 0] - mv[0] * xi[a, 2]
                    gb[2] = mv[0] * xi[a, 1] - mv[1] * xi[a, 0]
                    # dn/dxi_a = -[xi_b]x, dn/dxi_b = [xi_a]x ; P = (I - m m^T)/a
                    Da = np.zeros((3, 3))
                    Db = np.zeros((3, 3))
                    Da[0, 1] = xi[b, 2]
                    Da[0, 2] = -xi[b, 1]
                    Da[1, 0] = -xi[b, 2]
                    Da[1, 2] = xi[b, 0]
                    Da[2, 0] = xi[b, 1]
                    Da[2, 1] = -xi[b, 0]
                    Db[0, 1] = -xi[a, 2]
                    Db[0, 2] = xi[a, 1]
                    Db[1, 0] = xi[a, 2]
                    Db[1, 2] = -xi[a, 0]
                    Db[2, 0] = -xi[a, 1]
                    Db[2, 1] = xi[a, 0]
                    P = -np.outer(mv, mv)
                    for al in range(3):
                        P[al, al] += 1.0
                    P /= aa
                    Haa = Da.T @ P @ Da
                    Hab = Da.T @ P @ Db
                    Hbb = Db.T @ P @ Db
                    # d2 (m . (xi_a x xi_b)) / dxi_a dxi_b = -[m]x
                    Mx = np.zeros((3, 3))
                    Mx[0, 1] = mv[2]
                    Mx[0, 2] = -mv[1]
                    Mx[1, 0] = -mv[2]
                    Mx[1, 2] = mv[0]
                    Mx[2, 0] = mv[1]
                    Mx[2, 1] = -mv[0]
                    for al in range(3):
                        for be in range(3):
                            H[0, 0, al, be] = d2 * ga[al] * ga[be] + d1 * Haa[al, be]
                            H[1, 1, al, be] = d2 * gb[al] * gb[be] + d1 * Hbb[al, be]
                            hab = d2 * ga[al] * gb[be] + d1 * (Hab[al, be] + Mx[al, be])
                            H[0, 1, al, be] = hab
                            H[1, 0, be, al] = hab
                    for al in range(3):
                        g[0, al] = d1 * ga[al]
                        g[1, al] = d1 * gb[al]
                    _add_tuple(Kloc, f_loc, slots, 2, d, g, H)
                    n_trip += 1
        # ---- three-neighbour interactions (3D), psi3 = 1/2 C3 V (v/V - 1)^2 ----
        if d == 3 and C3[c] != 0.0:
            e3, k3 = _quadruples_3d(Kloc, f_loc, e_loc, xi, Xi, Ln, D2, nodes, vol, Vp * C3[c], p, r2, kcc)
            energy += e3
            n_quad += k3
        for m in range(nl):
            e_node[nodes[m]] += e_loc[m]
        if want_tangent and d == 3 and C3[c] != 0.0:
            _mirror_upper(Kloc, nl, d)
        if full:
            _close_central(Kloc, f_loc, nl, d)
        else:
            _close_central_force(f_loc, nl, d)
        for m in range(nl):
            for al in range(d):
                f[nodes[m], al] += f_loc[m * d + al]
        if not want_tangent:
            continue
        if full:
            _scatter(Kloc, nodes, nl, d, c, target)
        else:
            _scatter_pairs(Pd, nodes, nl, d, c, target)
        if pairs[0].shape[0]:
            _scatter_pairs(Pd, nodes, nl, d, c, pairs)
    return energy, n_pairs, n_trip, n_quad


@njit(parallel=True, cache=True)
def assemble_blocks(X, u, centers, nptr, nidx, C1, C2, C3, vol, want_tangent, f, e_node, r2,
                    color_ptr, block_ptr, target, pairs):
    """:func:`assemble` over spatial blocks of central points, in parallel and race-free.

    Central points are sorted by block (``block_ptr`` delimits each block's slice of
    ``centers``; ``nptr`` keeps absolute offsets into ``nidx``) and blocks by colour
    (``color_ptr``). Blocks of one colour are at least 2 delta apart, so the nodes
    {p} + horizon(p) they write (residual, energy, tangent rows) are disjoint: the
    blocks of a colour run in parallel (numba prange), the colours one after the other.
    Every sum runs in a fixed order, so the result does not depend on the thread count.
    ``target`` and ``pairs``: see :func:`_assemble`.
    """
    energy = 0.0
    n1 = 0
    n2 = 0
    n3 = 0
    for col in range(color_ptr.shape[0] - 1):
        b0 = color_ptr[col]
        nb = color_ptr[col + 1] - b0
        out_e = np.zeros(nb)
        out_n = np.zeros((nb, 3), np.int64)
        for k in prange(nb):
            s = block_ptr[b0 + k]
            e = block_ptr[b0 + k + 1]
            if e > s:
                r = _assemble(X, u, centers, nptr, nidx, C1, C2, C3, vol, want_tangent, f, e_node, r2,
                              s, e, target, pairs)
                out_e[k] = r[0]
                out_n[k, 0] = r[1]
                out_n[k, 1] = r[2]
                out_n[k, 2] = r[3]
        for k in range(nb):
            energy += out_e[k]
            n1 += out_n[k, 0]
            n2 += out_n[k, 1]
            n3 += out_n[k, 2]
    return energy, n1, n2, n3
