"""Logistic-regression (LR) contact normal and separation (004 Sec 3.1, Eq 19-25, 53-57).

For each multimaterial node of a CPDI or B2-CPDI run the point cloud is the material
points contributing to the node (004 Sec 3.1, Fig 3A): those whose shape function is
nonzero there, i.e. whose deformed domain x +- F R_0 has a corner in the cells around
the node (:func:`_support_nodes`), so a compressed or sheared particle joins the cloud
of every node it reaches.  Where a class has fewer than ``LR_MIN_POINTS`` points there,
or the cloud is flat (a node just beyond a body's free side sees one column of particles
of each body: a plane fitted to a line of points tilts with their small sideways
offsets; ``LR_FLAT``), the cloud is the particles centred in the 4^D cells around the
node instead.  uGIMP, linear and B2 runs take the particles centred in the 2^D cells
around the node (4^D where a class has fewer than ``LR_MIN_POINTS`` points): their
particles keep their shape, and there the support clouds made LR contact 5-8 % early in
004 Fig 2.  With the 2^D-cell clouds in CPDI runs LR let the 004 Fig 6 packing pass
through itself, the more the finer the grid (docs/mpm.md).
For material a against the lump of all others, classes are
c_p = -1 (a) and +1 (others); the separating plane x . phi = 0 with x = (X, 1)
minimises sum w_p (f(x_p, phi) - c_p)^2 + sum lambda_j phi_j^2 with the logistic
f = 2/(1 + exp(-x . phi)) - 1 (004 Eq 20), by the NLLS iteration of Eq 21 with the
Jacobian of Eq 53-56, phi^(0) = 0 (first step = linear regression), w_p = 1,
lambda = 1e-7 dx^2 (1, .., 1, 0) and the stopping rule 1 - n^(k+1) . n^(k) < 1e-5 or 15
iterations (Appendix, Eq 57).  Coordinates are taken relative to the node and scaled
by dx for conditioning (the penalty is scaled accordingly, so the minimiser is the
same).  The unit normal a -> b is phi_(1..D)/|phi_(1..D)|; the separation is Eq 24,
d_LR = min_{p in b}(X_p . n - R_p) - max_{p in a}(X_p . n + R_p), with R_p the distance
from the particle centre to its inscribed (deformed) ellipse(oid) along n (Eq 25).

At a node seen by two or more deformable fields and a rigid one, a deformable field's
lump is the other deformable fields, and its separation from the rigid fields is a
second regression against their particles alone (:func:`lr_kernel`): with the rigid
body in the lump, two bodies meeting beside a wall had their plane tilted towards the
wall and "touched" each other whenever one touched the wall.

Results go to ``normal[N, M, D]`` (normal from field k to the others at node i; zero
where not computed, then the kernels fall back to MVG) and ``separation[N, M]`` (NaN
where not computed, then the kernels fall back to the displacement separation).
"""
from __future__ import annotations

import math

import numpy as np

from interfaces.jit import njit

from .shape import B2CPDI, CPDI, SHAPE_CODES, snapped

LR_MAX_ITER = 15
LR_TOL = 1.0e-5
LR_PENALTY = 1.0e-7
#: fewest points of each class in a node's cloud before it takes the 4^D cells around it
LR_MIN_POINTS = 2
#: a cloud whose smallest principal spread (standard deviation) is below this many
#: cells is flat: it takes the 4^D cells around its node (two columns of particles at
#: 2 per cell: 0.25 cells; one column: 0)
LR_FLAT = 0.1
#: at most this many distinct nodes in one particle's support (2D B2-CPDI: 4 corners x 9)
SUPPORT_MAX = 64
#: at most this many particles in the 4^D-cell cloud of one node
WIDE_MAX = 4096


