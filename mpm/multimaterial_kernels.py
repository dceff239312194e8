"""numba kernels for multimaterial nodes: contact corrections and interface forces.

Public entry points live in :mod:`mpm.multimaterial` (thin wrappers that unpack the
tables); the kernels here loop over nodes in compiled code.  Equation numbers:
000 = Nairn CMES 2013, 002 = Nairn imperfect interfaces (Sec 2.4), 004 = Nairn et al.
(logistic regression, two corrections per step).
"""
from __future__ import annotations

import math

import numpy as np

from interfaces.jit import njit

from mpm.multimaterial_constants import (
    HPERP_NONE, LAW_FRICTION, LAW_IMPERFECT, LAW_NONE, LAW_PERFECT, LAW_STICK, NORMAL_AG, NORMAL_LR,
    NORMAL_AVG, NORMAL_MVG, NORMAL_RMVG, NORMAL_SN, NORMAL_SN_RADIAL, OUT_AREA, OUT_ENERGY,
    OUT_JUMP_N, OUT_JUMP_T, OUT_NX, OUT_STATUS, OUT_TRACTION_N, OUT_TRACTION_T,
    P_DN_COMPRESSION, P_DN_TENSION, P_DT, P_MU, S_AREA_CORRECTION, S_CONTACT_OFFSET,
    S_EDGE_CUTOFF, S_FORCE_LIMIT, S_HPERP, S_LUMP_CONSERVE, S_MASS_TOL, S_NORMAL,
    S_DF_DS, S_DF_S0, S_SEPARATION, S_SN_X, S_THREE_MATERIAL, SEP_DF, SEP_LR, SEP_OFFSET,
    SEP_VELOCITY, STATUS_CONTACT, THREE_EXPLICIT,
    STATUS_OVER_LIMIT,
    STATUS_INTERFACE, STATUS_LIMITED_N, STATUS_LIMITED_T, STATUS_SCREENED,
)
from mpm.multimaterial_lr import pair_index
from mpm.multimaterial_normals import (
    any_tangent, h_perp, normal_ag, normal_avg, normal_mvg, normal_rmvg, normal_sn,
)
from mpm.multimaterial_three import two_pair_impulses


# ---------------------------------------------------------------------------
# small helpers
# ---------------------------------------------------------------------------

#: a field lighter than this fraction of its partner at a two-material node has its
#: contact change computed on its own side (round-off of the partner's momentum,
#: ~1e-16 |p|, would otherwise dominate its velocity)
LIGHT_FIELD_RATIO = 1e-6

#: the rigid normal is turned only where it makes an angle clearly above 90 deg with the
#: deformable field's outward gradient (cosine below -this); at a lattice corner node the
#: two are perpendicular and their dot product is round-off of either sign
PERPENDICULAR_COSINE = 1e-9

#: rows of the per-node scratch vectors ``work`` the node kernels share (work[0] .. work[12])
WORK_ROWS = 13


@njit(cache=True, inline="always")
def _dot(u, v) -> float:
    s = 0.0
    for k in range(u.shape[0]):
        s += u[k] * v[k]
    return s


@njit(cache=True, inline="always")
def _pair_law(i, a, b, kind, params, node_zone, zone_pairs, zone_kind, zone_params, law):
    """Law code of the pair (a, b) at node i; fills ``law`` with its 4 parameters.
    A node inside a zone of that pair uses the zone's law (002 Fig 6)."""
    if node_zone.shape[0] > 0:
        z = node_zone[i]
        if z >= 0:
            za = zone_pairs[z, 0]
            zb = zone_pairs[z, 1]
            if (za == a and zb == b) or (za == b and zb == a):
                for k in range(4):
                    law[k] = zone_params[z, k]
                return zone_kind[z]
    for k in range(4):
        law[k] = params[a, b, k]
    return kind[a, b]


@njit(cache=True, inline="always")
def _present_fields(mass, i, tol, present) -> int:
    """Indices of fields with m_k > tol * m_total at node i; returns their count."""
    m = mass.shape[1]
    mtot = 0.0
    for k in range(m):
        mtot += mass[i, k]
    npres = 0
    if not (mtot > 0.0):
        return 0
    for k in range(m):
        if mass[i, k] > tol * mtot and mass[i, k] > 0.0:
            present[npres] = k
            npres += 1
    return npres


@njit(cache=True, inline="always")
def _gather_b(i, a, b_only, present, npres, mass, mom, force, vol, grad, xfield, p_b, f_b, g_b, x_b):
    """Quantities of the partner field b, or of the virtual material lumping every
    present field except a (000 Sec 2.2, 004 Eq 50) when ``b_only`` < 0.
    Returns (m_b, Omega_b); fills p_b, f_b, g_b and x_b (mass-weighted, 000 Eq 11)."""
    d = p_b.shape[0]
    for k in range(d):
        p_b[k] = 0.0
        f_b[k] = 0.0
        g_b[k] = 0.0
        x_b[k] = 0.0
    m_b = 0.0
    om_b = 0.0
    for j in range(npres):
        c = present[j]
        if c == a or (b_only >= 0 and c != b_only):
            continue
        mc = mass[i, c]
        m_b += mc
        om_b += vol[i, c]
        for k in range(d):
            p_b[k] += mom[i, c, k]
            f_b[k] += force[i, c, k]
            g_b[k] += grad[i, c, k]
            x_b[k] += mc * xfield[i, c, k]
    if m_b > 0.0:
        for k in range(d):
            x_b[k] /= m_b
    return m_b, om_b


@njit(cache=True, inline="always")
def _largest_partner(i, a, present, npres, vol, rigid) -> int:
    """The other non-rigid field with the most volume (000 Sec 2.6 step 2)."""
    best = -1
    bestv = -1.0
    for j in range(npres):
        c = present[j]
        if c == a or rigid[c] != 0:
            continue
        if vol[i, c] > bestv:
            bestv = vol[i, c]
            best = c
    return best


@njit(cache=True, refcount=False)
def _node_normal(i, a, b_law, g_a, g_b, om_a, om_b, a_rigid, b_rigid, settings, lr_normal, out) -> bool:
    """Unit normal from a to b by the selected method (000 Sec 2.5, 004 Eq 13, LR)."""
    method = int(settings[S_NORMAL])
    if method == NORMAL_SN:
        return normal_sn(settings[S_SN_X:S_SN_X + out.shape[0]], a, b_law, out)
    if method == NORMAL_MVG:
        return normal_mvg(g_a, g_b, out)
    if method == NORMAL_AVG:
        return normal_avg(om_a, g_a, om_b, g_b, out)
    if method == NORMAL_AG:
        return normal_ag(g_a, g_b, out)
    if method == NORMAL_RMVG:
        return normal_rmvg(g_a, g_b, a_rigid, b_rigid, out)
    # NORMAL_LR: precomputed per (node, material) by mpm.multimaterial_lr; where the
    # regression had no two-class point cloud, fall back to MVG. NORMAL_SN_RADIAL: the
    # fixed radial normals of mpm.multimaterial.MultimaterialTables.node_normals
    s = 0.0
    for k in range(out.shape[0]):
        out[k] = lr_normal[i, a, k]
        s += out[k] * out[k]
    if not (s > 0.0):
        return normal_mvg(g_a, g_b, out)
    s = 1.0 / math.sqrt(s)
    for k in range(out.shape[0]):
        out[k] *= s
    return True


