"""Compiled particle kernels of the 3D time step: P2G, G2P, stress updates, tractions.

The same phases, arguments and return values as the 2D kernels of :mod:`mpm.kernels`
(000 Eq 5-6, 10, 13; 004 Eq 5, 28-32), on the 3D grid of mpm/LAYOUT.md (flattened node
index n = i + nx (j + ny k)) and with the 3D Voigt order of the case materials
(``[xx, yy, zz, yz, xz, xy]``, engineering shear). The shape functions are the tensor
products of the 1D factors of :mod:`mpm.shape` (linear, uGIMP, B2): scatters run over
the trimmed 2-or-3 nodes per axis, gathers over the fixed 3 x 3 x 3 stencil.

The 2D kernels stay separate: their gathers are unrolled by hand over the 3 x 3 stencil
(twice as fast as a loop over a dimension-generic stencil), and 2D throughput is the
figure most runs depend on. The node kernels (grid update, multimaterial contact and
interface forces, nodal conditions) are written once for any D.
"""
from __future__ import annotations

import numpy as np

from interfaces.jit import FMA, njit

from .kernels import normalise_weights
from .shape import axis_weights3, axis_weights_tuple, edge_kind


@njit(cache=True, inline="always")
def _pick(k, a0, a1, a2):
    """a_k of three scalars (k < 3)."""
    return a0 if k == 0 else (a1 if k == 1 else a2)


@njit(cache=True, inline="always")
def inside_3d(i0, j0, k0, nax, nay, naz, nn) -> bool:
    """True when the support (i0.., j0.., k0..) of nax x nay x naz nodes lies on the grid."""
    return (i0 >= 0 and j0 >= 0 and k0 >= 0 and i0 + nax <= nn[0] and j0 + nay <= nn[1]
            and k0 + naz <= nn[2])


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def _axes(x, y, z, origin, cell, lp, kind):
    """1D weights along x, y and z of one point (:func:`mpm.shape.axis_weights_tuple`)."""
    ax = axis_weights_tuple(x, origin[0], cell[0], lp[0], kind)
    ay = axis_weights_tuple(y, origin[1], cell[1], lp[1], kind)
    az = axis_weights_tuple(z, origin[2], cell[2], lp[2], kind)
    return ax, ay, az


@njit(cache=True, fastmath=FMA, error_model="numpy")
def p2g_range_3d(lo, hi, x, v, pmass, pvol, stress, field, x0, origin, cell, nn, lp, kind,
                 multi, internal, mass, mom, force, volume, volgrad, disp, pos):
    """Scatter of particles lo..hi-1 into the nodal arrays (added to what they hold):
    mass, momentum, internal force -V sigma . grad S (with ``internal``) and, with
    ``multi``, volume, volume gradient and the mass-weighted displacement and position
    sums. Returns the first particle whose support leaves the grid, or -1."""
    M = mass.shape[1]
    nx = nn[0]
    ny = nn[1]
    for p in range(lo, hi):
        (i0, nax, w0, w1, w2, d0, d1, d2), (j0, nay, q0, q1, q2, e0, e1, e2), \
            (k0, naz, r0, r1, r2, c0, c1, c2) = _axes(x[p, 0], x[p, 1], x[p, 2], origin, cell,
                                                       lp, kind)
        if not inside_3d(i0, j0, k0, nax, nay, naz, nn):
            return p
        f = field[p]
        m = pmass[p]
        V = pvol[p]
        sc = V if internal else 0.0
        s0 = sc * stress[p, 0]
        s1 = sc * stress[p, 1]
        s2 = sc * stress[p, 2]
        s3 = sc * stress[p, 3]
        s4 = sc * stress[p, 4]
        s5 = sc * stress[p, 5]
        mv0 = m * v[p, 0]
        mv1 = m * v[p, 1]
        mv2 = m * v[p, 2]
        for c in range(naz):
            wz = _pick(c, r0, r1, r2)
            dwz = _pick(c, c0, c1, c2)
            for b in range(nay):
                wy = _pick(b, q0, q1, q2)
                dwy = _pick(b, e0, e1, e2)
                row = ((k0 + c) * ny + j0 + b) * nx + i0
                for a in range(nax):
                    wx = _pick(a, w0, w1, w2)
                    dwx = _pick(a, d0, d1, d2)
                    s = wx * wy * wz
                    g = (dwx * wy * wz, wx * dwy * wz, wx * wy * dwz)
                    n = row + a
                    mass[n, f] += s * m
                    mom[n, f, 0] += s * mv0
                    mom[n, f, 1] += s * mv1
                    mom[n, f, 2] += s * mv2
                    force[n, f, 0] -= s0 * g[0] + s5 * g[1] + s4 * g[2]
                    force[n, f, 1] -= s5 * g[0] + s1 * g[1] + s3 * g[2]
                    force[n, f, 2] -= s4 * g[0] + s3 * g[1] + s2 * g[2]
                    if multi:
                        volume[n, f] += s * V
                        for d in range(3):
                            volgrad[n, f, d] += g[d] * V
                            disp[n, f, d] += s * m * (x[p, d] - x0[p, d])
                            pos[n, f, d] += s * m * x[p, d]
    return -1