@njit(cache=True, refcount=False)
def _solve_small(M, r, x) -> bool:
    """Gaussian elimination with partial pivoting for a (D+1) x (D+1) system M x = r
    (``M`` and ``r`` are overwritten: callers assemble them afresh)."""
    n = r.shape[0]
    for c in range(n):
        piv = c
        for i in range(c + 1, n):
            if abs(M[i, c]) > abs(M[piv, c]):
                piv = i
        if M[piv, c] == 0.0:
            return False
        if piv != c:
            for j in range(n):
                tmp = M[c, j]
                M[c, j] = M[piv, j]
                M[piv, j] = tmp
            tmp = r[c]
            r[c] = r[piv]
            r[piv] = tmp
        for i in range(c + 1, n):
            f = M[i, c] / M[c, c]
            for j in range(c, n):
                M[i, j] -= f * M[c, j]
            r[i] -= f * r[c]
    for i in range(n - 1, -1, -1):
        s = r[i]
        for j in range(i + 1, n):
            s -= M[i, j] * x[j]
        x[i] = s / M[i, i]
    return True


@njit(cache=True)
def logistic_plane(xs, cls, n_pts, penalty, normal) -> int:
    """NLLS logistic regression (004 Eq 20-21, 53-56) on ``n_pts`` scaled points.

    ``xs[p, :D]`` are coordinates (already relative and scaled), ``cls[p]`` = -1/+1.
    Writes the unit normal (towards class +1) to ``normal``; returns the number of
    iterations, or -1 if the system is singular."""
    d = normal.shape[0]
    q = d + 1
    phi = np.zeros(q)
    A = np.empty((q, q))
    rhs = np.empty(q)
    step = np.empty(q)
    xp = np.empty(q)
    n_old = np.zeros(d)
    it = 0
    for it in range(1, LR_MAX_ITER + 1):
        for j in range(q):
            rhs[j] = -(penalty if j < d else 0.0) * phi[j]
            for k in range(q):
                A[j, k] = 0.0
            A[j, j] = penalty if j < d else 0.0
        for p in range(n_pts):
            for j in range(d):
                xp[j] = xs[p, j]
            xp[d] = 1.0
            z = 0.0
            for j in range(q):
                z += xp[j] * phi[j]
            if z < -500.0:
                z = -500.0
            e = math.exp(-z)
            f = 2.0 / (1.0 + e) - 1.0
            psi = 2.0 * e / ((1.0 + e) * (1.0 + e))            # Eq 53
            for j in range(q):
                rhs[j] += psi * (cls[p] - f) * xp[j]            # Eq 56
                for k in range(q):
                    A[j, k] += psi * psi * xp[j] * xp[k]        # Eq 54-55
        if not _solve_small(A, rhs, step):
            return -1
        for j in range(q):
            phi[j] += step[j]
        s = 0.0
        for j in range(d):
            s += phi[j] * phi[j]
        if not (s > 0.0):
            return -1
        s = 1.0 / math.sqrt(s)
        c = 0.0
        for j in range(d):
            normal[j] = phi[j] * s
            c += normal[j] * n_old[j]
        if it > 1 and 1.0 - c < LR_TOL:                          # Eq 57
            break
        for j in range(d):
            n_old[j] = normal[j]
    return it