@njit(cache=True, refcount=False)
def _rigid_normal(g_a, g_r, om_r, cell, settings, out) -> bool:
    """Normal from a deformable field to a rigid partner: the rigid body's own surface
    normal -g_r (000 Sec 2.5, RMVG; NairnMPM prefers the rigid gradient), turned to
    point the way the deformable field's outward gradient g_a points (out of a, into
    the rigid body). Without the turn a node beyond the mid-plane of a rigid body one
    or two cells thick sees g_r pointing out of the far face; the grid normals (AG:
    g_a - g_r, nearly parallel vectors cancel) then lay the normal along the face and
    the frictionless tangential motion carried the deformable field through the body
    (004 Fig 6 piston, found by tracing the first particle above it). A specified
    normal (SN) is kept; False when the rigid field has no gradient at the node (inside
    a rigid body its gradient is round-off: |g_r| below 1e-6 of Omega_r / dx). Where
    g_a and g_r are perpendicular (a field's corner node beside a flat rigid face) the
    rigid normal is kept: a sign test on their round-off dot product let a 1e-15 mm move
    of the particles decide contact there (004 Fig 6 piston, uGIMP)."""
    method = int(settings[S_NORMAL])
    if method == NORMAL_SN or method == NORMAL_SN_RADIAL:
        return False
    size_r = math.sqrt(_dot(g_r, g_r))
    if not (size_r > 1.0e-6 * om_r / cell[0]):
        return False
    for k in range(out.shape[0]):
        out[k] = -g_r[k]
    if _dot(out, g_a) < -PERPENDICULAR_COSINE * size_r * math.sqrt(_dot(g_a, g_a)):
        for k in range(out.shape[0]):
            out[k] = g_r[k]
    s = 1.0 / math.sqrt(_dot(out, out))      # > 0: |g_r| passed the test above
    for k in range(out.shape[0]):
        out[k] *= s
    return True


@njit(cache=True, inline="always")
def _rigid_order(i, present, npres, vol, rigid, order) -> int:
    """The rigid fields present at node i, most volume first (into ``order``); their count."""
    count = 0
    for j in range(npres):
        c = present[j]
        if rigid[c] == 0:
            continue
        q = count
        while q > 0 and vol[i, order[q - 1]] < vol[i, c]:
            order[q] = order[q - 1]
            q -= 1
        order[q] = c
        count += 1
    return count


@njit(cache=True, inline="always")
def _edge_distance(df, s0, ds, s) -> float:
    """d(s) of the tabulated curve (mpm.contact_separation), held at its ends."""
    u = (s - s0) / ds
    if u <= 0.0:
        return df[0]
    top = df.shape[0] - 1
    if u >= top:
        return df[top]
    k = int(u)
    f = u - k
    return df[k] + f * (df[k + 1] - df[k])


@njit(cache=True, refcount=False)
def _df_gap(i, x_a, x_b, n, cell, origin, nn, hc, settings, df) -> float:
    """004 Eq 15: d_b((x_b - x_i) . n) - d_a((x_a - x_i) . n), the normal gap between
    the two materials' edges (mm), with d_a = d and d_b(s) = -d(-s) in units of hc."""
    sa = 0.0
    sb = 0.0
    rem = i
    for k in range(n.shape[0]):
        xk = origin[k] + (rem % nn[k]) * cell[k]
        rem //= nn[k]
        sa += (x_a[k] - xk) * n[k]
        sb += (x_b[k] - xk) * n[k]
    s0 = settings[S_DF_S0]
    ds = settings[S_DF_DS]
    return -hc * (_edge_distance(df, s0, ds, -sb / hc) + _edge_distance(df, s0, ds, sa / hc))


@njit(cache=True, refcount=False)
def _jump(i, a, x_a, x_b, n, cell, origin, nn, settings, lr_sep, df, jump, t_hat) -> float:
    """Separation vector delta = x_b - x_a (000 Eq 11, 13) corrected by the contact
    offset (Eq 14, delta_con = factor * h_perp), or with its normal part replaced by
    the LR separation (004 Eq 24) or the DF gap between the edges (004 Eq 15, table
    ``df``).  Writes the corrected jump vector into ``jump`` and a unit tangent along
    its tangential part (000 Eq 15) into ``t_hat``; returns h_perp."""
    d = n.shape[0]
    for k in range(d):
        jump[k] = x_b[k] - x_a[k]
    dn = _dot(jump, n)
    tn = 0.0
    for k in range(d):
        t_hat[k] = jump[k] - dn * n[k]
        tn += t_hat[k] * t_hat[k]
    if tn > 1.0e-28 * (cell[0] * cell[0]):
        tn = 1.0 / math.sqrt(tn)
        for k in range(d):
            t_hat[k] *= tn
    else:
        any_tangent(n, t_hat)
    hmethod = int(settings[S_HPERP])
    h = h_perp(n, t_hat, cell, hmethod)
    sep = int(settings[S_SEPARATION])
    if sep == SEP_OFFSET:
        hc = h if hmethod != HPERP_NONE else cell[0]
        for k in range(d):
            jump[k] -= settings[S_CONTACT_OFFSET] * hc * n[k]
    elif sep == SEP_LR and not math.isnan(lr_sep[i, a]):
        # normal part from the LR separation (004 Eq 24), tangential from displacements
        shift = lr_sep[i, a] - dn
        for k in range(d):
            jump[k] += shift * n[k]
    elif sep == SEP_DF:
        hc = h if hmethod != HPERP_NONE else cell[0]
        shift = _df_gap(i, x_a, x_b, n, cell, origin, nn, hc, settings, df) - dn
        for k in range(d):
            jump[k] += shift * n[k]
    return h


