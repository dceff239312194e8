"""XPIC(m) and multimaterial XPIC(m) particle updates (004 Sec 3.3, Eq 35-44).

FLIP (V <- V + S a dt) keeps the null-space noise of the particle velocities; PIC
(V <- S v+) removes it but dissipates. XPIC(m) of Hammerquist and Nairn projects the
particle velocities with P = I - (I - S S+)^m (004 Eq 35-36) before adding S a dt:
m = 1 is PIC, larger m dissipates less while still filtering the null space.

Multimaterial XPIC(m) applies the series to each material velocity field on its own
(S+ -> S+_alpha) and, because the initial extrapolations were corrected for contact
(v_alpha = v_alpha0 + Delta v_alpha, 004 Eq 26), adds the term of the initial
correction (Eq 37). On the grid this is (Eq 39-44)

    P V = m S (v_alpha - v*_alpha),
    v*_alpha = sum_{k=2..m} (-1)^k (v*_k + (m - 1)/m Delta v*_{k-1})          (Eq 42)
    v*_k = (m + 1 - k)/k S+_alpha S v*_{k-1},  v*_1 = v_alpha                    (Eq 43)
    Delta v*_k = (m - k)/k S+_alpha S Delta v*_{k-1},  Delta v*_1 = Delta v_alpha  (Eq 44)

with (S+_alpha S w)_i = (1/m_i) sum_p m_p S_ip sum_j S_jp w_j over the particles of
field alpha. The particle update (Eq 35, blended with FLIP by the ``pic`` fraction
beta) is

    V <- (1 - beta)(V + S a dt) + beta S v~,   v~ = m (v_alpha - v*_alpha) + a dt,
    x <- x + dt S ((1 - beta) v+ + beta v~),

the positions moving with the grid velocity the particle velocity is taken from (for
m = 1, v~ = v+: exactly the PIC update, Eq 38). Where a velocity condition holds a
component (and on the B2 ghost nodes) v~ keeps the conditioned v+. Single-material
runs have Delta v = 0. The "uncorrected" variant (option ``xpic_correction`` false)
omits the Delta v terms, i.e. single-material XPIC(m) applied to each corrected field:
with perfect interfaces its departure from single-material XPIC scales with the
velocity itself (Eq 48) instead of with V - S v (Eq 47).

The accelerations a_alpha are those of the step's second contact correction (004 Eq
33, f^{C,1}), so with perfect interfaces every field reverts to the single-material
acceleration. The kinetic energy the projection removes is counted as dissipated.

Work arrays (mpm/state.py): ``NodalState.xpic`` [7, N, M, D] with the slots below and
``ParticleState.xpic`` [2, P, D] (S v~ and S (v~ - v+) at the start-of-step positions);
zero rows when XPIC is off. The kernels are written once for 2D and 3D (tensor-product
shapes: linear, uGIMP, B2, on the 3-node stencil of :func:`mpm.shape.axis_weights3`);
the CPDI shapes (2D) use each particle's node list of :func:`mpm.cpdi.shape_cpdi`, built
once per step from the start-of-step domains (the ones P2G used).
"""
from __future__ import annotations

import numpy as np
from numba import njit

from .cpdi import is_cpdi, shape_cpdi
from .kernels import nodal_kinematics
from .shape import axis_weights3
from .xpic_contact import contact_grid_velocity

#: slots of ``NodalState.xpic``
V0, DV, VK, DK, VN, DN, VS = range(7)
N_SLOTS = 7


@njit(cache=True, inline="always")
def _stencil(xp, origin, cell, nn, lp, kind, i0, w, idx, wt) -> bool:
    """Flat node indices and weights S_ip of the 3^D stencil of position ``xp`` into
    ``idx``, ``wt`` (``i0`` [3], ``w`` [3, 3]: scratch); False when the stencil leaves
    the grid."""
    D = xp.shape[0]
    for d in range(D):
        i, a, b, c, _, _, _ = axis_weights3(xp[d], origin[d], cell[d], lp[d], kind)
        if i < 0 or i + 3 > nn[d]:
            return False
        i0[d] = i
        w[d, 0] = a
        w[d, 1] = b
        w[d, 2] = c
    nz = 3 if D == 3 else 1
    c = 0
    for kz in range(nz):
        wz = w[2, kz] if D == 3 else 1.0
        base_z = (i0[2] + kz) * nn[1] if D == 3 else 0
        for ky in range(3):
            row = (base_z + i0[1] + ky) * nn[0] + i0[0]
            wyz = w[1, ky] * wz
            for kx in range(3):
                idx[c] = row + kx
                wt[c] = w[0, kx] * wyz
                c += 1
    return True


