"""CPDI and B2-CPDI shape functions and their particle kernels (2D planar).

CPDI (convected particle domain interpolation, Sadeghirad, Brannon and Burghardt 2011;
the form NairnMPM uses and 004 Sec 2 and 5 cite as [14]): the particle domain is a
parallelogram centred on x_p, spanned by the half domain vectors

    r1 = F (l_x, 0),    r2 = F (0, l_y)

(l the undeformed half widths, F the particle's in-plane deformation gradient), with
corners, counter-clockwise,

    c0 = x_p - r1 - r2,  c1 = x_p + r1 - r2,  c2 = x_p + r1 + r2,  c3 = x_p - r1 + r2.

The grid function N_i is replaced over the domain by its bilinear interpolant from the
corner values N_i(c_k); its domain average and the average of its gradient (the
divergence theorem over the domain boundary, on which the interpolant is linear
between corners) are

    S_ip      = (1/4) sum_k N_i(c_k)
    grad S_ip = (1/A_p) [(N_i(c0) - N_i(c2)) g0 + (N_i(c1) - N_i(c3)) g1],
    g0 = (r1_y - r2_y, r2_x - r1_x),  g1 = (r1_y + r2_y, -(r1_x + r2_x)),
    A_p = 4 (r1 x r2)

(Sadeghirad et al. 2011 Eq 24-25). ``CPDI`` takes the bilinear N_i (2 x 2 nodes per
corner); ``B2CPDI`` the quadratic B-spline (3 x 3 nodes per corner; 004 Sec 5: "replace
linear N_i(x) terms in CPDI shape function with quadratic spline"). Since
sum_i N_i(c) = 1 at every corner, sum_i S_ip = 1 and sum_i grad S_ip = 0 exactly.

Every kernel runs corner by corner: node i receives N_i(c_k) times the corner's
coefficients (1/4 for the weight, g_k / A_p for the gradient, g2 = -g0, g3 = -g1), so a
node touched by several corners simply accumulates (no merged node list).

F is carried for every particle of a CPDI run: a small-strain (linear) field updates
F <- (I + dt L) F and V = det(F) V_0 here with its stress, a finite-strain field through
:func:`mpm.finite_strain.finite_strain_update` as in the other shapes. The loaded-edge
offset of a traction follows F (foff = F foff_0) and the traction is extrapolated with
the mean of the corner function at the two corners of the loaded edge
(:func:`traction_weights_cpdi`).
"""
from __future__ import annotations

import numpy as np

from interfaces.jit import FMA, njit

from .kernels import normalise_fields, zero_nodal
from .shape import B2, B2CPDI, CPDI, LINEAR, axis_weights3


@njit(cache=True, inline="always")
def is_cpdi(kind: int) -> bool:
    """True for the CPDI shapes (domain vectors from F, corner-based weights)."""
    return kind >= CPDI


@njit(cache=True, inline="always")
def corner_kind(kind: int) -> int:
    """The grid function N_i evaluated at the domain corners: linear or B2."""
    return B2 if kind == B2CPDI else LINEAR


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def domain(p, x, F, hw):
    """Corner 0 and the half domain vectors of particle p, with the corner-gradient
    vectors divided by the area: (c0x, c0y, r1x, r1y, r2x, r2y, g0x, g0y, g1x, g1y)."""
    r1x = F[p, 0, 0] * hw[p, 0]
    r1y = F[p, 1, 0] * hw[p, 0]
    r2x = F[p, 0, 1] * hw[p, 1]
    r2y = F[p, 1, 1] * hw[p, 1]
    inv = 1.0 / (4.0 * (r1x * r2y - r1y * r2x))
    return (x[p, 0] - r1x - r2x, x[p, 1] - r1y - r2y, r1x, r1y, r2x, r2y,
            (r1y - r2y) * inv, (r2x - r1x) * inv, (r1y + r2y) * inv, -(r1x + r2x) * inv)


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def corner(k, c0x, c0y, r1x, r1y, r2x, r2y, g0x, g0y, g1x, g1y):
    """Position of corner k (counter-clockwise from c0) and its gradient coefficients
    (g_k / A_p): (x, y, gx, gy)."""
    if k == 0:
        return c0x, c0y, g0x, g0y
    if k == 1:
        return c0x + 2.0 * r1x, c0y + 2.0 * r1y, g1x, g1y
    if k == 2:
        return c0x + 2.0 * (r1x + r2x), c0y + 2.0 * (r1y + r2y), -g0x, -g0y
    return c0x + 2.0 * r2x, c0y + 2.0 * r2y, -g1x, -g1y