# ---------------------------------------------------------------------------
# contact / perfect-direction momentum change for one (a, b) interaction
# ---------------------------------------------------------------------------
@njit(cache=True, refcount=False)
def _delta_p(code, law, dp0, n, dn, approaching, touching, out, tv) -> bool:
    """Momentum change of material a (000 Eq 7-16, 004 Eq 8-10, 002 Sec 2.4).

    ``dp0`` = m_a v_c - p_a (000 Eq 7 / Eq 29 for rigid b), ``n`` the unit normal a->b,
    ``dn`` the normal separation.  Returns False if nothing changes."""
    d = n.shape[0]
    for k in range(d):
        out[k] = 0.0
    if code == LAW_PERFECT:
        for k in range(d):
            out[k] = dp0[k]
        return True
    dpn = _dot(dp0, n)
    if code == LAW_STICK or code == LAW_FRICTION:
        if not (approaching and touching):
            return False
        if code == LAW_STICK:
            for k in range(d):
                out[k] = dp0[k]
            return True
        # Coulomb friction, 004 Eq 8-10 with S_slide = min(mu N_c, dp0.t/(A_c dt)):
        # dp = (dp0.n) n + min(-mu dp0.n, dp0.t) t, t along the tangential part of dp0
        tt = 0.0
        for k in range(d):
            tv[k] = dp0[k] - dpn * n[k]
            tt += tv[k] * tv[k]
        tt = math.sqrt(tt)
        slide = 0.0
        if tt > 0.0:
            slide = min(-law[P_MU] * dpn, tt) / tt
        for k in range(d):
            out[k] = dpn * n[k] + slide * tv[k]
        return True
    if code == LAW_IMPERFECT:
        changed = False
        dn_t = law[P_DN_TENSION]
        dn_c = law[P_DN_COMPRESSION]
        normal_perfect = False
        if math.isinf(dn_t) and math.isinf(dn_c):
            normal_perfect = True                 # bonded in the normal direction
        elif dn <= 0.0 and math.isinf(dn_c):
            normal_perfect = approaching          # perfect in compression = contact
        elif dn > 0.0 and math.isinf(dn_t):
            normal_perfect = True
        if normal_perfect:
            for k in range(d):
                out[k] += dpn * n[k]
            changed = True
        if math.isinf(law[P_DT]):
            for k in range(d):
                out[k] += dp0[k] - dpn * n[k]
            changed = True
        return changed
    return False


@njit(cache=True, refcount=False)
def _interaction_dp(i, a, b_only, b_law, present, npres, phase, mass, mom, force, vol, grad, disp, pos,
                    cell, origin, nn, tvol, code, law, settings, rigid_b, lr_normal, lr_sep, df, dt,
                    out, work) -> bool:
    """Momentum change of material a against b (or the lump of all others)."""
    d = mom.shape[2]
    if code == LAW_NONE:
        return False
    p_b = work[0]
    f_b = work[1]
    g_b = work[2]
    x_b = work[3]
    dp0 = work[4]
    n = work[5]
    jump = work[6]
    t_hat = work[7]
    xfield = pos if _uses_positions(settings) else disp
    m_b, om_b = _gather_b(i, a, b_only, present, npres, mass, mom, force, vol, grad, xfield,
                          p_b, f_b, g_b, x_b)
    m_a = mass[i, a]
    for k in range(d):
        if rigid_b:                    # 000 Eq 28-29: v_c = v_b
            dp0[k] = m_a * p_b[k] / m_b - mom[i, a, k]
        else:                          # 000 Eq 7-8
            dp0[k] = m_a * (mom[i, a, k] + p_b[k]) / (m_a + m_b) - mom[i, a, k]
    if code == LAW_PERFECT:
        return _delta_p(code, law, dp0, dp0, 0.0, True, True, out, work[8])
    om_a = vol[i, a]
    if om_a + om_b < settings[S_EDGE_CUTOFF] * tvol:      # edge-node screening (000 Sec 3)
        return False
    if not (rigid_b and _rigid_normal(grad[i, a], g_b, om_b, cell, settings, n)) and \
            not _node_normal(i, a, b_law, grad[i, a], g_b, om_a, om_b, False, rigid_b, settings,
                             lr_normal, n):
        return False
    _jump(i, a, xfield[i, a], x_b, n, cell, origin, nn, settings, lr_sep, df, jump, t_hat)
    dn = _dot(jump, n)
    if phase == 1:
        # predict the separation at the end of the step with the updated velocities
        rel = 0.0
        for k in range(d):
            rel += (p_b[k] / m_b - mom[i, a, k] / m_a) * n[k]
        dn += dt * rel
    approaching = _dot(dp0, n) < 0.0         # 000 Eq 9: dv.n < 0  <=>  dp_a.n < 0
    # 000 Eq 12-14, 004 Eq 15/24; velocity-only detection (004 Eq 14 alone) skips the test
    touching = dn <= 0.0 or int(settings[S_SEPARATION]) == SEP_VELOCITY
    return _delta_p(code, law, dp0, n, dn, approaching, touching, out, work[8])


@njit(cache=True, inline="always")
def _uses_positions(settings) -> bool:
    """Offset (000 Eq 14) and DF (004 Eq 15) separations work on extrapolated positions."""
    sep = int(settings[S_SEPARATION])
    return sep == SEP_OFFSET or sep == SEP_DF


@njit(cache=True, inline="always")
def _cell_volume(cell, thick, i) -> float:
    v = 1.0
    for k in range(cell.shape[0]):
        v *= cell[k]
    if cell.shape[0] == 2:
        v *= thick[i] if thick.shape[0] > 1 else thick[0]
    return v


# ---------------------------------------------------------------------------
# nodes seen by three or more materials, pair by pair (004 Sec 3.4, Eq 49)
# ---------------------------------------------------------------------------
@njit(cache=True, refcount=False)
def _pair_contact(i, a, b, phase, mass, mom, vol, grad, xfield, cell, origin, nn, tvol, code,
                  settings, lr_normal, lr_sep, pair_normal, pair_sep, df, dt, n, work) -> bool:
    """Is the pair (a, b) in contact at node i? Its own normal a -> b into ``n`` (LR: the
    pair's regression, :func:`mpm.multimaterial_lr.lr_kernel`; grid normals: from the two
    fields' volume gradients alone) and its own separation (Eq 24 of the pair, or the
    displacement / offset / DF separation of the two fields); approaching and touching as
    for two materials (000 Eq 9, 12-14). A perfect pair is always in contact."""
    d = n.shape[0]
    lr = int(settings[S_NORMAL]) == NORMAL_LR
    slot = pair_index(min(a, b), max(a, b), mass.shape[1])
    if lr:
        s = 0.0
        for k in range(d):
            n[k] = pair_normal[i, slot, k] if a < b else -pair_normal[i, slot, k]
            s += n[k] * n[k]
        if not (s > 0.0) and not normal_mvg(grad[i, a], grad[i, b], n):
            return False
    elif not _node_normal(i, a, b, grad[i, a], grad[i, b], vol[i, a], vol[i, b], False, False,
                          settings, lr_normal, n):
        return False
    if code == LAW_PERFECT:
        return True
    if vol[i, a] + vol[i, b] < settings[S_EDGE_CUTOFF] * tvol:     # edge-node screening
        return False
    if int(settings[S_SEPARATION]) == SEP_LR:
        dn = pair_sep[i, slot] if lr else np.nan
        if math.isnan(dn):
            dn = 0.0
            for k in range(d):
                dn += (xfield[i, b, k] - xfield[i, a, k]) * n[k]
    else:
        _jump(i, a, xfield[i, a], xfield[i, b], n, cell, origin, nn, settings, lr_sep, df,
              work[6], work[7])
        dn = _dot(work[6], n)
    rel = 0.0
    for k in range(d):
        rel += (mom[i, b, k] / mass[i, b] - mom[i, a, k] / mass[i, a]) * n[k]
    if phase == 1:
        dn += dt * rel
    touching = dn <= 0.0 or int(settings[S_SEPARATION]) == SEP_VELOCITY
    return rel < 0.0 and touching


