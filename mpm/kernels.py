"""Compiled per-particle and per-node kernels of one explicit MPM time step (2D).

Layout of the nodal arrays: mpm/LAYOUT.md. Step order (004 Sec 3.2, Eq 26-34):
P2G -> contact correction (phase 0) -> interface forces -> momentum update with grid
damping and nodal boundary conditions -> contact correction (phase 1) -> G2P (FLIP,
optional PIC blend) -> stress update: USL (default, updated grid velocities), MUSL (
momenta re-extrapolated from the updated particles, robust on boundaries that cut
cells) or USF (phase-0 corrected initial extrapolation, before the internal force).

The particle loops are written over a particle range (``p2g_range_2d``,
``g2p_range_2d``): the serial kernels run them over all particles, mpm/parallel.py over
contiguous blocks in parallel (race-free P2G: one nodal buffer per block, numba has no
CPU atomics). The time step assembled from these kernels is mpm/step.py. Hot loops take the 1D shape weights as scalars
(:func:`mpm.shape.axis_weights_tuple`) and keep work arrays local: passing arrays into
inlined helpers per particle costs numba reference-count calls (halved P2G speed).
The 3D particle kernels, with the same arguments, are those of mpm/kernels3d.py.
"""
from __future__ import annotations

import math

import numpy as np

from interfaces.jit import FMA, njit

from .shape import (axis_weights, axis_weights3, axis_weights_tuple, edge_kind, shape_2d_work,
                    stencil_work)

#: stress-update schemes: update stress last (grid velocities after the momentum
#: update), first (initial extrapolation), modified USL (re-extrapolated particle momenta)
USL = 0
USF = 1
MUSL = 2
UPDATE_CODES = {"usl": USL, "usf": USF, "musl": MUSL}

# -------------------------------------------------------------------- P2G ----


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def _support(x, y, origin, cell, nn, lp, kind, wx, dwx, wy, dwy):
    """1D weights along x and y of one particle; returns (i0, j0, nodes along x,
    nodes along y), the counts -1 if the support leaves the grid."""
    i0, nax = axis_weights(x, origin[0], cell[0], lp[0], kind, wx, dwx)
    j0, nay = axis_weights(y, origin[1], cell[1], lp[1], kind, wy, dwy)
    if i0 < 0 or j0 < 0 or i0 + nax > nn[0] or j0 + nay > nn[1]:
        return i0, j0, -1, -1
    return i0, j0, nax, nay




@njit(cache=True, inline="always")
def _inside(i0, j0, nax, nay, nn) -> bool:
    """True when the support (i0.., j0..) of nax x nay nodes lies on the grid."""
    return i0 >= 0 and j0 >= 0 and i0 + nax <= nn[0] and j0 + nay <= nn[1]


@njit(cache=True)
def _traction_work():
    """Work arrays of :func:`_traction_weights`: 1D weights and gradients of the edge
    point (wx, dwx, wy, dwy) and of the particle (qx, dqx, qy, dqy), node indices and
    weights (9 each)."""
    return (np.empty(3), np.empty(3), np.empty(3), np.empty(3), np.empty(3), np.empty(3),
            np.empty(3), np.empty(3), np.empty(9, np.int64), np.empty(9))


@njit(cache=True, inline="always")
def normalise_weights(tw, c, tot) -> bool:
    """Divide the ``c`` traction weights ``tw`` by their sum ``tot``; False (nothing
    done) when no node qualified (``tot`` = 0)."""
    if tot <= 0.0:
        return False
    for k in range(c):
        tw[k] /= tot
    return True


@njit(cache=True, fastmath=FMA, error_model="numpy")
def _traction_weights(px, py, ex, ey, origin, cell, nn, lp, kind, tidx, tw,
                      wx, dwx, wy, dwy, qx, dqx, qy, dqy):
    """Nodes and weights carrying the traction of the particle at (px, py) whose loaded
    edge point is (ex, ey); returns their number.

    The grid weights of a surface point at the edge point (:func:`mpm.shape.edge_kind`:
    linear for GIMP, the particle-edge integral of GIMP tractions, so that on an edge
    lying on a node line the whole force goes to that line; the spline itself for B2,
    whose internal forces integrate the spline over the body), kept
    only on nodes of the particle's own support (S_ip > 0), then renormalised: a node
    without mass (the edge moved past a node line) would lose the force. The small
    share a tail node receives once the edge has moved past a node line balances the
    internal force of that node (dropping it costs 1.7 % of the end displacement of a
    uniaxial bar). Sides that are not aligned with the grid axes cut cells, where
    the edge point's nodes may hold only particle tails (huge accelerations): their
    particles carry no offset and use their own weights S_ip, as when no node qualifies.
    """
    k0, l0, nbx, nby = _support(px, py, origin, cell, nn, lp, kind, qx, dqx, qy, dqy)
    c = 0
    tot = 0.0
    if ex == px and ey == py:
        nay = 0  # no edge offset (side not on the grid axes): the particle's weights
    else:
        i0, j0, nax, nay = _support(ex, ey, origin, cell, nn, lp, edge_kind(kind), wx, dwx,
                                    wy, dwy)
    for b in range(nay):
        for a in range(nax):
            ka = i0 + a - k0
            lb = j0 + b - l0
            if 0 <= ka < nbx and 0 <= lb < nby and qx[ka] * qy[lb] > 0.0:
                w = wx[a] * wy[b]
                if w > 0.0:
                    tidx[c] = (j0 + b) * nn[0] + i0 + a
                    tw[c] = w
                    tot += w
                    c += 1
    if normalise_weights(tw, c, tot):
        return c
    c = 0
    for b in range(nby):
        for a in range(nbx):
            tidx[c] = (l0 + b) * nn[0] + k0 + a
            tw[c] = qx[a] * qy[b]
            c += 1
    return c