@njit(cache=True, inline="always")
def _pick(k, a0, a1, a2):
    return a0 if k == 0 else (a1 if k == 1 else a2)


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def corner_weights(cx, cy, origin, cell, nn, base):
    """1D grid-function values of a corner along x and y: (i0, j0, count, wx0..2,
    wy0..2); count (nodes per axis) -1 when the corner's support leaves the grid."""
    i0, w0, w1, w2, _, _, _ = axis_weights3(cx, origin[0], cell[0], 0.0, base)
    j0, q0, q1, q2, _, _, _ = axis_weights3(cy, origin[1], cell[1], 0.0, base)
    n = 3 if base == B2 else 2
    if i0 < 0 or j0 < 0 or i0 + n > nn[0] or j0 + n > nn[1]:
        n = -1
    return i0, j0, n, w0, w1, w2, q0, q1, q2


@njit(cache=True, refcount=False)
def shape_cpdi(p, x, F, hw, origin, cell, nn, kind, idx, S, G) -> int:
    """Nodes, S_ip and grad S_ip of particle p, one entry per (corner, node): a node
    touched by several corners appears several times (its S and G are the sums).
    ``idx``, ``S`` (>= 36) and ``G`` (>= 36 x 2) are filled in place; returns the count,
    or -1 when a corner's support leaves the grid. For tests and diagnostics; the
    kernels below inline the same loops."""
    base = corner_kind(kind)
    c0x, c0y, r1x, r1y, r2x, r2y, g0x, g0y, g1x, g1y = domain(p, x, F, hw)
    c = 0
    for k in range(4):
        cx, cy, gx, gy = corner(k, c0x, c0y, r1x, r1y, r2x, r2y, g0x, g0y, g1x, g1y)
        i0, j0, n, w0, w1, w2, q0, q1, q2 = corner_weights(cx, cy, origin, cell, nn, base)
        if n < 0:
            return -1
        for b in range(n):
            wy = _pick(b, q0, q1, q2)
            for a in range(n):
                N = _pick(a, w0, w1, w2) * wy
                idx[c] = (j0 + b) * nn[0] + i0 + a
                S[c] = 0.25 * N
                G[c, 0] = gx * N
                G[c, 1] = gy * N
                c += 1
    return c


# -------------------------------------------------------------------- P2G ----


@njit(cache=True, fastmath=FMA, error_model="numpy")
def p2g_cpdi(x, v, pmass, pvol, stress, field, x0, F, hw, fext, foff, foff0, load_scale,
             origin, cell, nn, kind, multi, internal, mass, mom, force, volume, volgrad, disp,
             pos):
    """P2G of :func:`mpm.kernels.p2g_2d` (same nodal sums: 000 Eq 5-6, 10, 13, 32; 004
    Eq 29) with the CPDI weights and gradients; tractions at the loaded edge point with
    the corner function along the loaded edge (:func:`traction_weights_cpdi`). Returns -1
    or a lost particle."""
    zero_nodal(multi, mass, mom, force, volume, volgrad, disp, pos)
    lost = scatter_cpdi(0, x.shape[0], x, v, pmass, pvol, stress, field, x0, F, hw, origin,
                        cell, nn, kind, multi, internal, mass, mom, force, volume, volgrad,
                        disp, pos)
    if lost >= 0:
        return lost
    tractions_cpdi(x, field, fext, foff, foff0, F, hw, load_scale, origin, cell, nn, kind,
                   force)
    if multi:
        normalise_fields(mass, disp, pos)
    return -1