@njit(cache=True, refcount=False)
def _particle_radius(n, r0, F, p, has_F) -> float:
    """R_p of 004 Eq 25: distance along n to the particle's inscribed deformed ellipse
    (n0 = F^-1 n by cofactors, 2D and 3D)."""
    d = n.shape[0]
    if not has_F:
        s = 0.0
        for j in range(d):
            s += n[j] * n[j] / (r0[p, j] * r0[p, j])
        return 1.0 / math.sqrt(s)
    f = F[p]
    if d == 2:
        det = f[0, 0] * f[1, 1] - f[0, 1] * f[1, 0]
        n00 = (f[1, 1] * n[0] - f[0, 1] * n[1]) / det
        n01 = (f[0, 0] * n[1] - f[1, 0] * n[0]) / det
        return 1.0 / math.sqrt(n00 * n00 / (r0[p, 0] * r0[p, 0]) + n01 * n01 / (r0[p, 1] * r0[p, 1]))
    s = 0.0
    det = (f[0, 0] * (f[1, 1] * f[2, 2] - f[1, 2] * f[2, 1])
           - f[0, 1] * (f[1, 0] * f[2, 2] - f[1, 2] * f[2, 0])
           + f[0, 2] * (f[1, 0] * f[2, 1] - f[1, 1] * f[2, 0]))
    for j in range(3):
        j1 = (j + 1) % 3
        j2 = (j + 2) % 3
        # row j of F^-1 = (column j1 x column j2 of F) / det
        c0 = f[1, j1] * f[2, j2] - f[2, j1] * f[1, j2]
        c1 = f[2, j1] * f[0, j2] - f[0, j1] * f[2, j2]
        c2 = f[0, j1] * f[1, j2] - f[1, j1] * f[0, j2]
        n0j = (c0 * n[0] + c1 * n[1] + c2 * n[2]) / det
        s += n0j * n0j / (r0[p, j] * r0[p, j])
    return 1.0 / math.sqrt(s)


@njit(cache=True, inline="always")
def _corner_base(p, c, x, r0, F, deform, b2, origin, cell, corner, base, on_line) -> None:
    """Corner ``c`` (bit k: + or - along domain vector k) of particle p's domain
    x +- F r0 (``deform``; else x +- r0) into ``corner``, and the first node of its
    stencil per axis into ``base``: the cell's lower node (linear), or the lower of the
    3 nearest nodes (``b2``).  ``on_line[k]``: the corner lies on node line base[k]
    (linear only).  A corner within ``SNAP`` cells of a node line (linear) or a cell
    midpoint (B2) is put on it, as the weights are (mpm.shape, "Ties")."""
    d = x.shape[1]
    for j in range(d):
        corner[j] = x[p, j]
        for k in range(d):
            sgn = 1.0 if (c >> k) & 1 else -1.0
            fjk = F[p, j, k] if deform else (1.0 if j == k else 0.0)
            corner[j] += sgn * fjk * r0[p, k]
    for k in range(d):
        t = (corner[k] - origin[k]) / cell[k]
        t = snapped(t, 0.5 if b2 else 0.0)      # as the weights (mpm/shape.py)
        base[k] = int(math.floor(t + 0.5)) - 1 if b2 else int(math.floor(t))
        on_line[k] = not b2 and t == base[k]


@njit(cache=True, refcount=False)
def _support_nodes(p, x, r0, F, deform, kind, origin, cell, nn, out, corner, base,
                   on_line) -> int:
    """The nodes where the CPDI (``kind`` CPDI) or B2-CPDI shape function of particle p
    is nonzero (written to ``out``; their count): the 2^D nodes of the cell holding each
    corner of its domain x +- F r0 (``deform``; else x +- r0), the 3^D nearest nodes of
    each corner for B2-CPDI. A corner on a node line counts the nodes on both sides of
    the line (the closed support of the hats: their weight there is 0, but a corner
    1e-16 cell to either side would reach one of them, so the cloud does not depend on
    the side round-off puts it). ``corner``, ``base``, ``on_line``: work arrays of
    length D."""
    d = x.shape[1]
    b2 = kind == B2CPDI
    total = 3 ** d
    cnt = 0
    for c in range(1 << d):
        _corner_base(p, c, x, r0, F, deform, b2, origin, cell, corner, base, on_line)
        for q in range(total):
            rem = q
            node = 0
            stride = 1
            for k in range(d):
                off = rem % 3 if b2 else rem % 3 - 1
                ik = base[k] + off
                rem //= 3
                if ik < 0 or ik >= nn[k] or (off < 0 and not on_line[k]):
                    node = -1
                    break
                node += ik * stride
                stride *= nn[k]
            if node < 0:
                continue
            seen = False
            for r in range(cnt):
                if out[r] == node:
                    seen = True
                    break
            if not seen and cnt < out.shape[0]:
                out[cnt] = node
                cnt += 1
    return cnt


