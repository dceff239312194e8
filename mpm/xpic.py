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

Work arrays (mpm/state.py): ``NodalState.xpic`` [7, N, M, D] with the slots below;
per particle ``ParticleState.xpic_node`` / ``xpic_weight`` (the stencils at the
start-of-step positions: written by P2G in 2D, by :func:`stencils_cpdi` for the CPDI
shapes) and ``ParticleState.xpic`` (the extrapolations, CPDI shapes and 3D only):
:func:`stencil_arrays`. The passes are written for the 2D tensor-product shapes (linear,
uGIMP, B2: a 3 x 3 window of P2G's 1D weights; the V and Delta v series of a pass in one
particle loop, the Delta v one only near the multimaterial nodes; v~ extrapolated and
blended inside G2P, :func:`mpm.kernels.g2p_range_2d`), for the CPDI shapes (2D, each
particle's node list of :func:`mpm.cpdi.shape_cpdi`) and for any D (3D: the 3^D stencil
recomputed in each pass).
"""
from __future__ import annotations

import numpy as np

from interfaces.jit import FMA, njit

from .cpdi import is_cpdi, shape_cpdi
from .kernels import _pick, nodal_kinematics
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


@njit(cache=True, refcount=False)
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


#: CPDI shapes: entries per particle (4 corners x 3 x 3 nodes of B2-CPDI; 2 x 2 for CPDI)
CPDI_ENTRIES = 36


def stencil_arrays(P: int, D: int, cpdi: bool, xpic: int) -> tuple:
    """The per-particle work arrays of an XPIC(m) run (``ParticleState.xpic``,
    ``xpic_node``, ``xpic_weight``; zero rows without XPIC):

    * 2D tensor-product shapes: ``xpic_node[p, 0]`` the flat index ((node * M + field) *
      2) of the x component of the first node of a 3 x 3 window holding the particle's
      support, ``xpic_weight[p]`` its 1D weights (x0, x1, x2, y0, y1, y2; 0 beyond the
      support), written by P2G from the weights it computes at the start-of-step
      positions (:func:`mpm.kernels.p2g_range_2d`); G2P extrapolates v~ and blends it
      (no ``xpic`` rows);
    * CPDI shapes: ``xpic_node[p]`` = (count, node of each entry), ``xpic_weight[p]`` the
      entries' S_ip (:func:`stencils_cpdi`), and ``xpic`` [2, P, 2] the extrapolations
      S v~, S (v~ - v+) of :func:`gather_particles`;
    * 3D: ``xpic`` [2, P, 3] only (the any-D passes recompute the stencils)."""
    if not xpic:
        return np.zeros((0, P, D)), np.zeros((0, 1), np.int64), np.zeros((0, 6))
    if cpdi:
        return (np.zeros((2, P, D)), np.zeros((P, 1 + CPDI_ENTRIES), np.int64),
                np.zeros((P, CPDI_ENTRIES)))
    if D == 2:
        return np.zeros((0, P, D)), np.zeros((P, 1), np.int64), np.zeros((P, 6))
    return np.zeros((2, P, D)), np.zeros((0, 1), np.int64), np.zeros((0, 6))


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def _window_gather(wf, slot, k, st, srow, w0, w1, w2, q0, q1, q2):
    """(S w)_p of a 3 x 3 window: node weights w0..w2 (x) times q0..q2 (y), ``k`` the flat
    index of the window's first node, ``st`` / ``srow`` the flat strides along x / y."""
    a0 = 0.0
    a1 = 0.0
    for jb in range(3):
        r = k + jb * srow
        q = _pick(jb, q0, q1, q2)
        a0 += q * (w0 * wf[slot, r] + w1 * wf[slot, r + st] + w2 * wf[slot, r + 2 * st])
        a1 += q * (w0 * wf[slot, r + 1] + w1 * wf[slot, r + st + 1]
                   + w2 * wf[slot, r + 2 * st + 1])
    return a0, a1


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def _window_scatter(wf, slot, k, st, srow, w0, w1, w2, q0, q1, q2, a0, a1) -> None:
    """wf[slot, i] += S_ip (a0, a1) over the 3 x 3 window of :func:`_window_gather` (the
    particle mass already in the weights)."""
    for jb in range(3):
        r = k + jb * srow
        q = _pick(jb, q0, q1, q2)
        for ia in range(3):
            s = _pick(ia, w0, w1, w2) * q
            c = r + ia * st
            wf[slot, c] += s * a0
            wf[slot, c + 1] += s * a1


