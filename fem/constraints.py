"""Exact linear constraints by DOF elimination: u = T q + g.

Perfect interface directions (D = inf, 002 Eq 1 in the limit) are imposed exactly,
never with a large penalty number:

* full ties (Dn = Dt = inf): coincident DOFs are merged (u_b = u_a);
* one perfect direction m (unit normal or tangent of a straight interface):
  m . (u_A - u_B) = 0 at every interface node, one DOF of the pair is eliminated
  (u_s = -sum_{j != s} c_j u_j / c_s with the largest pivot |c_s|);
* prescribed displacements: u_d = g_d;
* everywhere else on an interface, jump unknowns in the interface frame replace the
  body-b displacements (u_b = u_a + n j_n + t j_t), so that a large finite D sits on its
  own unknown and stays well conditioned.

The reduced system is K_red = T^T K T, f_red = T^T (f - K g): symmetric positive
definite whenever the constrained structure has no rigid motion, and as well
conditioned as the unconstrained one. Everything is vectorized (no loop over nodes).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from interfaces.errors import CaseError, SolverError


@dataclass
class Elimination:
    """u = T q + g with ``T`` (ndof, nfree) csr, ``g`` (ndof,); ``free`` the DOFs kept as
    unknowns (one per free column)."""

    T: sp.csr_matrix
    g: np.ndarray
    free: np.ndarray

    def expand(self, q: np.ndarray) -> np.ndarray:
        return self.T @ q + self.g

    def reduce(self, K: sp.spmatrix, f: np.ndarray, jumps: sp.spmatrix | None = None,
               K_jump: sp.spmatrix | None = None) -> tuple[sp.csr_matrix, np.ndarray]:
        """T^T K T and T^T (f - K g), plus G^T K_J G, -G^T K_J h for an interface stiffness
        K_J acting on the nodal jumps J = jumps @ u = G q + h (exact cancellation)."""
        # transposes as csr: a csc left factor would make scipy convert the large K T to csc
        Tt = self.T.T.tocsr()
        Kr = Tt @ (sp.csr_matrix(K) @ self.T)
        fr = Tt @ (f - K @ self.g)
        if K_jump is not None and K_jump.shape[0]:
            G, h = self.jump_map(jumps)
            Gt = G.T.tocsr()
            Kr = Kr + Gt @ (K_jump @ G)
            fr = fr - Gt @ (K_jump @ h)
        return Kr.tocsr(), fr

    def jump_map(self, jumps: sp.spmatrix) -> tuple[sp.csr_matrix, np.ndarray]:
        """G, h with J = G q + h."""
        G = (jumps @ self.T).tocsr()
        G.eliminate_zeros()
        return G, jumps @ self.g


def _representatives(ndof: int, ties: np.ndarray) -> np.ndarray:
    """rep[d]: smallest DOF of the group of DOFs tied to d (connected components)."""
    if len(ties) == 0:
        return np.arange(ndof)
    ties = np.asarray(ties, dtype=np.int64)
    G = sp.coo_matrix((np.ones(len(ties)), (ties[:, 0], ties[:, 1])), shape=(ndof, ndof))
    _, label = connected_components(G, directed=False)
    rep_of_label = np.full(label.max() + 1, ndof, dtype=np.int64)
    np.minimum.at(rep_of_label, label, np.arange(ndof))
    return rep_of_label[label]


def _core(ndof: int, ties=(), directional_a=(), directional_b=(), directions=(),
          prescribed=(), values=(), scale: float = 1.0, special=None):
    """Rows of u = T q + g for ties, one-direction constraints and prescribed DOFs.

    DOFs flagged in ``special`` get no row and no column here (the caller writes them).

    ties: (k, 2) DOF pairs with equal displacement; directional_a/_b: (k, 2) [x, y] DOFs
    of the two nodes and directions (k, 2) unit vectors m with m . (u_a - u_b) = 0;
    prescribed/values: DOFs and their displacements (mm). ``scale`` is a displacement
    scale for consistency checks of redundant constraints.
    """
    rep = _representatives(ndof, np.reshape(np.asarray(ties, dtype=np.int64), (-1, 2)))
    tol = 1e-10 * max(scale, 1e-300)

    # prescribed displacements, mapped to representatives
    pd = np.asarray(prescribed, dtype=np.int64)
    pv = np.asarray(values, dtype=float)
    presc = np.full(ndof, np.nan)
    if len(pd):
        r = rep[pd]
        order = np.argsort(r, kind="stable")
        r, v = r[order], pv[order]
        first = np.concatenate([[True], r[1:] != r[:-1]])
        grp = np.cumsum(first) - 1
        vmin = np.full(first.sum(), np.inf)
        vmax = np.full(first.sum(), -np.inf)
        np.minimum.at(vmin, grp, v)
        np.maximum.at(vmax, grp, v)
        bad = vmax - vmin > tol + 1e-12 * np.abs(vmax)
        if np.any(bad):
            d = r[first][bad][0]
            raise CaseError(f"boundary_conditions: conflicting prescribed displacements "
                            f"{vmin[bad][0]:g} and {vmax[bad][0]:g} on one DOF (DOF {d}, possibly through "
                            f"a perfect interface tie)")
        presc[r[first]] = v[first]
    is_presc = ~np.isnan(presc)

    # one-direction constraints m . (u_a - u_b) = 0 on representatives
    A = np.reshape(np.asarray(directional_a, dtype=np.int64), (-1, 2))
    B = np.reshape(np.asarray(directional_b, dtype=np.int64), (-1, 2))
    M = np.reshape(np.asarray(directions, dtype=float), (-1, 2))
    dofs = rep[np.concatenate([A, B], axis=1)]                       # (k, 4)
    coef = np.concatenate([M, -M], axis=1)
    same = np.all(dofs[:, :2] == dofs[:, 2:], axis=1)                 # already tied: m.(0) = 0
    if np.any((dofs[:, :2, None] == dofs[:, None, 2:]).any(axis=(1, 2)) & ~same):
        raise CaseError("interfaces: a node pair with one perfect direction is partly tied by another "
                        "perfect interface; this junction is not supported by fem")
    dofs, coef = dofs[~same], coef[~same]
    k = len(dofs)
    slave = np.empty(k, dtype=np.int64)
    keep = np.ones(k, dtype=bool)
    if k:
        free_entry = ~is_presc[dofs] & (np.abs(coef) > 1e-8)
        score = np.where(free_entry, np.abs(coef) * np.array([1.0, 1.0, 2.0, 2.0]), -1.0)
        s = np.argmax(score, axis=1)
        none = score[np.arange(k), s] < 0
        if np.any(none):  # every DOF prescribed: the constraint must already hold
            resid = np.einsum("kj,kj->k", coef[none], np.nan_to_num(presc[dofs[none]]))
            if np.any(np.abs(resid) > tol):
                raise CaseError("boundary_conditions: prescribed displacements open a perfect interface "
                                f"direction (jump {np.abs(resid).max():g} mm where D = inf)")
            keep[none] = False
        slave = dofs[np.arange(k), s]
        dofs, coef, s, slave = dofs[keep], coef[keep], s[keep], slave[keep]
        k = len(dofs)
        if len(np.unique(slave)) != k:
            raise CaseError("interfaces: a node lies on two interfaces with one perfect direction "
                            "(or is constrained twice); this junction is not supported by fem")
        master = np.abs(coef) > 0
        master[np.arange(k), s] = False
        if np.isin(dofs[master], slave).any():
            raise CaseError("interfaces: chained one-direction perfect constraints (a node is master of "
                            "one and slave of another); not supported by fem")
    is_slave = np.zeros(ndof, dtype=bool)
    is_slave[slave] = True

    # free unknowns: representatives neither prescribed nor eliminated
    special = np.zeros(ndof, bool) if special is None else special
    free = np.flatnonzero((rep == np.arange(ndof)) & ~is_presc & ~is_slave & ~special)
    col = np.full(ndof, -1, dtype=np.int64)
    col[free] = np.arange(len(free))

    rows, cols, vals = [], [], []
    g = np.zeros(ndof)
    r = rep
    m_free = (col[r] >= 0) & ~special
    rows.append(np.flatnonzero(m_free))
    cols.append(col[r[m_free]])
    vals.append(np.ones(m_free.sum()))
    m_p = is_presc[r]
    g[m_p] = presc[r[m_p]]
    if k:
        # u_slave = sum_j w_j u_j + w0, written for every DOF whose representative is a slave
        cs = coef[np.arange(k), s]
        w = -coef / cs[:, None]
        w[np.arange(k), s] = 0.0
        slave_row = np.full(ndof, -1, dtype=np.int64)
        slave_row[slave] = np.arange(k)
        d_all = np.flatnonzero(is_slave[r])
        c_of = slave_row[r[d_all]]
        for j in range(4):          # the four DOFs of a constraint (fixed count, not a node loop)
            dj = dofs[c_of, j]
            wj = w[c_of, j]
            fr = (col[dj] >= 0) & (wj != 0)
            rows.append(d_all[fr])
            cols.append(col[dj[fr]])
            vals.append(wj[fr])
            pr = is_presc[dj] & (wj != 0)
            np.add.at(g, d_all[pr], wj[pr] * presc[dj[pr]])
    return rows, cols, vals, g, free, col, is_presc


def build_elimination(ndof: int, pairs=None, prescribed=(), values=(), scale: float = 1.0) -> Elimination:
    """u = T q + g for interface node ``pairs`` (``fem.interface_mesh.NodePairs``) and
    prescribed DOFs/values (mm).

    Interface node pairs away from supports and junctions (the usual case) get jump
    unknowns in the interface frame: u_b = u_a + n j_n + t j_t, where a perfect direction
    simply has no unknown (exact tie, 002 Eq 1 with D = inf). A large finite D then
    multiplies only its own jump unknown, so D = 1e12 is as well conditioned as D = inf
    and converges to it as 1/D. Pairs touching prescribed DOFs or other pairs fall back to
    general elimination (ties, one-direction constraints with the largest pivot).
    """
    from_pairs = pairs is not None and len(pairs.a) > 0
    pd = np.asarray(prescribed, dtype=np.int64)
    special = np.zeros(ndof, bool)
    ties = np.zeros((0, 2), dtype=np.int64)
    da = db = np.zeros((0, 2), dtype=np.int64)
    dirs = np.zeros((0, 2))
    jump = np.zeros(0, dtype=bool)
    if from_pairs:
        node_presc = np.zeros(ndof, bool)
        node_presc[pd - pd % 2] = True
        count = np.bincount(np.concatenate([pairs.a, pairs.b]), minlength=ndof)
        jump = (pairs.straight & ~node_presc[pairs.a] & ~node_presc[pairs.b]
                & (count[pairs.a] == 1) & (count[pairs.b] == 1))
        special[pairs.b[jump]] = True
        special[pairs.b[jump] + 1] = True
        rest = ~jump
        both = rest & pairs.perfect_n & pairs.perfect_t
        ties = np.concatenate([np.stack([pairs.a[both] + c, pairs.b[both] + c], axis=1) for c in (0, 1)])
        one_n = rest & pairs.perfect_n & ~pairs.perfect_t
        one_t = rest & pairs.perfect_t & ~pairs.perfect_n
        sel = one_n | one_t
        da = np.stack([pairs.a[sel], pairs.a[sel] + 1], axis=1)
        db = np.stack([pairs.b[sel], pairs.b[sel] + 1], axis=1)
        dirs = np.where(one_n[sel, None], pairs.n[sel], pairs.t[sel])
    rows, cols, vals, g, free, col, is_presc = _core(ndof, ties, da, db, dirs, pd, values, scale, special)
    labels = [free]
    if from_pairs and jump.any():
        a, b = pairs.a[jump], pairs.b[jump]
        ncol = len(free)
        if np.any(col[a] < 0) or np.any(col[a + 1] < 0):   # guaranteed by the selection above
            raise SolverError("internal: a jump pair's body-a node is not a free unknown")
        jn = ~pairs.perfect_n[jump]
        jt = ~pairs.perfect_t[jump]
        col_n = np.full(len(a), -1)
        col_t = np.full(len(a), -1)
        col_n[jn] = ncol + np.arange(jn.sum())
        col_t[jt] = ncol + jn.sum() + np.arange(jt.sum())
        labels += [b[jn], b[jt] + 1]
        for c in (0, 1):                       # u_b[c] = u_a[c] + n[c] j_n + t[c] j_t
            rows += [b + c, b[jn] + c, b[jt] + c]
            cols += [col[a + c], col_n[jn], col_t[jt]]
            vals += [np.ones(len(a)), pairs.n[jump][jn, c], pairs.t[jump][jt, c]]
    free = np.concatenate(labels)
    T = sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(ndof, len(free))).tocsr()
    return Elimination(T=T, g=g, free=free)


__all__ = ["Elimination", "build_elimination"]