@njit(cache=True)
def start_fields(mass, mom, work) -> None:
    """After the initial contact correction: v_alpha = p_alpha / m_alpha into slot V0
    and Delta v_alpha = (p_alpha - p_alpha0) / m_alpha into DV (``work[DV]`` holds the
    momenta p_alpha0 saved before the correction, 004 Eq 26)."""
    N, M, D = mom.shape
    for n in range(N):
        for f in range(M):
            m = mass[n, f]
            inv = 1.0 / m if m > 0.0 else 0.0
            for d in range(D):
                work[DV, n, f, d] = (mom[n, f, d] - work[DV, n, f, d]) * inv
                work[V0, n, f, d] = mom[n, f, d] * inv


@njit(cache=True, fastmath=True, error_model="numpy")
def stencils_2d(x, origin, cell, nn, lp, kind, base, wts) -> None:
    """The 3 x 3 stencils of the particles, computed once per step for every pass: the
    flat index of the first node (-1 off the grid) and the weights S_ip, row by row."""
    nx = nn[0]
    for p in range(x.shape[0]):
        i0, w0, w1, w2, _, _, _ = axis_weights3(x[p, 0], origin[0], cell[0], lp[0], kind)
        j0, q0, q1, q2, _, _, _ = axis_weights3(x[p, 1], origin[1], cell[1], lp[1], kind)
        if i0 < 0 or j0 < 0 or i0 + 3 > nx or j0 + 3 > nn[1]:
            base[p] = -1
            continue
        base[p] = j0 * nx + i0
        wts[p, 0] = w0 * q0
        wts[p, 1] = w1 * q0
        wts[p, 2] = w2 * q0
        wts[p, 3] = w0 * q1
        wts[p, 4] = w1 * q1
        wts[p, 5] = w2 * q1
        wts[p, 6] = w0 * q2
        wts[p, 7] = w1 * q2
        wts[p, 8] = w2 * q2


@njit(cache=True, fastmath=True, error_model="numpy")
def _scatter_pass_2d(base, wts, pmass, field, nx, work, src, dst) -> None:
    """The particle loop of :func:`scatter_pass` in 2D: dst += sum_p m_p S_ip (S src)_p
    per field, unnormalised."""
    for p in range(base.shape[0]):
        b = base[p]
        if b < 0:
            continue
        f = field[p]
        a0 = 0.0
        a1 = 0.0
        for jb in range(3):
            row = b + jb * nx
            for ia in range(3):
                w = wts[p, 3 * jb + ia]
                a0 += w * work[src, row + ia, f, 0]
                a1 += w * work[src, row + ia, f, 1]
        a0 *= pmass[p]
        a1 *= pmass[p]
        for jb in range(3):
            row = b + jb * nx
            for ia in range(3):
                w = wts[p, 3 * jb + ia]
                work[dst, row + ia, f, 0] += w * a0
                work[dst, row + ia, f, 1] += w * a1


@njit(cache=True)
def scatter_pass(x, pmass, field, origin, cell, nn, lp, kind, work, src, dst, base,
                 wts, lists) -> None:
    """dst <- sum_p m_p S_ip (S src)_p (slots of ``work``), each field on its own
    particles: m_i S+_alpha S src before the division by the nodal mass (004 Eq 43-44);
    2D with the step's stencils ``base``, ``wts`` (:func:`stencils_2d`), CPDI shapes with
    its node ``lists`` = (nodes, weights, counts) (:func:`stencils_cpdi`)."""
    work[dst] = 0.0
    if lists[2].shape[0]:
        _scatter_pass_list(lists[0], lists[1], lists[2], pmass, field, work, src, dst)
    elif x.shape[1] == 2:
        _scatter_pass_2d(base, wts, pmass, field, nn[0], work, src, dst)
    else:
        _scatter_pass_any(x, pmass, field, origin, cell, nn, lp, kind, work, src, dst)