@njit(cache=True, fastmath=FMA, error_model="numpy")
def p2g_2d(x, v, pmass, pvol, stress, field, x0, fext, foff, load_scale,
           origin, cell, nn, lp, kind, multi, internal,
           mass, mom, force, volume, volgrad, disp, pos):
    """Particle-to-grid extrapolation (000 Eq 5-6, 10, 13; 004 Eq 5, 29).

    Zeroes and fills mass, momentum and force (internal -V sigma.grad S if
    ``internal``, plus the ramped particle traction force, extrapolated with the
    linear grid shape functions at the particle's loaded edge x_p + foff_p, i.e.
    integrated over the particle-domain edge as for GIMP tractions); with ``multi`` also
    volume, volume gradient, mass-weighted displacement and position (divided by the
    field mass at the end). Returns -1, or the index of a particle whose support
    left the grid. Serial scatter; :func:`mpm.parallel.p2g_blocks_2d` is the race-free
    parallel form.
    """
    zero_nodal(multi, mass, mom, force, volume, volgrad, disp, pos)
    lost = p2g_range_2d(0, x.shape[0], x, v, pmass, pvol, stress, field, x0, origin, cell, nn,
                        lp, kind, multi, internal, mass, mom, force, volume, volgrad, disp, pos)
    if lost >= 0:
        return lost
    p2g_tractions_2d(x, field, fext, foff, load_scale, origin, cell, nn, lp, kind, force)
    if multi:
        normalise_fields(mass, disp, pos)
    return -1


@njit(cache=True)
def zero_nodal(multi, mass, mom, force, volume, volgrad, disp, pos):
    """Zero the nodal arrays P2G fills (the multimaterial ones with ``multi``)."""
    mass[:] = 0.0
    mom[:] = 0.0
    force[:] = 0.0
    if multi:
        volume[:] = 0.0
        volgrad[:] = 0.0
        disp[:] = 0.0
        pos[:] = 0.0


@njit(cache=True, inline="always")
def _pick(k, a0, a1, a2):
    """a_k of three scalars (k < 3): a select, so the weights stay in registers."""
    return a0 if k == 0 else (a1 if k == 1 else a2)


@njit(cache=True, inline="always")
def _window3(i0, n, w0, w1, w2):
    """A 3-node window (start, weights) holding the support i0.. of 2 or 3 nodes (unused
    weights 0) on an axis of ``n`` nodes: shifted back one node at the grid's end."""
    if i0 + 3 > n:
        return i0 - 1, 0.0, w0, w1
    return i0, w0, w1, w2