@njit(cache=True, refcount=True)
def _explicit_three_plus(i, phase, present, npres, mass, mom, vol, grad, disp, pos, cell, origin,
                         nn, tvol, kind, params, settings, node_zone, zone_pairs, zone_kind,
                         zone_params, lr_normal, lr_sep, pair_normal, pair_sep, df, dt, dp,
                         touched, work, law) -> int:
    """004 Sec 3.4, explicit 3+ nodes: the pairs in contact found pair by pair; one pair
    corrected as two materials, two pairs sharing a material solved together
    (:func:`mpm.multimaterial_three.two_pair_impulses`), two unrelated pairs each on its
    own. Returns the number of pairs corrected, or -1 when the node must be lumped
    (three or more pairs in contact, or a pair with an imperfect-interface law)."""
    d = mom.shape[2]
    xfield = pos if _uses_positions(settings) else disp
    act = np.empty((3, 2), np.int64)
    act_code = np.empty(3, np.int64)
    act_mu = np.empty(3)
    act_n = np.empty((3, d))
    nact = 0
    for ja in range(npres):
        for jb in range(ja + 1, npres):
            a = present[ja]
            b = present[jb]
            code = _pair_law(i, a, b, kind, params, node_zone, zone_pairs, zone_kind, zone_params, law)
            if code == LAW_NONE:
                continue
            if code == LAW_IMPERFECT:
                return -1
            if not _pair_contact(i, a, b, phase, mass, mom, vol, grad, xfield, cell, origin, nn,
                                 tvol, code, settings, lr_normal, lr_sep, pair_normal, pair_sep,
                                 df, dt, work[5], work):
                continue
            if nact == 2:
                return -1                            # 3+ pairs in contact: lumping (004)
            act[nact, 0] = a
            act[nact, 1] = b
            act_code[nact] = code
            act_mu[nact] = law[P_MU]
            for k in range(d):
                act_n[nact, k] = work[5, k]
            nact += 1
    if nact == 2:
        common = _common_material(act)
        if common >= 0:
            _two_pairs(i, act, act_code, act_mu, act_n, common, mass, mom, dp, touched)
            return 2
    for q in range(nact):
        _one_pair(i, act[q, 0], act[q, 1], act_code[q], act_mu[q], act_n[q], mass, mom, dp,
                  touched, work, law)
    return nact


@njit(cache=True, inline="always")
def _common_material(act) -> int:
    """The material shared by the two pairs of ``act``, or -1."""
    for u in range(2):
        for v in range(2):
            if act[0, u] == act[1, v]:
                return act[0, u]
    return -1


@njit(cache=True, refcount=False)
def _one_pair(i, a, b, code, mu, n, mass, mom, dp, touched, work, law) -> None:
    """Momentum change of one pair in contact at a 3+ node, as at a two-material node."""
    d = n.shape[0]
    dp0 = work[4]
    law[P_MU] = mu
    m_a = mass[i, a]
    m_b = mass[i, b]
    for k in range(d):
        dp0[k] = m_a * (mom[i, a, k] + mom[i, b, k]) / (m_a + m_b) - mom[i, a, k]
    if _delta_p(code, law, dp0, n, 0.0, True, True, work[12], work[8]):
        for k in range(d):
            dp[a, k] += work[12, k]
            dp[b, k] -= work[12, k]
        touched[a] = True
        touched[b] = True


@njit(cache=True)
def _two_pairs(i, act, act_code, act_mu, act_n, common, mass, mom, dp, touched) -> None:
    """Two pairs (alpha, gamma), (beta, gamma) in contact: 004 Eq 49 solved for both laws."""
    d = act_n.shape[1]
    masses = np.empty(3)
    vel = np.empty((3, d))
    normals = np.empty((2, d))
    J = np.empty((2, d))
    other = np.empty(2, np.int64)
    for q in range(2):
        o = act[q, 0] if act[q, 1] == common else act[q, 1]
        sign = 1.0 if act[q, 0] == o else -1.0          # act_n points act[q, 0] -> act[q, 1]
        other[q] = o
        masses[q] = mass[i, o]
        for k in range(d):
            normals[q, k] = sign * act_n[q, k]
            vel[q, k] = mom[i, o, k] / mass[i, o]
    masses[2] = mass[i, common]
    for k in range(d):
        vel[2, k] = mom[i, common, k] / mass[i, common]
    if two_pair_impulses(masses, vel, normals, act_code[:2], act_mu[:2], J) == 0:
        return
    for q in range(2):
        o = other[q]
        touched[o] = True
        for k in range(d):
            dp[o, k] += J[q, k]
            dp[common, k] -= J[q, k]
    touched[common] = True


@njit(cache=True, inline="always")
def _restore_sum(i, present, npres, mass, mtot, dp) -> None:
    """Lumped 3+ nodes: a common velocity shift (each field's share m_c / m_total of the
    sum) that restores sum dp = 0 over the ``present`` fields without changing any
    relative velocity, hence without disturbing the contact laws."""
    for k in range(dp.shape[1]):
        s = 0.0
        for j in range(npres):
            s += dp[present[j], k]
        for j in range(npres):
            c = present[j]
            dp[c, k] -= mass[i, c] / mtot * s