@njit(cache=True)
def _reaching_bases(nodes, width, nn):
    """Flags over stencil bases (indexed like nodes): True where a stencil of ``width``
    nodes per axis starting there holds one of ``nodes``."""
    d = nn.shape[0]
    flag = np.zeros(np.prod(nn), dtype=np.bool_)
    idx = np.empty(d, dtype=np.int64)
    for j in range(nodes.shape[0]):
        rem = nodes[j]
        for k in range(d):
            idx[k] = rem % nn[k]
            rem //= nn[k]
        for q in range(width ** d):
            rem = q
            b = 0
            stride = 1
            for k in range(d):
                ik = idx[k] - rem % width
                rem //= width
                if ik < 0:
                    b = -1
                    break
                b += ik * stride
                stride *= nn[k]
            if b >= 0:
                flag[b] = True
    return flag


@njit(cache=True, refcount=False)
def _reaches(p, x, r0, F, deform, b2, origin, cell, nn, flag, corner, base, on_line) -> bool:
    """Whether some corner of particle p's domain has a stencil base flagged by
    :func:`_reaching_bases` (a cheap superset test before :func:`_support_nodes`)."""
    d = x.shape[1]
    for c in range(1 << d):
        _corner_base(p, c, x, r0, F, deform, b2, origin, cell, corner, base, on_line)
        b = 0
        stride = 1
        for k in range(d):
            bk = min(max(base[k] - (0 if b2 else 1), 0), nn[k] - 1)
            b += bk * stride
            stride *= nn[k]
        if flag[b]:
            return True
    return False


@njit(cache=True)
def _support_clouds(x, r0, F, deform, kind, origin, cell, nn, nodes, n_nodes):
    """Point clouds of ``nodes`` (004 Sec 3.1): the particles contributing to each, as
    CSR lists ``members[start[j]:start[j + 1]]`` for ``nodes[j]`` (particles in
    ascending order).  One pass over the particles; only those with a domain corner
    near one of ``nodes`` enumerate their support."""
    d = x.shape[1]
    b2 = kind == B2CPDI
    slot = np.full(n_nodes, -1, dtype=np.int64)
    for j in range(nodes.shape[0]):
        slot[nodes[j]] = j
    flag = _reaching_bases(nodes, 3, nn)
    buf = np.empty(SUPPORT_MAX, dtype=np.int64)
    corner = np.empty(d)
    base = np.empty(d, dtype=np.int64)
    on_line = np.zeros(d, dtype=np.bool_)
    hit_p = np.empty(max(16, 4 * nodes.shape[0]), dtype=np.int64)
    hit_j = np.empty_like(hit_p)
    n_hit = 0
    start = np.zeros(nodes.shape[0] + 1, dtype=np.int64)
    for p in range(x.shape[0]):
        if not _reaches(p, x, r0, F, deform, b2, origin, cell, nn, flag, corner, base, on_line):
            continue
        for r in range(_support_nodes(p, x, r0, F, deform, kind, origin, cell, nn, buf, corner,
                                      base, on_line)):
            j = slot[buf[r]]
            if j < 0:
                continue
            if n_hit == hit_p.shape[0]:
                hit_p = np.concatenate((hit_p, np.empty_like(hit_p)))
                hit_j = np.concatenate((hit_j, np.empty_like(hit_j)))
            hit_p[n_hit] = p
            hit_j[n_hit] = j
            n_hit += 1
            start[j + 1] += 1
    for j in range(nodes.shape[0]):
        start[j + 1] += start[j]
    fill = start[:-1].copy()
    members = np.empty(n_hit, dtype=np.int64)
    for h in range(n_hit):
        members[fill[hit_j[h]]] = hit_p[h]
        fill[hit_j[h]] += 1
    return start, members