@njit(cache=True, fastmath=FMA, error_model="numpy")
def p2g_range_2d(lo, hi, x, v, pmass, pvol, stress, field, x0, origin, cell, nn, lp, kind,
                 multi, internal, mass, mom, force, volume, volgrad, disp, pos, xnode=None,
                 xweight=None):
    """Scatter of particles lo..hi-1 (mass, momentum, internal force and, with
    ``multi``, the unnormalised multimaterial sums) into the given nodal arrays,
    added to what they hold. Returns the first particle whose support leaves the grid
    (the scatter stops there) or -1. XPIC(m) runs pass ``xnode``, ``xweight`` (rows >=
    P): each particle's 3 x 3 stencil for the XPIC passes of the step, from the weights
    computed here (:func:`mpm.xpic.stencil_arrays`).

    Written for speed (the scatter and the gather of G2P are most of a step): 1D weights
    as scalars, flat views of the nodal arrays, trimmed 2-or-3 node loops (fewer
    read-modify-writes than a fixed 3 x 3 stencil)."""
    M = mass.shape[1]
    mf = mass.reshape(-1)
    pf = mom.reshape(-1)
    ff = force.reshape(-1)
    if multi:
        vf = volume.reshape(-1)
        gf = volgrad.reshape(-1)
        df = disp.reshape(-1)
        qf = pos.reshape(-1)
    else:
        vf = mf
        gf = pf
        df = pf
        qf = pf
    nx = nn[0]
    for p in range(lo, hi):
        i0, nax, w0, w1, w2, d0, d1, d2 = axis_weights_tuple(x[p, 0], origin[0], cell[0], lp[0],
                                                             kind)
        j0, nay, q0, q1, q2, e0, e1, e2 = axis_weights_tuple(x[p, 1], origin[1], cell[1], lp[1],
                                                             kind)
        if not _inside(i0, j0, nax, nay, nn):
            return p
        f = field[p]
        if xnode is not None:
            if xnode.shape[0]:
                a, s0, s1, s2 = _window3(i0, nx, w0, w1, w2)
                b, t0, t1, t2 = _window3(j0, nn[1], q0, q1, q2)
                xnode[p, 0] = ((b * nx + a) * M + f) * 2
                xweight[p, 0] = s0
                xweight[p, 1] = s1
                xweight[p, 2] = s2
                xweight[p, 3] = t0
                xweight[p, 4] = t1
                xweight[p, 5] = t2
        m = pmass[p]
        V = pvol[p]
        mvx = m * v[p, 0]
        mvy = m * v[p, 1]
        if internal:
            sxx = V * stress[p, 0]
            syy = V * stress[p, 1]
            sxy = V * stress[p, 2]
        else:
            sxx = 0.0
            syy = 0.0
            sxy = 0.0
        mux = 0.0
        muy = 0.0
        mxx = 0.0
        mxy = 0.0
        if multi:
            mux = m * (x[p, 0] - x0[p, 0])
            muy = m * (x[p, 1] - x0[p, 1])
            mxx = m * x[p, 0]
            mxy = m * x[p, 1]
        for b in range(nay):
            row = (j0 + b) * nx + i0
            wy = _pick(b, q0, q1, q2)
            dwy = _pick(b, e0, e1, e2)
            for a in range(nax):
                wx = _pick(a, w0, w1, w2)
                s = wx * wy
                gx = _pick(a, d0, d1, d2) * wy
                gy = wx * dwy
                k = (row + a) * M + f
                mf[k] += s * m
                pf[2 * k] += s * mvx
                pf[2 * k + 1] += s * mvy
                ff[2 * k] -= sxx * gx + sxy * gy
                ff[2 * k + 1] -= sxy * gx + syy * gy
                if multi:
                    vf[k] += s * V
                    gf[2 * k] += gx * V
                    gf[2 * k + 1] += gy * V
                    df[2 * k] += s * mux
                    df[2 * k + 1] += s * muy
                    qf[2 * k] += s * mxx
                    qf[2 * k + 1] += s * mxy
    return -1


@njit(cache=True, fastmath=FMA, error_model="numpy")
def p2g_tractions_2d(x, field, fext, foff, load_scale, origin, cell, nn, lp, kind, force):
    """Add the ramped particle traction forces ``load_scale * fext`` to ``force`` at the
    nodes of the loaded particle edges (:func:`_traction_weights`)."""
    wx, dwx, wy, dwy, qx, dqx, qy, dqy, tidx, tw = _traction_work()
    for p in range(x.shape[0]):
        if fext[p, 0] != 0.0 or fext[p, 1] != 0.0:
            f = field[p]
            c = _traction_weights(x[p, 0], x[p, 1], x[p, 0] + foff[p, 0], x[p, 1] + foff[p, 1],
                                  origin, cell, nn, lp, kind, tidx, tw, wx, dwx, wy, dwy,
                                  qx, dqx, qy, dqy)
            for k in range(c):
                force[tidx[k], f, 0] += tw[k] * fext[p, 0] * load_scale
                force[tidx[k], f, 1] += tw[k] * fext[p, 1] * load_scale


@njit(cache=True, fastmath=FMA, error_model="numpy")
def normalise_fields(mass, disp, pos):
    """Mass-weighted sums of displacement and position -> field averages (000 Eq 13)."""
    for n in range(mass.shape[0]):
        for f in range(mass.shape[1]):
            if mass[n, f] > 0.0:
                inv = 1.0 / mass[n, f]
                for d in range(disp.shape[2]):
                    disp[n, f, d] *= inv
                    pos[n, f, d] *= inv


@njit(cache=True, fastmath=FMA, error_model="numpy")
def p2g_internal_force_2d(x, pvol, stress, field, origin, cell, nn, lp, kind, force):
    """Add the internal force -V_p sigma_p . grad S_ip to ``force`` (USF second pass)."""
    idx, S, G, wx, dwx, wy, dwy = stencil_work()
    for p in range(x.shape[0]):
        c = shape_2d_work(x[p, 0], x[p, 1], origin, cell, nn, lp, kind, idx, S, G,
                          wx, dwx, wy, dwy)
        f = field[p]
        V = pvol[p]
        for k in range(c):
            n = idx[k]
            force[n, f, 0] -= V * (stress[p, 0] * G[k, 0] + stress[p, 2] * G[k, 1])
            force[n, f, 1] -= V * (stress[p, 2] * G[k, 0] + stress[p, 1] * G[k, 1])


@njit(cache=True)
def multimaterial_nodes(mass):
    """Indices of nodes where two or more fields have mass > 0 (mpm/LAYOUT.md)."""
    N, M = mass.shape
    out = np.empty(N, np.int64)
    c = 0
    if M < 2:
        return out[:0]
    for n in range(N):
        k = 0
        for f in range(M):
            if mass[n, f] > 0.0:
                k += 1
        if k >= 2:
            out[c] = n
            c += 1
    return out[:c]