@njit(cache=True, fastmath=FMA, error_model="numpy", refcount=False)
def _scatter_2d(node, wgt, pmass, nx, M, wf, src, dst, pair, band) -> None:
    """The particle loop of :func:`scatter_passes` in 2D on the step's stencils (``wf``:
    the work slots, each flat): dst += sum_p m_p S_ip (S src)_p per field, unnormalised,
    and with ``pair`` = (src2, dst2) the same from src2 into dst2 in the same loop (the
    stencil read once; ``pair`` None compiles the loop without it) for the particles
    whose 3 x 3 window is centred on a node of ``band`` (src2 is zero elsewhere; ``band``
    per node and field, flat: node * M + field)."""
    st = 2 * M              # flat stride between x-neighbours
    srow = 2 * M * nx       # ... and between y-neighbours
    centre = (nx + 1) * M   # band index of the window's centre from its first node's
    for p in range(node.shape[0]):
        k = node[p, 0]
        if k < 0:
            continue
        w0 = wgt[p, 0]
        w1 = wgt[p, 1]
        w2 = wgt[p, 2]
        q0 = wgt[p, 3]
        q1 = wgt[p, 4]
        q2 = wgt[p, 5]
        a0, a1 = _window_gather(wf, src, k, st, srow, w0, w1, w2, q0, q1, q2)
        mp = pmass[p]
        _window_scatter(wf, dst, k, st, srow, w0, w1, w2, mp * q0, mp * q1, mp * q2, a0, a1)
        if pair is not None and band[(k >> 1) + centre]:
            b0, b1 = _window_gather(wf, pair[0], k, st, srow, w0, w1, w2, q0, q1, q2)
            _window_scatter(wf, pair[1], k, st, srow, w0, w1, w2, mp * q0, mp * q1, mp * q2,
                            b0, b1)


@njit(cache=True)
def scatter_passes(x, pmass, field, origin, cell, nn, lp, kind, work, src, dst, src2, dst2,
                   node, wgt, band) -> None:
    """dst <- sum_p m_p S_ip (S src)_p (slots of ``work``), each field on its own
    particles: m_i S+_alpha S src before the division by the nodal mass (004 Eq 43-44);
    with ``src2`` >= 0 also dst2 <- the same of src2 (the V and Delta v series of Eq
    43-44 in one loop over the particles; in 2D over the particles centred on a node of
    ``band``, :func:`delta_v_band`). 2D with the step's stencils ``node``, ``wgt``
    (written by P2G, :func:`stencil_arrays`), CPDI shapes with their node lists
    (:func:`stencils_cpdi`), 3D with the any-D loop."""
    work[dst] = 0.0
    if src2 >= 0:
        work[dst2] = 0.0
    if is_cpdi(kind):
        if src2 >= 0:
            _scatter_list(node, wgt, pmass, field, work, src, dst, (src2, dst2))
        else:
            _scatter_list(node, wgt, pmass, field, work, src, dst, None)
    elif x.shape[1] == 2:
        wf = work.reshape(work.shape[0], -1)
        if src2 >= 0:
            _scatter_2d(node, wgt, pmass, nn[0], work.shape[2], wf, src, dst, (src2, dst2),
                        band)
        else:
            _scatter_2d(node, wgt, pmass, nn[0], work.shape[2], wf, src, dst, None, band)
    else:
        _scatter_pass_any(x, pmass, field, origin, cell, nn, lp, kind, work, src, dst)
        if src2 >= 0:
            _scatter_pass_any(x, pmass, field, origin, cell, nn, lp, kind, work, src2, dst2)