@njit(cache=True)
def _scatter_pass_any(x, pmass, field, origin, cell, nn, lp, kind, work, src, dst) -> None:
    """The particle loop of :func:`scatter_pass` for any D (3^D stencil)."""
    D = x.shape[1]
    M = work.shape[2]
    ns = 27 if D == 3 else 9
    idx = np.empty(27, np.int64)
    wt = np.empty(27)
    i0 = np.zeros(3, np.int64)
    w3 = np.zeros((3, 3))
    wf = work.reshape(work.shape[0], -1)
    sv = np.empty(3)
    for p in range(x.shape[0]):
        if not _stencil(x[p], origin, cell, nn, lp, kind, i0, w3, idx, wt):
            continue
        f = field[p]
        for d in range(D):
            sv[d] = 0.0
        for c in range(ns):
            k = (idx[c] * M + f) * D
            for d in range(D):
                sv[d] += wt[c] * wf[src, k + d]
        mp = pmass[p]
        for c in range(ns):
            k = (idx[c] * M + f) * D
            for d in range(D):
                wf[dst, k + d] += mp * wt[c] * sv[d]


#: CPDI shapes: entries per particle (4 corners x 3 x 3 nodes of B2-CPDI; 2 x 2 for CPDI)
CPDI_ENTRIES = 36


@njit(cache=True, fastmath=True, error_model="numpy")
def stencils_cpdi(x, F, hw, origin, cell, nn, kind, cidx, cwt, cnt) -> None:
    """The CPDI / B2-CPDI node lists of the particles (mpm/cpdi.py, one entry per corner
    and node, a node reached by several corners listed once per corner), computed once
    per step for every pass: ``cnt[p]`` entries (-1 off the grid), nodes ``cidx`` and
    weights S_ip ``cwt``."""
    G = np.empty((CPDI_ENTRIES, 2))
    for p in range(x.shape[0]):
        cnt[p] = shape_cpdi(p, x, F, hw, origin, cell, nn, kind, cidx[p], cwt[p], G)


@njit(cache=True, fastmath=True, error_model="numpy")
def _scatter_pass_list(cidx, cwt, cnt, pmass, field, work, src, dst) -> None:
    """The particle loop of :func:`scatter_pass` on node lists (CPDI shapes, 2D)."""
    for p in range(cnt.shape[0]):
        f = field[p]
        a0 = 0.0
        a1 = 0.0
        for c in range(cnt[p]):
            w = cwt[p, c]
            a0 += w * work[src, cidx[p, c], f, 0]
            a1 += w * work[src, cidx[p, c], f, 1]
        a0 *= pmass[p]
        a1 *= pmass[p]
        for c in range(cnt[p]):
            w = cwt[p, c]
            work[dst, cidx[p, c], f, 0] += w * a0
            work[dst, cidx[p, c], f, 1] += w * a1


@njit(cache=True, fastmath=True, error_model="numpy")
def _gather_list(cidx, cwt, cnt, field, work, nvel, out) -> None:
    """:func:`gather_particles` on node lists (CPDI shapes, 2D)."""
    for p in range(cnt.shape[0]):
        f = field[p]
        a0 = 0.0
        a1 = 0.0
        b0 = 0.0
        b1 = 0.0
        for c in range(cnt[p]):
            w = cwt[p, c]
            n = cidx[p, c]
            v0 = work[VS, n, f, 0]
            v1 = work[VS, n, f, 1]
            a0 += w * v0
            a1 += w * v1
            b0 += w * (v0 - nvel[n, f, 0])
            b1 += w * (v1 - nvel[n, f, 1])
        out[0, p, 0] = a0
        out[0, p, 1] = a1
        out[1, p, 0] = b0
        out[1, p, 1] = b1