# ------------------------------------------------------------ grid update ----


@njit(cache=True, inline="always")
def real_share(real_mass, mass, n, f) -> float:
    """Share of the nodal mass that is the run's own material: 1, or with the B2
    symmetry folds (``real_mass`` = the masses before the fold) real / folded, so that
    the damping and reactions count only the real body's energy."""
    if real_mass.shape[0] == 0:
        return 1.0
    return real_mass[n, f] / mass[n, f]


@njit(cache=True, fastmath=FMA, error_model="numpy")
def grid_update(mass, mom, force, dt, alpha, bc_node, bc_field, bc_comp, bc_vel, real_mass):
    """Momentum update p+ = p + (f - alpha p) dt (004 Eq 30) with grid damping alpha,
    then nodal velocity conditions per field: p+ = m v_bc and f += (m v_bc - p+)/dt.

    ``force`` keeps the damping and the reaction terms so that the FLIP update sees
    the acceleration of the grid. Returns (energy dissipated by damping this step,
    work done by the prescribed velocities this step), of the real material
    (:func:`real_share`).
    """
    N, M, D = mom.shape
    diss = 0.0
    for n in range(N):
        for f in range(M):
            m = mass[n, f]
            if m <= 0.0:
                continue
            w = real_share(real_mass, mass, n, f)
            for d in range(D):
                p = mom[n, f, d]
                fd = force[n, f, d] - alpha * p
                diss += w * alpha * p * p / m * dt
                force[n, f, d] = fd
                mom[n, f, d] = p + fd * dt
    work = 0.0
    for b in range(bc_node.size):
        n = bc_node[b]
        f = bc_field[b]
        d = bc_comp[b]
        m = mass[n, f]
        if m <= 0.0:
            continue
        pn = m * bc_vel[b]
        reaction = (pn - mom[n, f, d]) / dt
        force[n, f, d] += reaction
        mom[n, f, d] = pn
        work += real_share(real_mass, mass, n, f) * reaction * bc_vel[b] * dt
    return diss, work


# -------------------------------------------------------- G2P and stress ----


@njit(cache=True, fastmath=FMA, error_model="numpy")
def nodal_kinematics(mass, mom, force, nvel, nacc):
    """Nodal velocity v = p/m and acceleration a = f/m per field (0 where m = 0).

    (The stopping criterion uses the particle-interpolated grid kinetic energy of
    :func:`g2p_2d`, not the nodal sum |p|^2 / 2m, so none is accumulated here.)
    """
    N, M, D = mom.shape
    for n in range(N):
        for f in range(M):
            m = mass[n, f]
            inv = 1.0 / m if m > 0.0 else 0.0
            for d in range(D):
                nvel[n, f, d] = mom[n, f, d] * inv
                nacc[n, f, d] = force[n, f, d] * inv


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def _stress_increment(p, f, L00, L01, L10, L11, dt, C, stress, strain, pvol):
    """Incremental small strain d_eps = sym(L) dt (engineering shear), sigma += C d_eps."""
    e0 = L00 * dt
    e1 = L11 * dt
    e2 = (L01 + L10) * dt
    strain[p, 0] += e0
    strain[p, 1] += e1
    strain[p, 2] += e2
    for a in range(3):
        stress[p, a] += C[f, a, 0] * e0 + C[f, a, 1] * e1 + C[f, a, 2] * e2
    pvol[p] *= 1.0 + e0 + e1


@njit(cache=True, inline="always")
def store_gradient_2d(velgrad, p, L00, L01, L10, L11):
    """velgrad[p] = L (finite-strain fields, :mod:`mpm.finite_strain`)."""
    velgrad[p, 0, 0] = L00
    velgrad[p, 0, 1] = L01
    velgrad[p, 1, 0] = L10
    velgrad[p, 1, 1] = L11