@njit(cache=True, fastmath=FMA, error_model="numpy")
def _traction_nodes_3d(p, x, foff, origin, cell, nn, lp, kind, tidx, tw) -> int:
    """Nodes and weights carrying the traction of particle p (the 3D form of
    :func:`mpm.kernels._traction_weights`): the surface-point grid weights at the
    loaded face point x_p + foff_p, kept on the nodes of the particle's own support and
    renormalised; the particle's own weights S_ip when no such node exists (or the
    particle has no face offset). Returns the number of nodes."""
    (k0, nbx, q0, q1, q2, _, _, _), (l0, nby, s0, s1, s2, _, _, _), \
        (m0, nbz, t0, t1, t2, _, _, _) = _axes(x[p, 0], x[p, 1], x[p, 2], origin, cell, lp, kind)
    nx = nn[0]
    ny = nn[1]
    c = 0
    tot = 0.0
    if foff[p, 0] != 0.0 or foff[p, 1] != 0.0 or foff[p, 2] != 0.0:
        (i0, nax, w0, w1, w2, _, _, _), (j0, nay, u0, u1, u2, _, _, _), \
            (h0, naz, z0, z1, z2, _, _, _) = _axes(x[p, 0] + foff[p, 0], x[p, 1] + foff[p, 1],
                                                    x[p, 2] + foff[p, 2], origin, cell, lp,
                                                    edge_kind(kind))
        for cz in range(naz):
            for b in range(nay):
                for a in range(nax):
                    ka = i0 + a - k0
                    lb = j0 + b - l0
                    mc = h0 + cz - m0
                    if not (0 <= ka < nbx and 0 <= lb < nby and 0 <= mc < nbz):
                        continue
                    if _pick(ka, q0, q1, q2) * _pick(lb, s0, s1, s2) * _pick(mc, t0, t1, t2) <= 0.0:
                        continue
                    w = _pick(a, w0, w1, w2) * _pick(b, u0, u1, u2) * _pick(cz, z0, z1, z2)
                    if w > 0.0:
                        tidx[c] = ((h0 + cz) * ny + j0 + b) * nx + i0 + a
                        tw[c] = w
                        tot += w
                        c += 1
    if normalise_weights(tw, c, tot):
        return c
    c = 0
    for cz in range(nbz):
        for b in range(nby):
            for a in range(nbx):
                tidx[c] = ((m0 + cz) * ny + l0 + b) * nx + k0 + a
                tw[c] = _pick(a, q0, q1, q2) * _pick(b, s0, s1, s2) * _pick(cz, t0, t1, t2)
                c += 1
    return c


@njit(cache=True, fastmath=FMA, error_model="numpy")
def p2g_tractions_3d(x, field, fext, foff, load_scale, origin, cell, nn, lp, kind, force):
    """Add the ramped particle traction forces ``load_scale * fext`` to ``force``."""
    tidx = np.empty(27, np.int64)
    tw = np.empty(27)
    for p in range(x.shape[0]):
        if fext[p, 0] != 0.0 or fext[p, 1] != 0.0 or fext[p, 2] != 0.0:
            f = field[p]
            c = _traction_nodes_3d(p, x, foff, origin, cell, nn, lp, kind, tidx, tw)
            for k in range(c):
                for d in range(3):
                    force[tidx[k], f, d] += tw[k] * fext[p, d] * load_scale


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def stress_increment_3d(p, f, L, dt, C, stress, strain, pvol) -> None:
    """Small-strain increment d_eps = sym(L) dt (Voigt [xx, yy, zz, yz, xz, xy],
    engineering shear), sigma += C d_eps, V *= 1 + tr(d_eps)."""
    de = (L[0, 0] * dt, L[1, 1] * dt, L[2, 2] * dt, (L[1, 2] + L[2, 1]) * dt,
          (L[0, 2] + L[2, 0]) * dt, (L[0, 1] + L[1, 0]) * dt)
    for a in range(6):
        strain[p, a] += de[a]
        s = 0.0
        for b in range(6):
            s += C[f, a, b] * de[b]
        stress[p, a] += s
    pvol[p] *= 1.0 + de[0] + de[1] + de[2]