@njit(cache=True)
def xpic_grid_velocity(m, corrected, x, pmass, field, origin, cell, nn, lp, kind, mass,
                       nacc, dt, work, base, wts, lists) -> None:
    """v~ = m (v_alpha - v*_alpha) + a_alpha dt into slot VS (004 Eq 41-44); ``work[V0]``
    and ``work[DV]`` hold v_alpha and Delta v_alpha (:func:`start_fields`). Without
    ``corrected`` the Delta v terms are left out (the uncorrected variant)."""
    work[VK] = work[V0]
    if corrected:
        work[DK] = work[DV]
    work[VS] = 0.0
    N, M, D = nacc.shape
    for k in range(2, m + 1):
        scatter_pass(x, pmass, field, origin, cell, nn, lp, kind, work, VK, VN, base, wts, lists)
        next_dk = corrected and k < m
        if next_dk:
            scatter_pass(x, pmass, field, origin, cell, nn, lp, kind, work, DK, DN, base, wts, lists)
        sign = 1.0 if k % 2 == 0 else -1.0
        cv = (m + 1.0 - k) / k            # Eq 43
        cd = (m - k) / k                  # Eq 44
        cdv = sign * (m - 1.0) / m        # Eq 42, on Delta v*_{k-1}
        for n in range(N):
            for f in range(M):
                mi = mass[n, f]
                inv = 1.0 / mi if mi > 0.0 else 0.0
                for d in range(D):
                    vk = cv * inv * work[VN, n, f, d]
                    work[VK, n, f, d] = vk
                    acc = sign * vk
                    if corrected:
                        acc += cdv * work[DK, n, f, d]
                    if next_dk:
                        work[DK, n, f, d] = cd * inv * work[DN, n, f, d]
                    work[VS, n, f, d] += acc
    for n in range(N):
        for f in range(M):
            for d in range(D):
                work[VS, n, f, d] = m * (work[V0, n, f, d] - work[VS, n, f, d]) \
                    + nacc[n, f, d] * dt


@njit(cache=True)
def keep_conditioned(work, nvel, bc_node, bc_field, bc_comp, g_node, g_field) -> None:
    """v~ = v+ on the components held by velocity conditions and on B2 ghost nodes."""
    for c in range(bc_node.shape[0]):
        work[VS, bc_node[c], bc_field[c], bc_comp[c]] = nvel[bc_node[c], bc_field[c], bc_comp[c]]
    for c in range(g_node.shape[0]):
        for d in range(nvel.shape[2]):
            work[VS, g_node[c], g_field[c], d] = nvel[g_node[c], g_field[c], d]


@njit(cache=True, fastmath=True, error_model="numpy")
def gather_particles(x, field, origin, cell, nn, lp, kind, work, nvel, out, base, wts,
                     lists) -> None:
    """out[0, p] = S v~, out[1, p] = S (v~ - v+) at the start-of-step positions (2D: the
    step's stencils ``base``, ``wts``; CPDI shapes: the node ``lists``)."""
    if lists[2].shape[0]:
        _gather_list(lists[0], lists[1], lists[2], field, work, nvel, out)
        return
    if x.shape[1] != 2:
        _gather_particles_any(x, field, origin, cell, nn, lp, kind, work, nvel, out)
        return
    nx = nn[0]
    for p in range(x.shape[0]):
        b = base[p]
        a0 = 0.0
        a1 = 0.0
        b0 = 0.0
        b1 = 0.0
        if b >= 0:
            f = field[p]
            for jb in range(3):
                row = b + jb * nx
                for ia in range(3):
                    w = wts[p, 3 * jb + ia]
                    n = row + ia
                    v0 = work[VS, n, f, 0]
                    v1 = work[VS, n, f, 1]
                    a0 += w * v0
                    a1 += w * v1
                    b0 += w * (v0 - nvel[n, f, 0])
                    b1 += w * (v1 - nvel[n, f, 1])
        out[0, p, 0] = a0
        out[0, p, 1] = a1
        out[1, p, 0] = b0
        out[1, p, 1] = b1


@njit(cache=True)
def _gather_particles_any(x, field, origin, cell, nn, lp, kind, work, nvel, out) -> None:
    """:func:`gather_particles` for any D (3^D stencil)."""
    D = x.shape[1]
    M = nvel.shape[1]
    ns = 27 if D == 3 else 9
    idx = np.empty(27, np.int64)
    wt = np.empty(27)
    i0 = np.zeros(3, np.int64)
    w3 = np.zeros((3, 3))
    for p in range(x.shape[0]):
        for d in range(D):
            out[0, p, d] = 0.0
            out[1, p, d] = 0.0
        if not _stencil(x[p], origin, cell, nn, lp, kind, i0, w3, idx, wt):
            continue
        f = field[p]
        for c in range(ns):
            n = idx[c]
            for d in range(D):
                vt = work[VS, n, f, d]
                out[0, p, d] += wt[c] * vt
                out[1, p, d] += wt[c] * (vt - nvel[n, f, d])