@njit(cache=True, fastmath=FMA, error_model="numpy")
def g2p_2d(x, v, pmass, pvol, pvol0, stress, strain, field, fext, foff, load_scale, C,
           origin, cell, nn, lp, kind, dt, pic, update_stress,
           nvel, nacc, velgrad, mkind):
    """Grid-to-particle update (004 Eq 28, 32 with f^{C,1}) and USL stress update.

    a = force/mass (``nacc``) and v+ = momentum/mass (``nvel``) of the particle's own
    field, from :func:`nodal_kinematics`;
    V <- (1 - pic)(V + dt S a) + pic S v+; x <- x + dt S v+; L = sum v+ (x) grad S.
    Returns (kinetic energy, strain energy, work of the external forces this step,
    index of a particle that left the grid or -1, kinetic energy of the grid motion seen
    by the particles sum m_p |S v+|^2 / 2). The last one is the stopping measure: the
    particle kinetic energy carries FLIP null-space velocities (004 Sec 3.3), and the
    nodal sum |p+|^2 / 2m has a floor from nodes holding only particle tails (bodies whose
    edges cut cells), where the unbalanced force of a tiny mass gives a large velocity
    that no particle follows (S_ip v_i -> 0). The particles of a finite-strain field
    (``mkind[f]`` nonzero, :mod:`mpm.finite_strain`) only get their velocity gradient
    stored in ``velgrad[p]`` (their stress update and energy are those of
    :func:`mpm.finite_strain.finite_strain_update`). Serial;
    :func:`mpm.parallel.g2p_blocks_2d` runs :func:`g2p_range_2d` over particle blocks.
    """
    return g2p_range_2d(0, x.shape[0], x, v, pmass, pvol, pvol0, stress, strain, field, fext,
                        foff, load_scale, C, origin, cell, nn, lp, kind, dt, pic,
                        update_stress, nvel, nacc, velgrad, mkind)[:5]


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def _gather_row3(k, st, wy, dwy, w0, w1, w2, d0, d1, d2, vf, af):
    """Sums over the 3 nodes k, k + st, k + 2 st of one stencil row (flat index k of the
    x component, st the flat stride between x-neighbours): (S a_x, S a_y, S v_x, S v_y,
    v_x G_x, v_x G_y, v_y G_x, v_y G_y)."""
    s0 = w0 * wy
    s1 = w1 * wy
    s2 = w2 * wy
    gx0 = d0 * wy
    gx1 = d1 * wy
    gx2 = d2 * wy
    gy0 = w0 * dwy
    gy1 = w1 * dwy
    gy2 = w2 * dwy
    u0 = vf[k]
    u1 = vf[k + st]
    u2 = vf[k + 2 * st]
    v0 = vf[k + 1]
    v1 = vf[k + st + 1]
    v2 = vf[k + 2 * st + 1]
    return (s0 * af[k] + s1 * af[k + st] + s2 * af[k + 2 * st],
            s0 * af[k + 1] + s1 * af[k + st + 1] + s2 * af[k + 2 * st + 1],
            s0 * u0 + s1 * u1 + s2 * u2,
            s0 * v0 + s1 * v1 + s2 * v2,
            gx0 * u0 + gx1 * u1 + gx2 * u2,
            gy0 * u0 + gy1 * u1 + gy2 * u2,
            gx0 * v0 + gx1 * v1 + gx2 * v2,
            gy0 * v0 + gy1 * v1 + gy2 * v2)


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def _row3(k, st, wy, w0, w1, w2, f):
    """wy (w0, w1, w2) . f over the 3 nodes k, k + st, k + 2 st of one stencil row (x and y
    components)."""
    return (wy * (w0 * f[k] + w1 * f[k + st] + w2 * f[k + 2 * st]),
            wy * (w0 * f[k + 1] + w1 * f[k + st + 1] + w2 * f[k + 2 * st + 1]))