@njit(cache=True, refcount=False)
def _deformable_contact(i, phase, present, npres, mass, mom, force, vol, grad, disp, pos, cell,
                        origin, nn, tvol, kind, params, settings, rigid, node_zone, zone_pairs,
                        zone_kind, zone_params, lr_normal, lr_sep, pair_normal, pair_sep, df, dt,
                        explicit, conserve, dp, touched, one, work, law) -> bool:
    """Momentum changes ``dp`` of the ``npres`` deformable fields ``present`` at node i
    against each other: two fields as a pair (000 Eq 7-16), three or more pair by pair
    (004 Sec 3.4, Eq 49, ``explicit``) or each against the lump of the others (000 Sec 2.6,
    004 Eq 50). Returns True if any field changed."""
    d = mom.shape[2]
    any_change = False
    if npres < 2:
        return False
    if npres == 2:
        # a field much lighter than its partner gets the change computed on its own
        # side and the heavier one its negative: the stick change m_a v_c - p_a
        # carries round-off of the size of |p_a|, which on a field holding only a
        # round-off-sized GIMP weight (m ~ 1e-65 of its partner) gave velocities
        # ~1e30 and a spurious damping dissipation of up to 1e7 N mm (an energy
        # balance off by 20x on a 0.1 mm DLS)
        a = present[0]
        b = present[1]
        if mass[i, b] < LIGHT_FIELD_RATIO * mass[i, a]:
            a = present[1]
            b = present[0]
        code = _pair_law(i, a, b, kind, params, node_zone, zone_pairs, zone_kind, zone_params, law)
        if _interaction_dp(i, a, b, b, present, npres, phase, mass, mom, force, vol, grad, disp, pos,
                           cell, origin, nn, tvol, code, law, settings, False, lr_normal, lr_sep, df,
                           dt, one, work):
            touched[a] = True
            touched[b] = True
            for k in range(d):
                dp[a, k] = one[k]
                dp[b, k] = -one[k]
            return True
        return False
    if explicit and _explicit_three_plus(
            i, phase, present, npres, mass, mom, vol, grad, disp, pos, cell, origin, nn, tvol,
            kind, params, settings, node_zone, zone_pairs, zone_kind, zone_params, lr_normal,
            lr_sep, pair_normal, pair_sep, df, dt, dp, touched, work, law) >= 0:
        # 3+ materials, pair by pair (004 Sec 3.4, Eq 49)
        for j in range(npres):
            any_change = any_change or touched[present[j]]
        return any_change
    # 3+ materials: each against the virtual lump of all others (000 Sec 2.6, 004 Eq 50),
    # law of the partner with the most volume
    mtot = 0.0
    for j in range(npres):
        mtot += mass[i, present[j]]
    for j in range(npres):
        a = present[j]
        b_law = _largest_partner(i, a, present, npres, vol, rigid)
        code = _pair_law(i, a, b_law, kind, params, node_zone, zone_pairs, zone_kind, zone_params, law)
        if _interaction_dp(i, a, -1, b_law, present, npres, phase, mass, mom, force, vol, grad,
                           disp, pos, cell, origin, nn, tvol, code, law, settings, False,
                           lr_normal, lr_sep, df, dt, one, work):
            touched[a] = True
            for k in range(d):
                dp[a, k] = one[k]
            any_change = True
    if any_change and conserve:
        _restore_sum(i, present, npres, mass, mtot, dp)
        for j in range(npres):
            touched[present[j]] = True
    return any_change


@njit(cache=True)
def correct_momentum_kernel(phase, mass, mom, force, vol, grad, disp, pos, cell, origin, nn, thick, kind,
                            params, settings, rigid, node_zone, zone_pairs, zone_kind, zone_params,
                            lr_normal, lr_sep, pair_normal, pair_sep, lr_rigid_sep, df, dt,
                            nodes) -> int:
    """Contact corrections on all multimaterial nodes (see mpm.multimaterial.correct_momentum).
    ``lr_rigid_sep``: LR separations of each field from the rigid fields (rows empty: the
    separations ``lr_sep`` serve the rigid partners too). Allocates the buffers of the node
    loop, :func:`_correct_nodes`, which runs without reference counting (interfaces/jit.py)."""
    m = mass.shape[1]
    d = mom.shape[2]
    return _correct_nodes(phase, mass, mom, force, vol, grad, disp, pos, cell, origin, nn, thick,
                          kind, params, settings, rigid, node_zone, zone_pairs, zone_kind,
                          zone_params, lr_normal, lr_sep, pair_normal, pair_sep, lr_rigid_sep, df,
                          dt, nodes, np.empty(m, np.int64), np.zeros((m, d)), np.zeros(m, np.bool_),
                          np.empty(m, np.int64), np.empty(m, np.int64), np.empty(4), np.empty(d),
                          np.empty((WORK_ROWS, d)))


@njit(cache=True, refcount=False)
def _correct_nodes(phase, mass, mom, force, vol, grad, disp, pos, cell, origin, nn, thick, kind,
                   params, settings, rigid, node_zone, zone_pairs, zone_kind, zone_params,
                   lr_normal, lr_sep, pair_normal, pair_sep, lr_rigid_sep, df, dt, nodes, present,
                   dp, touched, rigid_order, deformable, law, one, work) -> int:
    """The node loop of :func:`correct_momentum_kernel`, on its buffers."""
    d = mom.shape[2]
    tol = settings[S_MASS_TOL]
    conserve = settings[S_LUMP_CONSERVE] != 0.0
    explicit = int(settings[S_THREE_MATERIAL]) == THREE_EXPLICIT
    rigid_sep = lr_rigid_sep if lr_rigid_sep.shape[0] > 0 else lr_sep
    beside_rigid = int(settings[S_SEPARATION]) == SEP_LR
    inv_dt = 1.0 / dt if dt > 0.0 else 0.0
    count = 0
    for ii in range(nodes.shape[0]):
        i = nodes[ii]
        npres = _present_fields(mass, i, tol, present)
        if npres < 2:
            continue
        tvol = _cell_volume(cell, thick, i)
        for j in range(npres):
            touched[present[j]] = False
            for k in range(d):
                dp[present[j], k] = 0.0
        # the deformable fields first, among themselves, then each against every rigid
        # field present (000 Eq 28-31), which have the last word: most volume first, each
        # correction on the momentum left by the one before (at a corner of a wall and the
        # piston both hold; against the largest alone the field left through the other).
        # Beside a rigid body the deformable fields meet each other with LR separations
        # only (``beside_rigid``): NairnMPM skips their contact there, which let the
        # ellipses of 004 Fig 6 slide into each other along the walls and the piston; with
        # DF separations the same order lost a particle at a floor corner (docs/mpm.md,
        # "Bodies meeting beside a rigid body"), so grid separations keep NairnMPM's rule
        nrigid = _rigid_order(i, present, npres, vol, rigid, rigid_order)
        ndef = 0
        for j in range(npres):
            if rigid[present[j]] == 0:
                deformable[ndef] = present[j]
                ndef += 1
        any_change = False
        if nrigid == 0 or beside_rigid:
            any_change = _deformable_contact(
                i, phase, deformable, ndef, mass, mom, force, vol, grad, disp, pos, cell, origin,
                nn, tvol, kind, params, settings, rigid, node_zone, zone_pairs, zone_kind,
                zone_params, lr_normal, lr_sep, pair_normal, pair_sep, df, dt, explicit, conserve,
                dp, touched, one, work, law)
        if nrigid > 0:
            for j in range(ndef):
                a = deformable[j]
                if touched[a]:
                    for k in range(d):
                        mom[i, a, k] += dp[a, k]     # the rigid corrections see it
                for q in range(nrigid):
                    r = rigid_order[q]
                    code = _pair_law(i, a, r, kind, params, node_zone, zone_pairs, zone_kind, zone_params,
                                     law)
                    if _interaction_dp(i, a, r, r, present, npres, phase, mass, mom, force, vol, grad,
                                       disp, pos, cell, origin, nn, tvol, code, law, settings, True,
                                       lr_normal, rigid_sep, df, dt, one, work):
                        touched[a] = True
                        any_change = True
                        for k in range(d):
                            dp[a, k] += one[k]
                            mom[i, a, k] += one[k]
                if touched[a]:
                    for k in range(d):
                        mom[i, a, k] -= dp[a, k]     # applied once, below, with f_C,1
        if not any_change:
            continue
        count += 1
        for j in range(npres):
            c = present[j]
            if not touched[c]:
                continue
            for k in range(d):
                mom[i, c, k] += dp[c, k]
                if phase == 1:
                    force[i, c, k] += dp[c, k] * inv_dt     # 004 Eq 33, f_C,1 = dp+/dt
    return count