@njit(cache=True, fastmath=FMA, error_model="numpy", refcount=False)
def scatter_cpdi(lo, hi, x, v, pmass, pvol, stress, field, x0, F, hw, origin, cell, nn,
                 kind, multi, internal, mass, mom, force, volume, volgrad, disp, pos):
    """Scatter of particles lo..hi-1 corner by corner, added to the nodal arrays."""
    M = mass.shape[1]
    nx = nn[0]
    base = corner_kind(kind)
    for p in range(lo, hi):
        f = field[p]
        m = pmass[p]
        V = pvol[p]
        sxx = V * stress[p, 0] if internal else 0.0
        syy = V * stress[p, 1] if internal else 0.0
        sxy = V * stress[p, 2] if internal else 0.0
        c0x, c0y, r1x, r1y, r2x, r2y, g0x, g0y, g1x, g1y = domain(p, x, F, hw)
        for k in range(4):
            cx, cy, gx, gy = corner(k, c0x, c0y, r1x, r1y, r2x, r2y, g0x, g0y, g1x, g1y)
            i0, j0, n, w0, w1, w2, q0, q1, q2 = corner_weights(cx, cy, origin, cell, nn, base)
            if n < 0:
                return p
            for b in range(n):
                wy = _pick(b, q0, q1, q2)
                for a in range(n):
                    N = _pick(a, w0, w1, w2) * wy
                    if N == 0.0:
                        continue
                    s = 0.25 * N
                    Gx = gx * N
                    Gy = gy * N
                    node = (j0 + b) * nx + i0 + a
                    mass[node, f] += s * m
                    mom[node, f, 0] += s * m * v[p, 0]
                    mom[node, f, 1] += s * m * v[p, 1]
                    force[node, f, 0] -= sxx * Gx + sxy * Gy
                    force[node, f, 1] -= sxy * Gx + syy * Gy
                    if multi:
                        volume[node, f] += s * V
                        volgrad[node, f, 0] += Gx * V
                        volgrad[node, f, 1] += Gy * V
                        disp[node, f, 0] += s * m * (x[p, 0] - x0[p, 0])
                        disp[node, f, 1] += s * m * (x[p, 1] - x0[p, 1])
                        pos[node, f, 0] += s * m * x[p, 0]
                        pos[node, f, 1] += s * m * x[p, 1]
    return -1


@njit(cache=True, fastmath=FMA, error_model="numpy", refcount=False)
def traction_weights_cpdi(p, x, F, hw, foff, foff0, origin, cell, nn, kind, tidx, tw) -> int:
    """Nodes and weights carrying the traction of particle p (``tidx``, ``tw``: >= 36,
    one entry per (point, node); returns their number).

    The loaded edge of the domain runs between the two corners x_p + foff_p +- r, r the
    half domain vector along the edge (r2 for an offset foff_0 along x, r1 along y).
    CPDI's internal force integrates the linear interpolant of N_i along that edge, so
    the consistent edge load is t |edge| (N_i(e-) + N_i(e+)) / 2: the mean of the corner
    function at the edge's two corners (with the B-spline, N_i at the edge midpoint
    left a uniformly stressed bar out of balance by 30 % of the stress; linear N_i are
    linear along an edge inside a cell, where both agree). A particle without an
    offset (side not on the grid axes) loads its own S_ip."""
    base = corner_kind(kind)
    c0x, c0y, r1x, r1y, r2x, r2y, g0x, g0y, g1x, g1y = domain(p, x, F, hw)
    c = 0
    if foff[p, 0] != 0.0 or foff[p, 1] != 0.0:
        along_y = abs(foff0[p, 0]) >= abs(foff0[p, 1])
        ex = r2x if along_y else r1x
        ey = r2y if along_y else r1y
        for e in range(2):
            sgn = 1.0 if e == 0 else -1.0
            i0, j0, n, w0, w1, w2, q0, q1, q2 = corner_weights(
                x[p, 0] + foff[p, 0] + sgn * ex, x[p, 1] + foff[p, 1] + sgn * ey, origin,
                cell, nn, base)
            for b in range(n):
                for a in range(n):
                    tidx[c] = (j0 + b) * nn[0] + i0 + a
                    tw[c] = 0.5 * _pick(a, w0, w1, w2) * _pick(b, q0, q1, q2)
                    c += 1
        return c
    for k in range(4):
        cx, cy, _, _ = corner(k, c0x, c0y, r1x, r1y, r2x, r2y, g0x, g0y, g1x, g1y)
        i0, j0, n, w0, w1, w2, q0, q1, q2 = corner_weights(cx, cy, origin, cell, nn, base)
        for b in range(n):
            for a in range(n):
                tidx[c] = (j0 + b) * nn[0] + i0 + a
                tw[c] = 0.25 * _pick(a, w0, w1, w2) * _pick(b, q0, q1, q2)
                c += 1
    return c