@njit(cache=True, inline="always")
def store_gradient_3d(velgrad, p, L) -> None:
    """velgrad[p] = L (finite-strain fields, :mod:`mpm.finite_strain`)."""
    for i in range(3):
        for j in range(3):
            velgrad[p, i, j] = L[i, j]


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def _strain_energy(p, pvol0, stress, strain) -> float:
    s = 0.0
    for a in range(6):
        s += stress[p, a] * strain[p, a]
    return 0.5 * pvol0[p] * s


@njit(cache=True, fastmath=FMA, error_model="numpy")
def g2p_range_3d(lo, hi, x, v, pmass, pvol, pvol0, stress, strain, field, fext, foff,
                 load_scale, C, origin, cell, nn, lp, kind, dt, pic, update_stress, nvel, nacc,
                 velgrad, mkind):
    """Grid-to-particle update of particles lo..hi-1 (the 3D form of
    :func:`mpm.kernels.g2p_range_2d`: FLIP with the ``pic`` blend, x += dt S v+,
    L = sum v+ (x) grad S, USL stress update, or L stored in ``velgrad`` for a
    finite-strain field); returns (kinetic energy, strain energy of the linear fields,
    external work, lost particle or -1, grid kinetic energy)."""
    ke = 0.0
    ke_grid = 0.0
    U = 0.0
    work = 0.0
    lost = -1
    tidx = np.empty(27, np.int64)
    tw = np.empty(27)
    nx = nn[0]
    ny = nn[1]
    L = np.empty((3, 3))
    acc = np.empty(3)
    vel = np.empty(3)
    for p in range(lo, hi):
        i0, w0, w1, w2, d0, d1, d2 = axis_weights3(x[p, 0], origin[0], cell[0], lp[0], kind)
        j0, q0, q1, q2, e0, e1, e2 = axis_weights3(x[p, 1], origin[1], cell[1], lp[1], kind)
        k0, r0, r1, r2, c0, c1, c2 = axis_weights3(x[p, 2], origin[2], cell[2], lp[2], kind)
        if not inside_3d(i0, j0, k0, 3, 3, 3, nn):
            lost = p
            continue
        f = field[p]
        acc[:] = 0.0
        vel[:] = 0.0
        L[:] = 0.0
        for c in range(3):
            wz = _pick(c, r0, r1, r2)
            dwz = _pick(c, c0, c1, c2)
            for b in range(3):
                wy = _pick(b, q0, q1, q2)
                dwy = _pick(b, e0, e1, e2)
                row = ((k0 + c) * ny + j0 + b) * nx + i0
                for a in range(3):
                    wx = _pick(a, w0, w1, w2)
                    dwx = _pick(a, d0, d1, d2)
                    s = wx * wy * wz
                    g = (dwx * wy * wz, wx * dwy * wz, wx * wy * dwz)
                    n = row + a
                    for i in range(3):
                        vi = nvel[n, f, i]
                        acc[i] += s * nacc[n, f, i]
                        vel[i] += s * vi
                        L[i, 0] += vi * g[0]
                        L[i, 1] += vi * g[1]
                        L[i, 2] += vi * g[2]
        if fext[p, 0] != 0.0 or fext[p, 1] != 0.0 or fext[p, 2] != 0.0:
            # work of the traction: force x velocity of the nodes that carried it
            nc = _traction_nodes_3d(p, x, foff, origin, cell, nn, lp, kind, tidx, tw)
            for kk in range(nc):
                for d in range(3):
                    work += load_scale * dt * fext[p, d] * nvel[tidx[kk], f, d] * tw[kk]
        for d in range(3):
            x[p, d] += dt * vel[d]
            v[p, d] = (1.0 - pic) * (v[p, d] + dt * acc[d]) + pic * vel[d]
            ke += 0.5 * pmass[p] * v[p, d] * v[p, d]
            ke_grid += 0.5 * pmass[p] * vel[d] * vel[d]
        if mkind[f] != 0:
            if update_stress:
                store_gradient_3d(velgrad, p, L)
            continue
        if update_stress:
            stress_increment_3d(p, f, L, dt, C, stress, strain, pvol)
        U += _strain_energy(p, pvol0, stress, strain)
    return ke, U, work, lost, ke_grid