# ---------------------------------------------------------------------------
# imperfect interface forces (000 Eq 17-27, 002 Eq 37-39)
# ---------------------------------------------------------------------------
@njit(cache=True, inline="always")
def _contact_area(i, a, b_only, present, npres, om_a, om_b, area_vol, h, settings) -> float:
    """Contact area, 000 Eq 20 (ERRATA 8) with dx -> h_perp (Eq 22); volumes carry t.
    With ``area_vol`` (reference nodal volumes) in place of the current om_a, om_b."""
    if area_vol.shape[0] > 0:
        om_a = area_vol[i, a]
        om_b = 0.0
        for j in range(npres):
            c = present[j]
            if c != a and (b_only < 0 or c == b_only):
                om_b += area_vol[i, c]
    omega = om_a + om_b
    if settings[S_AREA_CORRECTION] != 0.0:
        return math.sqrt(2.0 * omega * min(om_a, om_b)) / h
    return omega / h


@njit(cache=True, refcount=False)
def _interface_force(i, a, b_only, b_law, present, npres, mass, mom, force, vol, area_vol, grad,
                     disp, pos, cell, origin, nn, tvol, law, settings, rigid_b, lr_normal, lr_sep, df,
                     dt, f_out, node_out, write_out, work) -> float:
    """Interface force on material a from b (or the lump of the others); returns U_i.
    ``area_vol``: the nodal volumes of Eq 20 (reference configuration), or empty for
    the current ones (mpm.multimaterial.AREA_VOLUMES)."""
    d = mom.shape[2]
    for k in range(d):
        f_out[k] = 0.0
    p_b = work[0]
    f_b = work[1]
    g_b = work[2]
    x_b = work[3]
    n = work[4]
    jump = work[5]
    t_hat = work[6]
    jt = work[7]
    ft = work[8]
    fmax = work[9]
    fmt = work[10]
    fstick = work[11]
    xfield = pos if _uses_positions(settings) else disp
    m_b, om_b = _gather_b(i, a, b_only, present, npres, mass, mom, force, vol, grad, xfield,
                          p_b, f_b, g_b, x_b)
    m_a = mass[i, a]
    om_a = vol[i, a]
    omega = om_a + om_b
    if omega < settings[S_EDGE_CUTOFF] * tvol:             # edge-node screening
        if write_out:
            node_out[i, OUT_STATUS] = STATUS_SCREENED
        return 0.0
    if not (rigid_b and _rigid_normal(grad[i, a], g_b, om_b, cell, settings, n)) and \
            not _node_normal(i, a, b_law, grad[i, a], g_b, om_a, om_b, False, rigid_b, settings,
                             lr_normal, n):
        return 0.0
    h = _jump(i, a, xfield[i, a], x_b, n, cell, origin, nn, settings, lr_sep, df, jump, t_hat)
    area = _contact_area(i, a, b_only, present, npres, om_a, om_b, area_vol, h, settings)
    dn = _dot(jump, n)
    for k in range(d):
        jt[k] = jump[k] - dn * n[k]
    dn_stiff = law[P_DN_COMPRESSION] if dn <= 0.0 else law[P_DN_TENSION]   # bilinear, 002 Sec 2.4
    dt_stiff = law[P_DT]
    n_finite = not math.isinf(dn_stiff)
    t_finite = not math.isinf(dt_stiff)
    fn = dn_stiff * dn * area if n_finite else 0.0
    for k in range(d):
        ft[k] = 0.0
    if t_finite:
        for k in range(d):
            ft[k] = dt_stiff * jt[k] * area
    status = STATUS_INTERFACE
    if dn <= 0.0:
        status += STATUS_CONTACT
    e_n = 0.5 * dn_stiff * dn * dn * area if n_finite else 0.0
    e_t = 0.5 * dt_stiff * _dot(jt, jt) * area if t_finite else 0.0
    if dt > 0.0:
        # 000 Eq 26-27: the force that brings a and b to the centre-of-mass position at
        # the end of the step.  Eq 26 is derived for the midpoint position update of
        # Eq 23-25 (u+ = u + dt (p + dt f / 2) / m), which gives the factors 2.  This
        # MPM moves particles with the updated velocity (u+ = u + dt (p + dt f) / m,
        # G2P in mpm/LAYOUT.md), for which the same condition gives
        # f_max = m_red [u] / dt^2 + Delta p / dt + Delta f; with the printed factors
        # the capped force overshoots the centre of mass and the relative motion grows
        # by 1 + sqrt(2) per step (stiff interfaces diverge even with limiting).
        # A direction whose force exceeds that bound becomes stick contact with zero
        # energy (000 after Eq 27): the applied force only equalises the velocities,
        # f_stick = Delta p / dt + Delta f, as the momentum correction of a perfect
        # direction does (applying f_max itself feeds the jump back at the stability
        # limit and diverged on DLS at Dn = Dt = 1e5).  A direction whose stiffness
        # alone exceeds the bound (D A dt^2 > m_red: the spring overshoots the centre of
        # mass for any jump) is also limited, whatever the velocities.
        if rigid_b:
            m_red = m_a
        else:
            m_red = m_a * m_b / (m_a + m_b)
        for k in range(d):
            if rigid_b:
                dp0 = m_a * p_b[k] / m_b - mom[i, a, k]
                dfk = -force[i, a, k]
            else:
                dp0 = m_red * (p_b[k] / m_b - mom[i, a, k] / m_a)
                dfk = (m_a * f_b[k] - m_b * force[i, a, k]) / (m_a + m_b)
            fmax[k] = m_red / (dt * dt) * jump[k] + dp0 / dt + dfk
            fstick[k] = dp0 / dt + dfk
        fmax_n = _dot(fmax, n)
        for k in range(d):
            fmt[k] = fmax[k] - fmax_n * n[k]
        over_n = n_finite and (abs(fn) > abs(fmax_n) or dn_stiff * area * dt * dt > m_red)
        over_t = t_finite and (_dot(ft, ft) > _dot(fmt, fmt) or dt_stiff * area * dt * dt > m_red)
        if settings[S_FORCE_LIMIT] == 0.0:
            # no limiting: flag the node, the caller warns (explicit instability)
            if over_n or over_t:
                status += STATUS_OVER_LIMIT
            over_n = False
            over_t = False
        if over_n:
            # limited direction -> stick (velocity-equalising force, zero energy)
            fn = _dot(fstick, n)
            e_n = 0.0
            status += STATUS_LIMITED_N
        if over_t:
            fsn = _dot(fstick, n)
            for k in range(d):
                ft[k] = fstick[k] - fsn * n[k]
            e_t = 0.0
            status += STATUS_LIMITED_T
    for k in range(d):
        f_out[k] = fn * n[k] + ft[k]
    energy = e_n + e_t
    if write_out:
        if d == 2:
            jt_s = -jump[0] * n[1] + jump[1] * n[0]
            tt_s = (-ft[0] * n[1] + ft[1] * n[0]) / area if area > 0.0 else 0.0
        else:
            jt_s = math.sqrt(_dot(jt, jt))
            tt_s = math.sqrt(_dot(ft, ft)) / area if area > 0.0 else 0.0
        node_out[i, OUT_JUMP_N] = dn
        node_out[i, OUT_JUMP_T] = jt_s
        node_out[i, OUT_TRACTION_N] = fn / area if area > 0.0 else 0.0
        node_out[i, OUT_TRACTION_T] = tt_s
        for k in range(d):
            node_out[i, OUT_NX + k] = n[k]
        node_out[i, OUT_AREA] = area
        node_out[i, OUT_ENERGY] = energy
        node_out[i, OUT_STATUS] = status
    return energy