@njit(cache=True)
def _scatter_pass_any(x, pmass, field, origin, cell, nn, lp, kind, work, src, dst) -> None:
    """The particle loop of :func:`scatter_passes` for any D (3^D stencil)."""
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


@njit(cache=True, fastmath=FMA, error_model="numpy")
def stencils_cpdi(x, F, hw, origin, cell, nn, kind, node, wgt) -> None:
    """The CPDI / B2-CPDI node lists of the particles (mpm/cpdi.py, one entry per corner
    and node, a node reached by several corners listed once per corner), computed once
    per step for every pass: ``node[p, 0]`` entries (-1 off the grid), their nodes in
    ``node[p, 1:]`` and weights S_ip in ``wgt[p]``."""
    G = np.empty((CPDI_ENTRIES, 2))
    for p in range(x.shape[0]):
        node[p, 0] = shape_cpdi(p, x, F, hw, origin, cell, nn, kind, node[p, 1:], wgt[p], G)


@njit(cache=True, fastmath=FMA, error_model="numpy", refcount=False)
def _scatter_list(node, wgt, pmass, field, work, src, dst, pair) -> None:
    """The particle loop of :func:`scatter_passes` on node lists (CPDI shapes, 2D; ``pair``
    as in :func:`_scatter_2d`)."""
    for p in range(node.shape[0]):
        f = field[p]
        a0 = 0.0
        a1 = 0.0
        b0 = 0.0
        b1 = 0.0
        for c in range(node[p, 0]):
            w = wgt[p, c]
            n = node[p, c + 1]
            a0 += w * work[src, n, f, 0]
            a1 += w * work[src, n, f, 1]
            if pair is not None:
                b0 += w * work[pair[0], n, f, 0]
                b1 += w * work[pair[0], n, f, 1]
        mp = pmass[p]
        for c in range(node[p, 0]):
            w = wgt[p, c] * mp
            n = node[p, c + 1]
            work[dst, n, f, 0] += w * a0
            work[dst, n, f, 1] += w * a1
            if pair is not None:
                work[pair[1], n, f, 0] += w * b0
                work[pair[1], n, f, 1] += w * b1


@njit(cache=True, fastmath=FMA, error_model="numpy", refcount=False)
def _gather_list(node, wgt, field, work, nvel, out) -> None:
    """:func:`gather_particles` on node lists (CPDI shapes, 2D)."""
    for p in range(node.shape[0]):
        f = field[p]
        a0 = 0.0
        a1 = 0.0
        b0 = 0.0
        b1 = 0.0
        for c in range(node[p, 0]):
            w = wgt[p, c]
            n = node[p, c + 1]
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
def delta_v_band(m, nn, M, nodes):
    """The nodes within 2 m - 5 nodes (each axis) of a multimaterial node of ``nodes``
    (2D grid), per node and field (flat: node * M + field, every field): Delta v (004 Eq 26) lives on those nodes only and each S+_alpha S of Eq
    44 spreads it by at most 2 nodes (a particle's 3 x 3 window), so the Delta v series
    up to Delta v*_{m-2}, the last one scattered, reaches no particle whose window is
    centred outside this band."""
    nx, ny = nn[0], nn[1]
    band = np.zeros(nx * ny * M, np.bool_)
    R = max(2 * m - 5, 1)
    for c in range(nodes.shape[0]):
        i = nodes[c] % nx
        j = nodes[c] // nx
        for jj in range(max(j - R, 0), min(j + R + 1, ny)):
            for ii in range(max(i - R, 0), min(i + R + 1, nx)):
                for f in range(M):
                    band[(jj * nx + ii) * M + f] = True
    return band