@njit(cache=True, fastmath=FMA, error_model="numpy")
def tractions_cpdi(x, field, fext, foff, foff0, F, hw, load_scale, origin, cell, nn, kind,
                   force):
    """The ramped traction forces on the loaded domain edges (foff = F foff_0), on the
    nodes of :func:`traction_weights_cpdi`."""
    tidx = np.empty(36, np.int64)
    tw = np.empty(36)
    for p in range(x.shape[0]):
        if fext[p, 0] != 0.0 or fext[p, 1] != 0.0:
            f = field[p]
            c = traction_weights_cpdi(p, x, F, hw, foff, foff0, origin, cell, nn, kind, tidx,
                                      tw)
            for k in range(c):
                force[tidx[k], f, 0] += tw[k] * fext[p, 0] * load_scale
                force[tidx[k], f, 1] += tw[k] * fext[p, 1] * load_scale


@njit(cache=True, fastmath=FMA, error_model="numpy", refcount=False)
def internal_force_cpdi(x, pvol, stress, field, F, hw, origin, cell, nn, kind, force):
    """USF second pass: add -V_p sigma_p . grad S_ip to ``force``."""
    nx = nn[0]
    base = corner_kind(kind)
    for p in range(x.shape[0]):
        f = field[p]
        V = pvol[p]
        c0x, c0y, r1x, r1y, r2x, r2y, g0x, g0y, g1x, g1y = domain(p, x, F, hw)
        for k in range(4):
            cx, cy, gx, gy = corner(k, c0x, c0y, r1x, r1y, r2x, r2y, g0x, g0y, g1x, g1y)
            i0, j0, n, w0, w1, w2, q0, q1, q2 = corner_weights(cx, cy, origin, cell, nn, base)
            for b in range(n):
                wy = _pick(b, q0, q1, q2)
                for a in range(n):
                    N = _pick(a, w0, w1, w2) * wy
                    node = (j0 + b) * nx + i0 + a
                    Gx = gx * N * V
                    Gy = gy * N * V
                    force[node, f, 0] -= stress[p, 0] * Gx + stress[p, 2] * Gy
                    force[node, f, 1] -= stress[p, 2] * Gx + stress[p, 1] * Gy


@njit(cache=True, fastmath=FMA, error_model="numpy", refcount=False)
def momentum_cpdi(x, v, pmass, field, F, hw, origin, cell, nn, kind, mass, mom):
    """MUSL: mass and momentum of the updated particles re-extrapolated (start-of-step
    domains)."""
    mass[:] = 0.0
    mom[:] = 0.0
    nx = nn[0]
    base = corner_kind(kind)
    for p in range(x.shape[0]):
        f = field[p]
        m = 0.25 * pmass[p]
        c0x, c0y, r1x, r1y, r2x, r2y, g0x, g0y, g1x, g1y = domain(p, x, F, hw)
        for k in range(4):
            cx, cy, gx, gy = corner(k, c0x, c0y, r1x, r1y, r2x, r2y, g0x, g0y, g1x, g1y)
            i0, j0, n, w0, w1, w2, q0, q1, q2 = corner_weights(cx, cy, origin, cell, nn, base)
            for b in range(n):
                wy = _pick(b, q0, q1, q2)
                for a in range(n):
                    s = _pick(a, w0, w1, w2) * wy * m
                    node = (j0 + b) * nx + i0 + a
                    mass[node, f] += s
                    mom[node, f, 0] += s * v[p, 0]
                    mom[node, f, 1] += s * v[p, 1]