@njit(cache=True)
def _bin_particles(x, origin, cell, nn):
    """Counting sort of particles by cell; returns (order, start[ncell + 1])."""
    P, d = x.shape
    ncell_axis = np.empty(d, dtype=np.int64)
    ncell = 1
    for k in range(d):
        ncell_axis[k] = nn[k] - 1
        ncell *= ncell_axis[k]
    cid = np.empty(P, dtype=np.int64)
    count = np.zeros(ncell + 1, dtype=np.int64)
    for p in range(P):
        c = 0
        stride = 1
        for k in range(d):
            ck = int(math.floor((x[p, k] - origin[k]) / cell[k]))
            ck = min(max(ck, 0), ncell_axis[k] - 1)
            c += ck * stride
            stride *= ncell_axis[k]
        cid[p] = c
        count[c + 1] += 1
    for c in range(ncell):
        count[c + 1] += count[c]
    start = count.copy()
    order = np.empty(P, dtype=np.int64)
    fill = count[:ncell].copy()
    for p in range(P):
        order[fill[cid[p]]] = p
        fill[cid[p]] += 1
    return order, start


@njit(cache=True)
def _gather_cloud(i, ring, x, field, order, start, origin, cell, nn, idx_out) -> int:
    """Particles in the (2 ring)^D cells around node i; returns their count."""
    d = x.shape[1]
    ijk = np.empty(d, dtype=np.int64)
    rem = i
    for k in range(d):
        ijk[k] = rem % nn[k]
        rem //= nn[k]
    ncell_axis = nn - 1
    side = 2 * ring
    total = 1
    for k in range(d):
        total *= side
    cnt = 0
    for c in range(total):
        rem = c
        cidx = 0
        stride = 1
        ok = True
        for k in range(d):
            off = rem % side - ring
            rem //= side
            ck = ijk[k] + off
            if ck < 0 or ck >= ncell_axis[k]:
                ok = False
                break
            cidx += ck * stride
            stride *= ncell_axis[k]
        if not ok:
            continue
        for s in range(start[cidx], start[cidx + 1]):
            if cnt < idx_out.shape[0]:
                idx_out[cnt] = order[s]
                cnt += 1
    return cnt


#: class +1 against material a: every other material present at the node (004 Eq 50),
#: the other deformable ones, or the rigid ones (codes for ``b`` < 0)
LUMP_ALL = -1
LUMP_DEFORMABLE = -2
LUMP_RIGID = -3


@njit(cache=True, inline="always")
def _in_class_b(f, a, b, rigid, mass, i, tol, mtot) -> bool:
    """Particle field ``f`` belongs to class +1 against material ``a``: the material ``b``,
    or (``b`` < 0) another material present at node i: any (``LUMP_ALL``, the lump of
    004 Eq 50), a deformable one (``LUMP_DEFORMABLE``) or a rigid one (``LUMP_RIGID``)."""
    if f == a:
        return False
    if b >= 0:
        return f == b
    if b == LUMP_DEFORMABLE and rigid[f] != 0 or b == LUMP_RIGID and rigid[f] == 0:
        return False
    return mass[i, f] > tol * mtot


@njit(cache=True, refcount=False)
def _class_counts(cloud, field, a, b, rigid, mass, i, tol, mtot):
    """Points of class -1 (material a) and +1 (b, or the lump of the others) in ``cloud``."""
    na = 0
    nb = 0
    for q in range(cloud.shape[0]):
        f = field[cloud[q]]
        if f == a:
            na += 1
        elif _in_class_b(f, a, b, rigid, mass, i, tol, mtot):
            nb += 1
    return na, nb