@njit(cache=True)
def blend_particles(beta, dt, pmass, v, x, out):
    """V <- (1 - beta) V_FLIP + beta S v~, x += beta dt S (v~ - v+) (the FLIP update and
    x += dt S v+ already done by G2P); returns (kinetic energy after, before)."""
    ke = 0.0
    ke_flip = 0.0
    D = v.shape[1]
    for p in range(v.shape[0]):
        s0 = 0.0
        s1 = 0.0
        for d in range(D):
            vf = v[p, d]
            s0 += vf * vf
            vn = (1.0 - beta) * vf + beta * out[0, p, d]
            v[p, d] = vn
            s1 += vn * vn
            x[p, d] += beta * dt * out[1, p, d]
        ke_flip += 0.5 * pmass[p] * s0
        ke += 0.5 * pmass[p] * s1
    return ke, ke_flip


@njit(cache=True, inline="always")
def phase_xpic_save(ctl, nd) -> None:
    """Before the initial contact correction: the momenta p_alpha0 (for Delta v_alpha)."""
    if ctl.xpic > 1:
        nd.xpic[DV] = nd.momentum


@njit(cache=True, inline="always")
def phase_xpic_start(ctl, nd) -> None:
    """After the initial contact correction: v_alpha and Delta v_alpha (004 Eq 26)."""
    if ctl.xpic > 1:
        start_fields(nd.mass, nd.momentum, nd.xpic)


@njit(cache=True, inline="always")
def phase_xpic_grid(ctl, pt, grid, nd, bc, pairs, nodes) -> None:
    """Before G2P: the XPIC(m) grid velocity v~ (004 Eq 41-44; m = 1: v+), held to the
    contact conditions of ``pairs`` on the multimaterial ``nodes`` (mpm/xpic_contact.py),
    and its extrapolations to the particles."""
    if ctl.xpic < 1:
        return
    nodal_kinematics(nd.mass, nd.momentum, nd.force, nd.velocity, nd.acceleration)
    P = pt.x.shape[0]
    cpdi = is_cpdi(grid.kind)
    n2 = P if pt.x.shape[1] == 2 and not cpdi else 0
    nl = P if cpdi else 0
    base = np.empty(n2, np.int64)
    wts = np.empty((n2, 9))
    lists = (np.empty((nl, CPDI_ENTRIES), np.int64), np.empty((nl, CPDI_ENTRIES)),
             np.empty(nl, np.int64))
    if n2:
        stencils_2d(pt.x, grid.origin, grid.cell, grid.nn, pt.lp, grid.kind, base, wts)
    if nl:
        stencils_cpdi(pt.x, pt.F, pt.half_width, grid.origin, grid.cell, grid.nn, grid.kind,
                      lists[0], lists[1], lists[2])
    if ctl.xpic == 1:
        nd.xpic[VS] = nd.velocity
    else:
        mass = nd.real_mass if nd.real_mass.shape[0] else nd.mass
        # Delta v is zero without a second field: its series is skipped
        corrected = ctl.xpic_correction and nd.mass.shape[1] > 1
        xpic_grid_velocity(ctl.xpic, corrected, pt.x, pt.mass, pt.field, grid.origin,
                           grid.cell, grid.nn, pt.lp, grid.kind, mass, nd.acceleration, ctl.dt,
                           nd.xpic, base, wts, lists)
        if nodes.size:
            contact_grid_velocity(nd.xpic[VS], nd.mass, nd.volume, nd.volume_gradient,
                                  nd.displacement, nd.position, grid.cell, grid.origin, grid.nn,
                                  pairs, ctl.dt, nodes)
        keep_conditioned(nd.xpic, nd.velocity, bc.node, bc.field, bc.comp, bc.ghost_node,
                         bc.ghost_field)
    gather_particles(pt.x, pt.field, grid.origin, grid.cell, grid.nn, pt.lp, grid.kind,
                     nd.xpic, nd.velocity, pt.xpic, base, wts, lists)


@njit(cache=True, inline="always")
def phase_xpic_particles(ctl, pt, ke):
    """After the FLIP G2P: the XPIC(m) velocities and positions (Eq 35); returns (kinetic
    energy, the kinetic energy the projection removed)."""
    if ctl.xpic < 1:
        return ke, 0.0
    ke_new, ke_flip = blend_particles(ctl.xpic_blend, ctl.dt, pt.mass, pt.v, pt.x, pt.xpic)
    return ke_new, ke_flip - ke_new