# ------------------------------------------------------- G2P and stress ----


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def _gather(p, x, F, hw, origin, cell, nn, kind, f, vel, acc, mass, use_mass):
    """Velocity, acceleration and velocity gradient of particle p from the nodal fields
    of its field f: (ax, ay, vx, vy, L00, L01, L10, L11, lost). ``use_mass``: nodal
    velocities = momentum / mass where mass > 0 (``vel`` = momenta), else ``vel``
    holds velocities."""
    base = corner_kind(kind)
    c0x, c0y, r1x, r1y, r2x, r2y, g0x, g0y, g1x, g1y = domain(p, x, F, hw)
    ax = 0.0
    ay = 0.0
    vx = 0.0
    vy = 0.0
    L00 = 0.0
    L01 = 0.0
    L10 = 0.0
    L11 = 0.0
    nx = nn[0]
    for k in range(4):
        cx, cy, gx, gy = corner(k, c0x, c0y, r1x, r1y, r2x, r2y, g0x, g0y, g1x, g1y)
        i0, j0, n, w0, w1, w2, q0, q1, q2 = corner_weights(cx, cy, origin, cell, nn, base)
        if n < 0:
            return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, True
        cvx = 0.0
        cvy = 0.0
        for b in range(n):
            wy = _pick(b, q0, q1, q2)
            for a in range(n):
                N = _pick(a, w0, w1, w2) * wy
                node = (j0 + b) * nx + i0 + a
                if use_mass:
                    mn = mass[node, f]
                    if mn <= 0.0:
                        continue
                    ux = vel[node, f, 0] / mn
                    uy = vel[node, f, 1] / mn
                else:
                    ux = vel[node, f, 0]
                    uy = vel[node, f, 1]
                    ax += 0.25 * N * acc[node, f, 0]
                    ay += 0.25 * N * acc[node, f, 1]
                cvx += N * ux
                cvy += N * uy
        vx += 0.25 * cvx
        vy += 0.25 * cvy
        L00 += cvx * gx
        L01 += cvx * gy
        L10 += cvy * gx
        L11 += cvy * gy
    return ax, ay, vx, vy, L00, L01, L10, L11, False


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def _update_linear(p, f, L00, L01, L10, L11, dt, C, stress, strain, pvol, pvol0, F, foff,
                   foff0) -> float:
    """Small-strain field of a CPDI run: sigma += C sym(L) dt, strain += sym(L) dt, F <-
    (I + dt L) F (in plane), V = det F V_0, foff = F foff_0; returns V_0 sigma:eps / 2."""
    de0 = L00 * dt
    de1 = L11 * dt
    de2 = (L01 + L10) * dt
    strain[p, 0] += de0
    strain[p, 1] += de1
    strain[p, 2] += de2
    stress[p, 0] += C[f, 0, 0] * de0 + C[f, 0, 1] * de1 + C[f, 0, 2] * de2
    stress[p, 1] += C[f, 1, 0] * de0 + C[f, 1, 1] * de1 + C[f, 1, 2] * de2
    stress[p, 2] += C[f, 2, 0] * de0 + C[f, 2, 1] * de1 + C[f, 2, 2] * de2
    a00 = 1.0 + dt * L00
    a01 = dt * L01
    a10 = dt * L10
    a11 = 1.0 + dt * L11
    f00 = a00 * F[p, 0, 0] + a01 * F[p, 1, 0]
    f01 = a00 * F[p, 0, 1] + a01 * F[p, 1, 1]
    f10 = a10 * F[p, 0, 0] + a11 * F[p, 1, 0]
    f11 = a10 * F[p, 0, 1] + a11 * F[p, 1, 1]
    F[p, 0, 0] = f00
    F[p, 0, 1] = f01
    F[p, 1, 0] = f10
    F[p, 1, 1] = f11
    pvol[p] = (f00 * f11 - f01 * f10) * pvol0[p]
    foff[p, 0] = f00 * foff0[p, 0] + f01 * foff0[p, 1]
    foff[p, 1] = f10 * foff0[p, 0] + f11 * foff0[p, 1]
    return 0.5 * pvol0[p] * (stress[p, 0] * strain[p, 0] + stress[p, 1] * strain[p, 1]
                             + stress[p, 2] * strain[p, 2])