@njit(cache=True)
def _flat_cloud(cloud, x, field, a, b, rigid, mass, i, tol, mtot, dx) -> bool:
    """Does the two-class cloud lie (nearly) in a line (2D) or plane (3D)?  Its smallest
    principal spread below LR_FLAT cells: a plane fitted to it is ill-posed, its normal
    swinging with the points' small sideways offsets (a node beyond a body's free side
    sees one column of particles of each body there)."""
    d = x.shape[1]
    mean = np.zeros(d)
    cov = np.zeros((d, d))
    n = 0
    for q in range(cloud.shape[0]):
        p = cloud[q]
        if field[p] == a or _in_class_b(field[p], a, b, rigid, mass, i, tol, mtot):
            n += 1
            for k in range(d):
                mean[k] += x[p, k]
    for k in range(d):
        mean[k] /= n
    for q in range(cloud.shape[0]):
        p = cloud[q]
        if field[p] == a or _in_class_b(field[p], a, b, rigid, mass, i, tol, mtot):
            for j in range(d):
                for k in range(d):
                    cov[j, k] += (x[p, j] - mean[j]) * (x[p, k] - mean[k]) / (n * dx * dx)
    if d == 2:                      # smallest eigenvalue of the 2 x 2 covariance
        half = 0.5 * (cov[0, 0] - cov[1, 1])
        low = 0.5 * (cov[0, 0] + cov[1, 1]) - math.sqrt(half * half + cov[0, 1] * cov[0, 1])
    else:
        low = np.linalg.eigvalsh(cov)[0]
    return low < LR_FLAT * LR_FLAT


@njit(cache=True)
def _cloud_plane(i, a, b, xi, cloud, check_flat, wide, x, field, r0, F, has_F, rigid, mass, mtot,
                 tol, order, start, origin, cell, nn, idx, xs, cls, nvec) -> float:
    """LR plane at node i between material ``a`` (class -1) and ``b`` (class +1; ``b`` < 0:
    a lump of other present materials, :func:`_in_class_b`) from the node's point cloud ``cloud``
    (the particles of the 4^D cells around the node, gathered into ``wide``, where a
    class has fewer than LR_MIN_POINTS points there or, ``check_flat``, the cloud is
    flat): writes the unit normal a -> b to
    ``nvec`` and returns d_LR (Eq 24), or NaN when there is no two-class cloud or the
    regression is singular. Coordinates are taken relative to the node ``xi`` in cells."""
    d = x.shape[1]
    na, nb = _class_counts(cloud, field, a, b, rigid, mass, i, tol, mtot)
    if na < LR_MIN_POINTS or nb < LR_MIN_POINTS or (
            check_flat and _flat_cloud(cloud, x, field, a, b, rigid, mass, i, tol, mtot, cell[0])):
        cloud = wide[:_gather_cloud(i, 2, x, field, order, start, origin, cell, nn, wide)]
        na, nb = _class_counts(cloud, field, a, b, rigid, mass, i, tol, mtot)
    if na == 0 or nb == 0:
        return np.nan
    npts = 0
    for q in range(cloud.shape[0]):
        p = cloud[q]
        f = field[p]
        if f != a and not _in_class_b(f, a, b, rigid, mass, i, tol, mtot):
            continue          # material absent from this node or not of the pair
        for k in range(d):
            xs[npts, k] = (x[p, k] - xi[k]) / cell[0]
        cls[npts] = -1.0 if f == a else 1.0
        idx[npts] = p
        npts += 1
    if logistic_plane(xs, cls, npts, LR_PENALTY, nvec) < 0:
        return np.nan
    amax = -1.0e300
    bmin = 1.0e300
    for q in range(npts):
        p = idx[q]
        proj = 0.0
        for k in range(d):
            proj += x[p, k] * nvec[k]
        rp = _particle_radius(nvec, r0, F, p, has_F)
        if cls[q] < 0.0:
            amax = max(amax, proj + rp)
        else:
            bmin = min(bmin, proj - rp)
    return bmin - amax                                          # Eq 24


@njit(cache=True, inline="always")
def pair_index(a, b, m) -> int:
    """Slot of the material pair a < b among the m (m - 1) / 2 pairs."""
    return a * m - a * (a + 1) // 2 + (b - a - 1)