@njit(cache=True, refcount=False)
def _deformable_interface_forces(i, fields, nf, mass, mom, force, vol, area_vol, grad, disp, pos, cell,
                                 origin, nn, tvol, kind, params, settings, rigid, node_zone, zone_pairs,
                                 zone_kind, zone_params, lr_normal, lr_sep, df, dt, conserve, fadd,
                                 node_out, write_out, one, work, law) -> float:
    """Interface forces ``fadd`` among the ``nf`` deformable ``fields`` at node i: two as a
    pair, equal and opposite (002 Eq 39), three or more each against the lump of the
    others (000 Sec 2.6), the energy of the node counted once (half the sum over its
    materials). Returns the interface energy of the node."""
    d = mom.shape[2]
    if nf == 2:
        a = fields[0]
        b = fields[1]
        code = _pair_law(i, a, b, kind, params, node_zone, zone_pairs, zone_kind, zone_params, law)
        if code != LAW_IMPERFECT:
            return 0.0
        energy = _interface_force(i, a, b, b, fields, nf, mass, mom, force, vol, area_vol, grad, disp,
                                  pos, cell, origin, nn, tvol, law, settings, False, lr_normal, lr_sep,
                                  df, dt, one, node_out, write_out, work)
        for k in range(d):
            fadd[a, k] += one[k]
            fadd[b, k] -= one[k]
        return energy
    mtot = 0.0
    for j in range(nf):
        mtot += mass[i, fields[j]]
    e_node = 0.0
    any_force = False
    for j in range(nf):
        a = fields[j]
        b_law = _largest_partner(i, a, fields, nf, vol, rigid)
        code = _pair_law(i, a, b_law, kind, params, node_zone, zone_pairs, zone_kind, zone_params, law)
        if code != LAW_IMPERFECT:
            continue
        e_node += _interface_force(i, a, -1, b_law, fields, nf, mass, mom, force, vol, area_vol, grad,
                                   disp, pos, cell, origin, nn, tvol, law, settings, False, lr_normal,
                                   lr_sep, df, dt, one, node_out, write_out and not any_force, work)
        any_force = True
        for k in range(d):
            fadd[a, k] += one[k]
    if write_out and any_force:
        node_out[i, OUT_ENERGY] = 0.5 * e_node
    if any_force and conserve:
        _restore_sum(i, fields, nf, mass, mtot, fadd)
    return 0.5 * e_node


@njit(cache=True)
def interface_forces_kernel(mass, mom, vol, area_vol, grad, disp, pos, cell, origin, nn, thick, kind,
                            params, settings, rigid, node_zone, zone_pairs, zone_kind, zone_params,
                            lr_normal, lr_sep, lr_rigid_sep, df, dt, force, node_out, nodes) -> float:
    """Interface forces on all multimaterial nodes (see mpm.multimaterial.add_interface_forces).
    ``lr_rigid_sep`` as in :func:`correct_momentum_kernel`. At a node that also sees a
    rigid body the deformable fields first take their forces among themselves (an
    interface ending on a wall keeps its end node), then each its force from the
    largest rigid partner. Allocates the buffers of the node loop,
    :func:`_interface_nodes`, which runs without reference counting (interfaces/jit.py)."""
    m = mass.shape[1]
    d = mom.shape[2]
    return _interface_nodes(mass, mom, vol, area_vol, grad, disp, pos, cell, origin, nn, thick,
                            kind, params, settings, rigid, node_zone, zone_pairs, zone_kind,
                            zone_params, lr_normal, lr_sep, lr_rigid_sep, df, dt, force, node_out,
                            nodes, np.empty(m, np.int64), np.empty(m, np.int64), np.zeros((m, d)),
                            np.empty(4), np.empty(d), np.empty((WORK_ROWS, d)))