@njit(cache=True, fastmath=FMA, error_model="numpy")
def g2p_range_2d(lo, hi, x, v, pmass, pvol, pvol0, stress, strain, field, fext, foff,
                 load_scale, C, origin, cell, nn, lp, kind, dt, pic, update_stress, nvel, nacc,
                 velgrad, mkind, beta=0.0, vtil=None):
    """:func:`g2p_2d` for particles lo..hi-1 (each particle only touches its own data).

    The gather runs over the fixed 3 x 3 stencil of :func:`mpm.shape.axis_weights3`
    (unrolled; zero weights outside the support), so a particle is lost when that
    stencil leaves the grid (the grid keeps >= 2 empty cells of padding).

    With ``vtil`` (the flat XPIC(m) grid velocity v~ of mpm/xpic.py, laid out as
    ``nvel``; None compiles the loop without it) the XPIC blend of 004 Eq 35 follows in
    the same loop: V <- (1 - beta) V + beta S v~, x += beta dt (S v~ - S v+); the sixth
    value returned is the kinetic energy before that blend (the FLIP one; = the first
    without it)."""
    ke = 0.0
    ke_flip = 0.0
    ke_grid = 0.0
    U = 0.0
    work = 0.0
    lost = -1
    wx, dwx, wy, dwy, qx, dqx, qy, dqy, tidx, tw = _traction_work()
    nx = nn[0]
    M = nvel.shape[1]
    vf = nvel.reshape(-1)
    af = nacc.reshape(-1)
    st = 2 * M              # flat stride between x-neighbours
    srow = 2 * M * nx       # ... and between y-neighbours
    for p in range(lo, hi):
        i0, w0, w1, w2, d0, d1, d2 = axis_weights3(x[p, 0], origin[0], cell[0], lp[0], kind)
        j0, q0, q1, q2, e0, e1, e2 = axis_weights3(x[p, 1], origin[1], cell[1], lp[1], kind)
        if not _inside(i0, j0, 3, 3, nn):
            lost = p
            continue
        f = field[p]
        k = 2 * ((j0 * nx + i0) * M + f)
        a0, b0, c0, g0, l0, m0, n0, o0 = _gather_row3(k, st, q0, e0, w0, w1, w2, d0, d1, d2,
                                                      vf, af)
        a1, b1, c1, g1, l1, m1, n1, o1 = _gather_row3(k + srow, st, q1, e1, w0, w1, w2, d0, d1,
                                                      d2, vf, af)
        a2, b2, c2, g2, l2, m2, n2, o2 = _gather_row3(k + 2 * srow, st, q2, e2, w0, w1, w2, d0,
                                                      d1, d2, vf, af)
        ax = a0 + a1 + a2
        ay = b0 + b1 + b2
        vx = c0 + c1 + c2
        vy = g0 + g1 + g2
        L00 = l0 + l1 + l2
        L01 = m0 + m1 + m2
        L10 = n0 + n1 + n2
        L11 = o0 + o1 + o2
        if fext[p, 0] != 0.0 or fext[p, 1] != 0.0:
            # work of the traction: force x velocity of the nodes that carried it
            # (weights at the start-of-step position, as in P2G)
            c = _traction_weights(x[p, 0], x[p, 1], x[p, 0] + foff[p, 0],
                                  x[p, 1] + foff[p, 1], origin, cell, nn, lp, kind, tidx, tw,
                                  wx, dwx, wy, dwy, qx, dqx, qy, dqy)
            for kk in range(c):
                work += load_scale * dt * (fext[p, 0] * nvel[tidx[kk], f, 0]
                                           + fext[p, 1] * nvel[tidx[kk], f, 1]) * tw[kk]
        x[p, 0] += dt * vx
        x[p, 1] += dt * vy
        u0 = (1.0 - pic) * (v[p, 0] + dt * ax) + pic * vx
        u1 = (1.0 - pic) * (v[p, 1] + dt * ay) + pic * vy
        if vtil is not None:
            ke_flip += 0.5 * pmass[p] * (u0 * u0 + u1 * u1)
            # S v~ (004 Eq 35), the start-of-step weights of the gathers above
            hx0, hy0 = _row3(k, st, q0, w0, w1, w2, vtil)
            hx1, hy1 = _row3(k + srow, st, q1, w0, w1, w2, vtil)
            hx2, hy2 = _row3(k + 2 * srow, st, q2, w0, w1, w2, vtil)
            tx = hx0 + hx1 + hx2
            ty = hy0 + hy1 + hy2
            u0 = (1.0 - beta) * u0 + beta * tx
            u1 = (1.0 - beta) * u1 + beta * ty
            x[p, 0] += beta * dt * (tx - vx)
            x[p, 1] += beta * dt * (ty - vy)
        v[p, 0] = u0
        v[p, 1] = u1
        ke += 0.5 * pmass[p] * (u0 * u0 + u1 * u1)
        ke_grid += 0.5 * pmass[p] * (vx * vx + vy * vy)
        if mkind[f] != 0:
            # finite-strain field: mpm.finite_strain updates F, stress and energy
            if update_stress:
                store_gradient_2d(velgrad, p, L00, L01, L10, L11)
            continue
        s0 = stress[p, 0]
        s1 = stress[p, 1]
        s2 = stress[p, 2]
        t0 = strain[p, 0]
        t1 = strain[p, 1]
        t2 = strain[p, 2]
        if update_stress:
            # small-strain increment sym(L) dt (engineering shear), sigma += C d_eps
            # (:func:`_stress_increment`, written out: an array-argument helper per
            # particle costs numba reference counting)
            de0 = L00 * dt
            de1 = L11 * dt
            de2 = (L01 + L10) * dt
            t0 += de0
            t1 += de1
            t2 += de2
            s0 += C[f, 0, 0] * de0 + C[f, 0, 1] * de1 + C[f, 0, 2] * de2
            s1 += C[f, 1, 0] * de0 + C[f, 1, 1] * de1 + C[f, 1, 2] * de2
            s2 += C[f, 2, 0] * de0 + C[f, 2, 1] * de1 + C[f, 2, 2] * de2
            strain[p, 0] = t0
            strain[p, 1] = t1
            strain[p, 2] = t2
            stress[p, 0] = s0
            stress[p, 1] = s1
            stress[p, 2] = s2
            pvol[p] *= 1.0 + de0 + de1
        U += 0.5 * pvol0[p] * (s0 * t0 + s1 * t1 + s2 * t2)
    if vtil is None:
        ke_flip = ke
    return ke, U, work, lost, ke_grid, ke_flip