@njit(cache=True)
def xpic_grid_velocity(m, corrected, x, pmass, field, origin, cell, nn, lp, kind, mass,
                       nacc, dt, work, node, wgt, nodes) -> None:
    """v~ = m (v_alpha - v*_alpha) + a_alpha dt into slot VS (004 Eq 41-44); ``work[V0]``
    and ``work[DV]`` hold v_alpha and Delta v_alpha (:func:`start_fields`), the latter
    non-zero on the multimaterial ``nodes`` only. Without ``corrected`` the Delta v
    terms are left out (the uncorrected variant)."""
    work[VK] = work[V0]
    if corrected:
        work[DK] = work[DV]
    band = delta_v_band(m, nn, work.shape[2], nodes) if corrected and x.shape[1] == 2 \
        else np.zeros(0, np.bool_)
    work[VS] = 0.0
    N, M, D = nacc.shape
    inv = np.empty(N * M)
    mf = mass.reshape(-1)
    for e in range(N * M):
        inv[e] = 1.0 / mf[e] if mf[e] > 0.0 else 0.0
    wf = work.reshape(work.shape[0], -1)
    for k in range(2, m + 1):
        next_dk = corrected and k < m
        scatter_passes(x, pmass, field, origin, cell, nn, lp, kind, work, VK, VN,
                       DK if next_dk else -1, DN, node, wgt, band)
        sign = 1.0 if k % 2 == 0 else -1.0
        cv = (m + 1.0 - k) / k            # Eq 43
        if corrected:
            _series_terms_dv(wf, inv, D, cv, sign, sign * (m - 1.0) / m,   # Eq 42
                             (m - k) / k if next_dk else 0.0)              # Eq 44
        else:
            _series_terms(wf, inv, D, cv, sign)
    _finish(wf, nacc.reshape(-1), m, dt)