@njit(cache=True, refcount=False)
def _interface_nodes(mass, mom, vol, area_vol, grad, disp, pos, cell, origin, nn, thick, kind,
                     params, settings, rigid, node_zone, zone_pairs, zone_kind, zone_params,
                     lr_normal, lr_sep, lr_rigid_sep, df, dt, force, node_out, nodes, present,
                     deformable, fadd, law, one, work) -> float:
    """The node loop of :func:`interface_forces_kernel`, on its buffers."""
    n_nodes = mass.shape[0]
    d = mom.shape[2]
    tol = settings[S_MASS_TOL]
    conserve = settings[S_LUMP_CONSERVE] != 0.0
    write_out = node_out.shape[0] == n_nodes
    if write_out:
        node_out[:, :] = 0.0
    rigid_sep = lr_rigid_sep if lr_rigid_sep.shape[0] > 0 else lr_sep
    total = 0.0
    for ii in range(nodes.shape[0]):
        i = nodes[ii]
        npres = _present_fields(mass, i, tol, present)
        if npres < 2:
            continue
        tvol = _cell_volume(cell, thick, i)
        r = -1
        rv = -1.0
        ndef = 0
        for j in range(npres):
            c = present[j]
            for k in range(d):
                fadd[c, k] = 0.0
            if rigid[c] == 0:
                deformable[ndef] = c
                ndef += 1
            elif vol[i, c] > rv:
                rv = vol[i, c]
                r = c
        if ndef >= 2:
            total += _deformable_interface_forces(
                i, deformable, ndef, mass, mom, force, vol, area_vol, grad, disp, pos, cell, origin, nn,
                tvol, kind, params, settings, rigid, node_zone, zone_pairs, zone_kind, zone_params,
                lr_normal, lr_sep, df, dt, conserve, fadd, node_out, write_out, one, work, law)
        if r >= 0:
            # rigid partner: force on the deformable fields only, energy per interaction
            for j in range(ndef):
                a = deformable[j]
                code = _pair_law(i, a, r, kind, params, node_zone, zone_pairs, zone_kind, zone_params, law)
                if code != LAW_IMPERFECT:
                    continue
                total += _interface_force(i, a, r, r, present, npres, mass, mom, force, vol, area_vol,
                                          grad, disp, pos, cell, origin, nn, tvol, law, settings, True,
                                          lr_normal, rigid_sep, df, dt, one, node_out, write_out, work)
                for k in range(d):
                    fadd[a, k] += one[k]
        for j in range(npres):
            c = present[j]
            for k in range(d):
                force[i, c, k] += fadd[c, k]
    return total


@njit(cache=True, refcount=False)
def stick_limited_kernel(mass, mom, node_out, nodes) -> None:
    """Hold the force-limited directions of this step's interface nodes as stick on
    re-extrapolated momenta (MUSL): a direction limited by 000 Eq 26 is a
    velocity-equalising constraint for the step (the force that brings both fields to
    their centre of mass), so, as the momentum correction of a perfect direction is
    applied again to the re-extrapolated momenta, both fields take the centre-of-mass
    velocity along the limited direction(s) at the nodes of two fields (the normal of
    the step, ``node_out``). Without it the strain update of MUSL sees the two fields'
    own velocities where the interface is held stiff, and a particulate composite
    with every node limited (Dn = Dt = 1e7 at 50 um cells) diverged."""
    if node_out.shape[0] == 0:
        return
    n_fields = mass.shape[1]
    d = mom.shape[2]
    limited_n = int(STATUS_LIMITED_N)
    limited_t = int(STATUS_LIMITED_T)
    for q in range(nodes.size):
        i = nodes[q]
        status = int(node_out[i, OUT_STATUS])
        ln = (status & limited_n) != 0
        lt = (status & limited_t) != 0
        if not (ln or lt):
            continue
        a = -1
        b = -1
        count = 0
        for f in range(n_fields):
            if mass[i, f] > 0.0:
                count += 1
                if a < 0:
                    a = f
                else:
                    b = f
        if count != 2:
            continue
        M = mass[i, a] + mass[i, b]
        vcn = 0.0
        van = 0.0
        vbn = 0.0
        for k in range(d):
            nk = node_out[i, OUT_NX + k]
            vcn += (mom[i, a, k] + mom[i, b, k]) / M * nk
            van += mom[i, a, k] / mass[i, a] * nk
            vbn += mom[i, b, k] / mass[i, b] * nk
        for k in range(d):
            nk = node_out[i, OUT_NX + k]
            vc = (mom[i, a, k] + mom[i, b, k]) / M
            for f, vfn in ((a, van), (b, vbn)):
                v = mom[i, f, k] / mass[i, f]
                normal_part = vcn * nk if ln else vfn * nk
                tangential = (vc - vcn * nk) if lt else (v - vfn * nk)
                mom[i, f, k] = mass[i, f] * (normal_part + tangential)


# ---------------------------------------------------------------------------
# nodal velocity conditions after the contact corrections
# ---------------------------------------------------------------------------
@njit(cache=True)
def bonded_velocity_bc_kernel(mass, momentum, force, bc_node, bc_field, bc_comp, bc_vel,
                              kind, params, settings, node_zone, zone_pairs, zone_kind,
                              zone_params, dt, with_force):
    """Re-impose nodal velocity conditions after a momentum correction.

    Condition b prescribes v_bc on field f at node n.  The correction may have moved
    that field (perfect bond to the centre of mass, 000 Eq 7-8), so it is reset, and
    so is every other field present at n that is perfectly bonded to f there: a bonded
    node is one continuum point, which the condition holds (a body split by a perfect
    interface then equals the uncut body, 004 Eq 34).  p = m v_bc; with ``with_force``
    the reaction (p_bc - p)/dt is also added to ``force`` (keeps a = f/m consistent with
    the momentum change for FLIP).  Returns the work of these reactions this step."""
    n_nodes, m = mass.shape
    tol = settings[S_MASS_TOL]
    law = np.empty(4)
    work = 0.0
    for b in range(bc_node.shape[0]):
        i = bc_node[b]
        f = bc_field[b]
        d = bc_comp[b]
        if not (mass[i, f] > 0.0):
            continue
        mtot = 0.0
        for k in range(m):
            mtot += mass[i, k]
        for g in range(m):
            mg = mass[i, g]
            if g != f:
                if not (mg > 0.0 and mg > tol * mtot):
                    continue
                if _pair_law(i, f, g, kind, params, node_zone, zone_pairs, zone_kind,
                             zone_params, law) != LAW_PERFECT:
                    continue
            pn = mg * bc_vel[b]
            if with_force:
                reaction = (pn - momentum[i, g, d]) / dt
                force[i, g, d] += reaction
                work += reaction * bc_vel[b] * dt
            momentum[i, g, d] = pn
    return work