@njit(cache=True, fastmath=FMA, error_model="numpy")
def stress_from_grid_2d(x, pvol, pvol0, stress, strain, field, C, origin, cell, nn, lp, kind,
                        dt, mass, mom, velgrad, mkind):
    """Stress update with L = sum (p_i/m_i) (x) grad S_ip of the particle's own field.

    USF: called with the (contact-corrected) initial extrapolation; MUSL: with the
    momenta re-extrapolated from the updated particle velocities (mass-weighted
    averages of particle velocities, so nodes holding only the tails of particles
    cannot feed huge velocities into L). Returns the strain energy of the linear
    fields; a finite-strain field's L is stored in ``velgrad`` (:func:`g2p_2d`).
    """
    wx = np.empty(3)
    dwx = np.empty(3)
    wy = np.empty(3)
    dwy = np.empty(3)
    nx = nn[0]
    U = 0.0
    for p in range(x.shape[0]):
        i0, nax, wx[0], wx[1], wx[2], dwx[0], dwx[1], dwx[2] = axis_weights_tuple(
            x[p, 0], origin[0], cell[0], lp[0], kind)
        j0, nay, wy[0], wy[1], wy[2], dwy[0], dwy[1], dwy[2] = axis_weights_tuple(
            x[p, 1], origin[1], cell[1], lp[1], kind)
        if not _inside(i0, j0, nax, nay, nn):
            nax = -1
        f = field[p]
        L00 = 0.0
        L01 = 0.0
        L10 = 0.0
        L11 = 0.0
        for b in range(nay):
            row = (j0 + b) * nx + i0
            for a in range(nax):
                n = row + a
                m = mass[n, f]
                if m <= 0.0:
                    continue
                gx = dwx[a] * wy[b]
                gy = wx[a] * dwy[b]
                vnx = mom[n, f, 0] / m
                vny = mom[n, f, 1] / m
                L00 += vnx * gx
                L01 += vnx * gy
                L10 += vny * gx
                L11 += vny * gy
        if mkind[f] != 0:
            store_gradient_2d(velgrad, p, L00, L01, L10, L11)
            continue
        _stress_increment(p, f, L00, L01, L10, L11, dt, C, stress, strain, pvol)
        U += 0.5 * pvol0[p] * (stress[p, 0] * strain[p, 0] + stress[p, 1] * strain[p, 1]
                               + stress[p, 2] * strain[p, 2])
    return U


@njit(cache=True, fastmath=FMA, error_model="numpy")
def p2g_momentum_2d(x, v, pmass, field, origin, cell, nn, lp, kind, mass, mom):
    """Re-extrapolate mass and momentum of the updated particles (MUSL, Sulsky et al.)."""
    mass[:] = 0.0
    mom[:] = 0.0
    wx = np.empty(3)
    dwx = np.empty(3)
    wy = np.empty(3)
    dwy = np.empty(3)
    nx = nn[0]
    for p in range(x.shape[0]):
        i0, nax, wx[0], wx[1], wx[2], dwx[0], dwx[1], dwx[2] = axis_weights_tuple(
            x[p, 0], origin[0], cell[0], lp[0], kind)
        j0, nay, wy[0], wy[1], wy[2], dwy[0], dwy[1], dwy[2] = axis_weights_tuple(
            x[p, 1], origin[1], cell[1], lp[1], kind)
        if not _inside(i0, j0, nax, nay, nn):
            nax = -1
        if nax < 0:
            continue
        f = field[p]
        m = pmass[p]
        for b in range(nay):
            row = (j0 + b) * nx + i0
            for a in range(nax):
                s = wx[a] * wy[b] * m
                n = row + a
                mass[n, f] += s
                mom[n, f, 0] += s * v[p, 0]
                mom[n, f, 1] += s * v[p, 1]


@njit(cache=True)
def fold_ghosts(mass, mom, force, g_node, g_field, g_comp, g_mirror, g_ref, g_plane, plane_node,
                plane_field, plane_of, bc_vel, with_force, real_mass):
    """Fold the reflected material of the B2 symmetry planes onto the nodes inside
    (:class:`mpm.boundary.GhostNodes`), plane after plane: each ghost adds its momentum
    and force to its mirror node, reflected (odd about 2 m_g v_bc for a prescribed
    component, even otherwise), and its mass once; then the plane's nodes count twice.
    The force only ``with_force`` (MUSL re-extrapolation: mass and momentum); then
    ``real_mass`` receives the masses before the fold (:func:`real_share`)."""
    if with_force:
        real_mass[:] = mass
    n_planes = 0
    for b in range(plane_of.size):
        n_planes = max(n_planes, plane_of[b] + 1)
    for b in range(g_plane.size):
        n_planes = max(n_planes, g_plane[b] + 1)
    for q in range(n_planes):
        for b in range(g_node.size):
            if g_plane[b] != q:
                continue
            n = g_node[b]
            f = g_field[b]
            d = g_comp[b]
            m = g_mirror[b]
            mg = mass[n, f]
            if mg <= 0.0:
                continue
            if g_ref[b] >= 0:
                mom[m, f, d] += 2.0 * mg * bc_vel[g_ref[b]] - mom[n, f, d]
                if with_force:
                    force[m, f, d] -= force[n, f, d]
            else:
                mom[m, f, d] += mom[n, f, d]
                if with_force:
                    force[m, f, d] += force[n, f, d]
        for b in range(g_node.size):
            first = b == 0 or g_node[b] != g_node[b - 1] or g_field[b] != g_field[b - 1] \
                or g_plane[b] != g_plane[b - 1]
            if g_plane[b] == q and first:
                mass[g_mirror[b], g_field[b]] += mass[g_node[b], g_field[b]]
        for b in range(plane_node.size):
            if plane_of[b] != q:
                continue
            n = plane_node[b]
            f = plane_field[b]
            mass[n, f] *= 2.0
            for d in range(mom.shape[2]):
                mom[n, f, d] *= 2.0
                if with_force:
                    force[n, f, d] *= 2.0