@njit(cache=True, fastmath=FMA, error_model="numpy")
def stress_from_grid_3d(x, pvol, pvol0, stress, strain, field, C, origin, cell, nn, lp, kind,
                        dt, mass, mom, velgrad, mkind):
    """Stress update with L = sum (p_i/m_i) (x) grad S_ip of the particle's own field
    (USF: initial extrapolation; MUSL: re-extrapolated momenta); returns the strain
    energy of the linear fields (finite-strain fields: L stored in ``velgrad``). The 3D
    form of :func:`mpm.kernels.stress_from_grid_2d`."""
    nx = nn[0]
    ny = nn[1]
    U = 0.0
    L = np.empty((3, 3))
    for p in range(x.shape[0]):
        (i0, nax, w0, w1, w2, d0, d1, d2), (j0, nay, q0, q1, q2, e0, e1, e2), \
            (k0, naz, r0, r1, r2, c0, c1, c2) = _axes(x[p, 0], x[p, 1], x[p, 2], origin, cell,
                                                       lp, kind)
        if not inside_3d(i0, j0, k0, nax, nay, naz, nn):
            naz = 0
        f = field[p]
        L[:] = 0.0
        for c in range(naz):
            for b in range(nay):
                row = ((k0 + c) * ny + j0 + b) * nx + i0
                for a in range(nax):
                    n = row + a
                    m = mass[n, f]
                    if m <= 0.0:
                        continue
                    wx = _pick(a, w0, w1, w2)
                    wy = _pick(b, q0, q1, q2)
                    wz = _pick(c, r0, r1, r2)
                    g = (_pick(a, d0, d1, d2) * wy * wz, wx * _pick(b, e0, e1, e2) * wz,
                         wx * wy * _pick(c, c0, c1, c2))
                    for i in range(3):
                        vi = mom[n, f, i] / m
                        for j in range(3):
                            L[i, j] += vi * g[j]
        if mkind[f] != 0:
            store_gradient_3d(velgrad, p, L)
            continue
        stress_increment_3d(p, f, L, dt, C, stress, strain, pvol)
        U += _strain_energy(p, pvol0, stress, strain)
    return U


@njit(cache=True, fastmath=FMA, error_model="numpy")
def p2g_momentum_3d(x, v, pmass, field, origin, cell, nn, lp, kind, mass, mom):
    """Re-extrapolate mass and momentum of the updated particles (MUSL)."""
    mass[:] = 0.0
    mom[:] = 0.0
    nx = nn[0]
    ny = nn[1]
    for p in range(x.shape[0]):
        (i0, nax, w0, w1, w2, _, _, _), (j0, nay, q0, q1, q2, _, _, _), \
            (k0, naz, r0, r1, r2, _, _, _) = _axes(x[p, 0], x[p, 1], x[p, 2], origin, cell, lp,
                                                    kind)
        if not inside_3d(i0, j0, k0, nax, nay, naz, nn):
            continue
        f = field[p]
        for c in range(naz):
            for b in range(nay):
                row = ((k0 + c) * ny + j0 + b) * nx + i0
                for a in range(nax):
                    s = _pick(a, w0, w1, w2) * _pick(b, q0, q1, q2) * _pick(c, r0, r1, r2) \
                        * pmass[p]
                    n = row + a
                    mass[n, f] += s
                    for d in range(3):
                        mom[n, f, d] += s * v[p, d]


@njit(cache=True, fastmath=FMA, error_model="numpy")
def p2g_internal_force_3d(x, pvol, stress, field, origin, cell, nn, lp, kind, force):
    """Add the internal force -V_p sigma_p . grad S_ip to ``force`` (USF second pass)."""
    nx = nn[0]
    ny = nn[1]
    for p in range(x.shape[0]):
        (i0, nax, w0, w1, w2, d0, d1, d2), (j0, nay, q0, q1, q2, e0, e1, e2), \
            (k0, naz, r0, r1, r2, c0, c1, c2) = _axes(x[p, 0], x[p, 1], x[p, 2], origin, cell,
                                                       lp, kind)
        if not inside_3d(i0, j0, k0, nax, nay, naz, nn):
            continue
        f = field[p]
        V = pvol[p]
        s = stress[p]
        for c in range(naz):
            for b in range(nay):
                row = ((k0 + c) * ny + j0 + b) * nx + i0
                for a in range(nax):
                    wx = _pick(a, w0, w1, w2)
                    wy = _pick(b, q0, q1, q2)
                    wz = _pick(c, r0, r1, r2)
                    gx = _pick(a, d0, d1, d2) * wy * wz
                    gy = wx * _pick(b, e0, e1, e2) * wz
                    gz = wx * wy * _pick(c, c0, c1, c2)
                    n = row + a
                    force[n, f, 0] -= V * (s[0] * gx + s[5] * gy + s[4] * gz)
                    force[n, f, 1] -= V * (s[5] * gx + s[1] * gy + s[3] * gz)
                    force[n, f, 2] -= V * (s[4] * gx + s[3] * gy + s[2] * gz)