@njit(cache=True)
def lr_kernel(x, field, r0, F, has_F, kind, origin, cell, nn, mass, nodes, tol, rigid, normal,
              separation, pair_normal, pair_separation, rigid_separation) -> int:
    """LR normal and separation for every node in ``nodes`` and every present field
    (against the lump of the others); with ``pair_normal`` rows (option three_material =
    explicit), also for every pair a < b of the materials present at nodes seen by 3+
    materials (normal a -> b in ``pair_normal[i, pair_index(a, b, m)]``). ``kind`` is the
    run's shape function (mpm.shape codes): it sets each node's point cloud (module
    docstring); ``has_F``: ``F`` deforms the radii R_p of Eq 25 and the CPDI domains.

    Rigid fields (``rigid[f]`` != 0; ``rigid_separation`` rows present): at a node seen by
    two or more deformable fields and a rigid one, a deformable field's lump is the other
    deformable fields (the rigid body's particles would tilt the plane between two
    bodies meeting beside a wall towards the wall, and make them touch whenever one
    touches the wall), and its separation from the rigid fields (Eq 24 with the lump of
    the rigid fields as class +1) goes to ``rigid_separation[i, a]``; the contact with a
    rigid body takes its normal from the rigid body itself."""
    n_nodes, m = mass.shape
    d = x.shape[1]
    normal[:, :, :] = 0.0
    separation[:, :] = np.nan
    pairs = pair_normal.shape[0] > 0
    if pairs:
        pair_normal[:, :, :] = 0.0
        pair_separation[:, :] = np.nan
    support = kind == CPDI or kind == B2CPDI
    if support:
        sstart, members = _support_clouds(x, r0, F, has_F, kind, origin, cell, nn, nodes,
                                           n_nodes)
    else:
        sstart, members = np.zeros(nodes.shape[0] + 1, dtype=np.int64), np.empty(0, np.int64)
    order, start = _bin_particles(x, origin, cell, nn)
    near = np.empty(WIDE_MAX, dtype=np.int64)
    wide = np.empty(WIDE_MAX, dtype=np.int64)
    cap = WIDE_MAX
    for j in range(nodes.shape[0]):
        cap = max(cap, sstart[j + 1] - sstart[j])
    idx = np.empty(cap, dtype=np.int64)
    xs = np.empty((cap, d))
    cls = np.empty(cap)
    nvec = np.empty(d)
    present = np.empty(m, dtype=np.int64)
    xi = np.empty(d)
    with_rigid = rigid_separation.shape[0] > 0
    if with_rigid:
        rigid_separation[:, :] = np.nan
    solved = 0
    for ii in range(nodes.shape[0]):
        i = nodes[ii]
        mtot = 0.0
        for k in range(m):
            mtot += mass[i, k]
        npres = 0
        ndef = 0
        for k in range(m):
            if mass[i, k] > tol * mtot and mass[i, k] > 0.0:
                present[npres] = k
                npres += 1
                if rigid[k] == 0:
                    ndef += 1
        if npres < 2:
            continue
        split = with_rigid and 2 <= ndef < npres      # deformable fields meet beside a rigid one
        rem = i
        for k in range(d):
            xi[k] = origin[k] + (rem % nn[k]) * cell[k]
            rem //= nn[k]
        if support:
            cloud = members[sstart[ii]:sstart[ii + 1]]
        else:
            cloud = near[:_gather_cloud(i, 1, x, field, order, start, origin, cell, nn, near)]
        n_solve = 1 if npres == 2 else npres
        for jj in range(n_solve):
            a = present[jj]
            if split and rigid[a] != 0:
                continue                     # rigid fields take no contact correction
            lump = LUMP_DEFORMABLE if split else LUMP_ALL
            dlr = _cloud_plane(i, a, lump, xi, cloud, support, wide, x, field, r0, F, has_F,
                               rigid, mass, mtot, tol, order, start, origin, cell, nn, idx, xs,
                               cls, nvec)
            if not math.isnan(dlr):
                for k in range(d):
                    normal[i, a, k] = nvec[k]
                separation[i, a] = dlr
                if npres == 2:
                    b = present[1]
                    for k in range(d):
                        normal[i, b, k] = -nvec[k]
                    separation[i, b] = dlr
                solved += 1
            if split:
                rigid_separation[i, a] = _cloud_plane(
                    i, a, LUMP_RIGID, xi, cloud, support, wide, x, field, r0, F, has_F, rigid,
                    mass, mtot, tol, order, start, origin, cell, nn, idx, xs, cls, nvec)
            elif with_rigid:
                rigid_separation[i, a] = dlr
                if npres == 2:
                    rigid_separation[i, present[1]] = dlr
        if not pairs or npres < 3:
            continue
        for ja in range(npres):
            for jb in range(ja + 1, npres):
                a = present[ja]
                b = present[jb]
                dlr = _cloud_plane(i, a, b, xi, cloud, support, wide, x, field, r0, F, has_F,
                                   rigid, mass, mtot, tol, order, start, origin, cell, nn, idx,
                                   xs, cls, nvec)
                if math.isnan(dlr):
                    continue
                slot = pair_index(a, b, m)
                for k in range(d):
                    pair_normal[i, slot, k] = nvec[k]
                pair_separation[i, slot] = dlr
                solved += 1
    return solved