@njit(cache=True)
def reflect_ghosts(mass, mom, force, dt, g_node, g_field, g_comp, g_mirror, g_ref, bc_vel,
                   with_force, real_mass):
    """Velocities of the B2 ghost nodes (:class:`mpm.boundary.GhostNodes`) reflected from
    their mirror nodes: v_g = 2 v_bc - v_m for a prescribed component (``g_ref`` >= 0,
    the condition's step velocity ``bc_vel[g_ref]``), v_g = v_m otherwise; the
    reaction goes into ``force`` with ``with_force``. Three passes (a corner ghost may
    mirror another side's ghost). Returns the reactions' work."""
    work = 0.0
    for _ in range(3):
        for b in range(g_node.size):
            n = g_node[b]
            f = g_field[b]
            d = g_comp[b]
            m = mass[n, f]
            if m <= 0.0:
                continue
            mm = mass[g_mirror[b], f]
            vm = mom[g_mirror[b], f, d] / mm if mm > 0.0 else 0.0
            v = 2.0 * bc_vel[g_ref[b]] - vm if g_ref[b] >= 0 else vm
            pn = m * v
            if with_force:
                reaction = (pn - mom[n, f, d]) / dt
                force[n, f, d] += reaction
                work += real_share(real_mass, mass, n, f) * reaction * v * dt
            mom[n, f, d] = pn
    return work


@njit(cache=True)
def set_velocity_bc(mass, mom, bc_node, bc_field, bc_comp, bc_vel):
    """Nodal velocity conditions on re-extrapolated momenta: p = m v_bc."""
    for b in range(bc_node.size):
        n = bc_node[b]
        f = bc_field[b]
        mom[n, f, bc_comp[b]] = mass[n, f] * bc_vel[b]


# ------------------------------------------------------------------ time ----


#: how a nodal condition's velocity evolves (``mpm.boundary.NodalConditions.ramp``)
HOLD = 0             # ``vel`` until ``t_end``, then 0 (fixed, unramped velocity, linear displacement u / T)
DISP_COSINE = 1      # displacement u (1 - cos(pi t / T)) / 2 (002 Eq 49), ``vel`` = u
VEL_LINEAR = 2       # velocity v t / T up to v, ``vel`` = v
VEL_COSINE = 3       # velocity v (1 - cos(pi t / T)) / 2 up to v, ``vel`` = v
#: load ramps of tractions (``interfaces.case.RAMPS`` order)
RAMP_LINEAR = 0
RAMP_COSINE = 1


@njit(cache=True)
def ramp_fraction(s, code):
    """Load fraction of the ramp ``code`` at s = t / T (0 before, 1 after the ramp)."""
    if s <= 0.0:
        return 0.0
    if s >= 1.0:
        return 1.0
    if code == RAMP_COSINE:
        return 0.5 * (1.0 - math.cos(math.pi * s))
    return s


@njit(cache=True)
def ramp_integral(t, T, code):
    """int_0^t of the ramp fraction (s): the displacement of a unit ramped velocity."""
    if t <= 0.0:
        return 0.0
    if t >= T:
        return t - 0.5 * T
    if code == RAMP_COSINE:
        return 0.5 * t - 0.5 * T / math.pi * math.sin(math.pi * t / T)
    return 0.5 * t * t / T


@njit(cache=True)
def step_velocities(t, dt, bc_vel, bc_tend, bc_ramp, bc_tramp, vel):
    """Nodal condition velocities for the step t -> t + dt.

    ``HOLD``: ``bc_vel`` while the condition lasts (t < ``bc_tend``), scaled by the
    fraction of the step before ``bc_tend`` so a displacement u imposed as u / T over T
    moves by exactly u whatever T / dt is (ceil(T / dt) full steps overshoot by up to
    dt / T). The ramped histories (cosine displacement, linear or cosine velocity over
    ``bc_tramp``) impose the mean velocity of the step, (U(t + dt) - U(t)) / dt with U
    the prescribed displacement, so the boundary follows the history exactly at every
    step end."""
    for b in range(bc_vel.size):
        code = bc_ramp[b]
        if code == HOLD:
            frac = (bc_tend[b] - t) / dt
            if frac >= 1.0:
                vel[b] = bc_vel[b]
            elif frac > 0.0:
                vel[b] = bc_vel[b] * frac
            else:
                vel[b] = 0.0
        elif code == DISP_COSINE:
            T = bc_tramp[b]
            vel[b] = bc_vel[b] * (ramp_fraction((t + dt) / T, RAMP_COSINE)
                                  - ramp_fraction(t / T, RAMP_COSINE)) / dt
        else:
            T = bc_tramp[b]
            rc = RAMP_COSINE if code == VEL_COSINE else RAMP_LINEAR
            vel[b] = bc_vel[b] * (ramp_integral(t + dt, T, rc) - ramp_integral(t, T, rc)) / dt


@njit(cache=True)
def ramp(t, ramp_time, code):
    """Traction load fraction at time t: linear t / ramp_time or cosine
    (1 - cos(pi t / ramp_time)) / 2, up to 1."""
    if ramp_time <= 0.0 or t >= ramp_time:
        return 1.0
    if code == RAMP_COSINE:
        return 0.5 * (1.0 - math.cos(math.pi * t / ramp_time))
    return t / ramp_time