@njit(cache=True, fastmath=FMA, error_model="numpy")
def g2p_cpdi(x, v, pmass, pvol, pvol0, stress, strain, field, fext, foff, foff0, F, hw,
             load_scale, C, origin, cell, nn, kind, dt, pic, update_stress, nvel, nacc,
             velgrad, mkind):
    """G2P of :func:`mpm.kernels.g2p_2d` (FLIP with the PIC blend, x += dt sum S v+,
    L = sum v+ (x) grad S; USL: the stress update, finite-strain fields' L stored in
    ``velgrad``) with the CPDI weights; returns (kinetic, strain energy of the linear
    fields, external work, lost particle or -1, grid kinetic energy)."""
    ke = 0.0
    ke_grid = 0.0
    U = 0.0
    work = 0.0
    lost = -1
    tidx = np.empty(36, np.int64)
    tw = np.empty(36)
    no_mass = np.zeros((1, 1))      # nodal velocities given: the masses are not read
    for p in range(x.shape[0]):
        f = field[p]
        ax, ay, vx, vy, L00, L01, L10, L11, out = _gather(p, x, F, hw, origin, cell, nn, kind,
                                                          f, nvel, nacc, no_mass, False)
        if out:
            lost = p
            continue
        if fext[p, 0] != 0.0 or fext[p, 1] != 0.0:
            c = traction_weights_cpdi(p, x, F, hw, foff, foff0, origin, cell, nn, kind, tidx,
                                      tw)
            for kk in range(c):
                work += load_scale * dt * (fext[p, 0] * nvel[tidx[kk], f, 0]
                                           + fext[p, 1] * nvel[tidx[kk], f, 1]) * tw[kk]
        x[p, 0] += dt * vx
        x[p, 1] += dt * vy
        v[p, 0] = (1.0 - pic) * (v[p, 0] + dt * ax) + pic * vx
        v[p, 1] = (1.0 - pic) * (v[p, 1] + dt * ay) + pic * vy
        ke += 0.5 * pmass[p] * (v[p, 0] * v[p, 0] + v[p, 1] * v[p, 1])
        ke_grid += 0.5 * pmass[p] * (vx * vx + vy * vy)
        if mkind[f] != 0:
            if update_stress:
                velgrad[p, 0, 0] = L00
                velgrad[p, 0, 1] = L01
                velgrad[p, 1, 0] = L10
                velgrad[p, 1, 1] = L11
            continue
        if update_stress:
            U += _update_linear(p, f, L00, L01, L10, L11, dt, C, stress, strain, pvol, pvol0,
                                F, foff, foff0)
        else:
            U += 0.5 * pvol0[p] * (stress[p, 0] * strain[p, 0] + stress[p, 1] * strain[p, 1]
                                   + stress[p, 2] * strain[p, 2])
    return ke, U, work, lost, ke_grid


@njit(cache=True, fastmath=FMA, error_model="numpy", refcount=False)
def stress_cpdi(x, pvol, pvol0, stress, strain, field, foff, foff0, F, hw, C, origin, cell,
                nn, kind, dt, mass, mom, velgrad, mkind) -> float:
    """USF / MUSL stress update with L = sum (p_i / m_i) (x) grad S_ip of the particle's
    own field at positions ``x`` (:func:`mpm.kernels.stress_from_grid_2d` with the CPDI
    gradients); returns the strain energy of the linear fields."""
    U = 0.0
    for p in range(x.shape[0]):
        f = field[p]
        _, _, _, _, L00, L01, L10, L11, out = _gather(p, x, F, hw, origin, cell, nn, kind, f,
                                                      mom, mom, mass, True)
        if mkind[f] != 0:
            velgrad[p, 0, 0] = L00
            velgrad[p, 0, 1] = L01
            velgrad[p, 1, 0] = L10
            velgrad[p, 1, 1] = L11
            continue
        U += _update_linear(p, f, L00, L01, L10, L11, dt, C, stress, strain, pvol, pvol0, F,
                            foff, foff0)
    return U


# ------------------------------------------------------------- run setup ----

#: the shape options whose particles carry a deformation gradient and domain vectors
CPDI_SHAPES = ("cpdi", "b2cpdi")


def cpdi_refusal(case, shape: str) -> str | None:
    """The one-line reason a case cannot run with ``shape`` (a CPDI shape), or None."""
    if shape not in CPDI_SHAPES:
        return None
    if case.analysis == "3d":
        return (f"{shape!r} is implemented in 2D (plane strain / plane stress) only; in 3d use "
                "ugimp, linear or b2")
    if case.analysis == "axisymmetric":
        return (f"{shape!r} is implemented for planar analyses only (its hoop terms are not); "
                "use ugimp, linear or b2 in axisymmetric runs")
    return None


def reference_scatter_cpdi(pt, grid, kind: int, nd) -> int:
    """One scatter of the undeformed particles (x0, V0, F = I) into the multimaterial
    nodal sums of ``nd`` (the reference nodal volumes of 000 Eq 20); returns -1 or a
    lost particle."""
    hw = np.ascontiguousarray(np.broadcast_to(0.5 * np.asarray(pt.spacing, float), pt.x0.shape))
    F = np.ascontiguousarray(np.broadcast_to(np.eye(3), (pt.P, 3, 3)))
    return scatter_cpdi(0, pt.P, pt.x0, np.zeros_like(pt.x0), pt.mass, pt.volume0, pt.stress,
                        pt.field, pt.x0, F, hw, grid.origin, grid.cell, grid.nn, kind, True, False,
                        nd.mass, nd.momentum, nd.force, nd.volume, nd.volume_gradient,
                        nd.displacement, nd.position)