@njit(cache=True, fastmath=FMA, error_model="numpy", refcount=False)
def _series_terms(wf, inv, D, cv, sign) -> None:
    """After the pass k: v*_k = cv S+ S v*_{k-1} (VN over the nodal mass, Eq 43) into VK,
    added with its sign to the sum v*_alpha in VS (Eq 42)."""
    for e in range(wf.shape[1]):
        vk = cv * inv[e // D] * wf[VN, e]
        wf[VK, e] = vk
        wf[VS, e] += sign * vk


@njit(cache=True, fastmath=FMA, error_model="numpy", refcount=False)
def _series_terms_dv(wf, inv, D, cv, sign, cdv, cd) -> None:
    """:func:`_series_terms` with the Delta v terms: the sum also takes cdv Delta v*_{k-1}
    (Eq 42) and, with ``cd`` != 0, Delta v*_k = cd S+ S Delta v*_{k-1} (DN, Eq 44) goes
    into DK."""
    for e in range(wf.shape[1]):
        vk = cv * inv[e // D] * wf[VN, e]
        wf[VK, e] = vk
        wf[VS, e] += sign * vk + cdv * wf[DK, e]
        if cd != 0.0:
            wf[DK, e] = cd * inv[e // D] * wf[DN, e]


@njit(cache=True, fastmath=FMA, error_model="numpy", refcount=False)
def _finish(wf, acc, m, dt) -> None:
    """v~ = m (v_alpha - v*_alpha) + a_alpha dt into VS (Eq 41)."""
    for e in range(wf.shape[1]):
        wf[VS, e] = m * (wf[V0, e] - wf[VS, e]) + acc[e] * dt


@njit(cache=True, refcount=False)
def keep_conditioned(work, nvel, bc_node, bc_field, bc_comp, g_node, g_field) -> None:
    """v~ = v+ on the components held by velocity conditions and on B2 ghost nodes."""
    for c in range(bc_node.shape[0]):
        work[VS, bc_node[c], bc_field[c], bc_comp[c]] = nvel[bc_node[c], bc_field[c], bc_comp[c]]
    for c in range(g_node.shape[0]):
        for d in range(nvel.shape[2]):
            work[VS, g_node[c], g_field[c], d] = nvel[g_node[c], g_field[c], d]


@njit(cache=True)
def gather_particles(x, field, origin, cell, nn, lp, kind, work, nvel, out, node, wgt) -> None:
    """out[0, p] = S v~, out[1, p] = S (v~ - v+) at the start-of-step positions (CPDI
    shapes: the node lists; 3D: the 3^D stencils of ``x``); the 2D tensor-product shapes
    extrapolate inside G2P instead (:func:`mpm.kernels.g2p_range_2d`)."""
    if is_cpdi(kind):
        _gather_list(node, wgt, field, work, nvel, out)
    else:
        _gather_particles_any(x, field, origin, cell, nn, lp, kind, work, nvel, out)


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


@njit(cache=True, refcount=False)
def blend_particles(beta, dt, pmass, v, x, out):
    """V <- (1 - beta) V_FLIP + beta S v~, x += beta dt S (v~ - v+) (the FLIP update and
    x += dt S v+ already done by G2P) from the extrapolations ``out`` of
    :func:`gather_particles`; returns (kinetic energy after, before)."""
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
    """Before G2P: the CPDI shapes' node lists at the start-of-step domains (2D
    tensor-product shapes: the stencils P2G wrote), the XPIC(m) grid velocity v~ (004 Eq
    41-44; m = 1: v+), held to the contact conditions of ``pairs`` on the multimaterial
    ``nodes`` (mpm/xpic_contact.py) and, CPDI shapes and 3D, its extrapolations to the
    particles."""
    if ctl.xpic < 1:
        return
    nodal_kinematics(nd.mass, nd.momentum, nd.force, nd.velocity, nd.acceleration)
    cpdi = is_cpdi(grid.kind)
    if cpdi:
        stencils_cpdi(pt.x, pt.F, pt.half_width, grid.origin, grid.cell, grid.nn, grid.kind,
                      pt.xpic_node, pt.xpic_weight)
    if ctl.xpic == 1:
        nd.xpic[VS] = nd.velocity
    else:
        mass = nd.real_mass if nd.real_mass.shape[0] else nd.mass
        # Delta v is zero without a second field: its series is skipped
        corrected = ctl.xpic_correction and nd.mass.shape[1] > 1
        xpic_grid_velocity(ctl.xpic, corrected, pt.x, pt.mass, pt.field, grid.origin,
                           grid.cell, grid.nn, pt.lp, grid.kind, mass, nd.acceleration, ctl.dt,
                           nd.xpic, pt.xpic_node, pt.xpic_weight, nodes)
        if nodes.size:
            contact_grid_velocity(nd.xpic[VS], nd.mass, nd.volume, nd.volume_gradient,
                                  nd.displacement, nd.position, grid.cell, grid.origin, grid.nn,
                                  pairs, ctl.dt, nodes)
        keep_conditioned(nd.xpic, nd.velocity, bc.node, bc.field, bc.comp, bc.ghost_node,
                         bc.ghost_field)
    if cpdi or pt.x.shape[1] != 2:
        gather_particles(pt.x, pt.field, grid.origin, grid.cell, grid.nn, pt.lp, grid.kind,
                         nd.xpic, nd.velocity, pt.xpic, pt.xpic_node, pt.xpic_weight)


@njit(cache=True, inline="always")
def phase_xpic_particles(ctl, pt, ke, ke_flip):
    """After G2P: the XPIC(m) velocities and positions (Eq 35) of the CPDI shapes and 3D
    runs from their extrapolations (2D tensor-product shapes: G2P blended them,
    :func:`mpm.kernels.g2p_range_2d`, ``ke_flip`` its kinetic energy before the blend);
    returns (kinetic energy, the kinetic energy the projection removed)."""
    if ctl.xpic < 1:
        return ke, 0.0
    if pt.xpic.shape[0]:
        ke, ke_flip = blend_particles(ctl.xpic_blend, ctl.dt, pt.mass, pt.v, pt.x, pt.xpic)
    return ke, ke_flip - ke