def lr_normals_separations(x: np.ndarray, field: np.ndarray, half_width: np.ndarray,
                           origin: np.ndarray, cell: np.ndarray, nn: np.ndarray,
                           mass: np.ndarray, nodes: np.ndarray | None = None,
                           F: np.ndarray | None = None, mass_tolerance: float = 0.0,
                           out: tuple | None = None, shape: str = "ugimp"
                           ) -> tuple[np.ndarray, np.ndarray]:
    """LR contact normals and separations for one step (004 Eq 19-25, 53-57).

    ``x[P, D]`` particle positions, ``field[P]`` body index, ``half_width`` the
    undeformed particle radii R_0 ((D,) or (P, D); half the particle spacing),
    ``F[P, D, D]`` optional deformation gradients for Eq 25, grid ``origin``/``cell``/
    ``nn`` as in mpm/LAYOUT.md, ``mass[N, M]`` nodal field masses, ``nodes`` the
    multimaterial nodes (default: all), ``shape`` the run's shape functions (they set
    each node's point cloud: module docstring).  Returns ``(normal[N, M, D],
    separation[N, M])`` to pass as ``lr=`` to :func:`mpm.multimaterial.correct_momentum` and
    :func:`mpm.multimaterial.add_interface_forces` (reuse ``out`` to avoid allocation).
    """
    x = np.ascontiguousarray(x, dtype=np.float64)
    P, d = x.shape
    n_nodes, m = mass.shape
    r0 = np.asarray(half_width, dtype=np.float64)
    if r0.ndim == 1:
        r0 = np.broadcast_to(r0, (P, d))
    r0 = np.ascontiguousarray(r0)
    if np.any(r0 <= 0.0):
        raise ValueError("lr_normals_separations: half_width must be > 0")
    if shape not in SHAPE_CODES:
        raise ValueError(f"lr_normals_separations: shape must be one of {sorted(SHAPE_CODES)}, "
                         f"got {shape!r}")
    has_F = F is not None
    F_arr = np.ascontiguousarray(F, dtype=np.float64) if has_F else np.zeros((1, d, d))
    if nodes is None:
        nodes = np.arange(n_nodes, dtype=np.int64)
    if out is None:
        out = (np.zeros((n_nodes, m, d)), np.zeros((n_nodes, m)))
    lr_kernel(x, np.ascontiguousarray(field, dtype=np.int64), r0, F_arr, has_F,
              SHAPE_CODES[shape], np.asarray(origin, dtype=np.float64),
              np.asarray(cell, dtype=np.float64), np.asarray(nn, dtype=np.int64), mass, np.ascontiguousarray(nodes, dtype=np.int64),
              float(mass_tolerance), np.zeros(m, dtype=np.int64), out[0], out[1],
              np.zeros((0, 0, d)), np.zeros((0, 0)), np.zeros((0, m)))
    return out
