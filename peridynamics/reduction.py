"""K_ff: the tangent over the free independent DOFs, refilled from the fixed pattern.

The map from the full block-CSR pattern (node DOFs, :class:`~peridynamics.assembly.Pattern`)
to the reduced CSR (free independent DOFs, :class:`~peridynamics.assembly.DofMap`) is
built once per solve by a compiled two-pass count-and-fill, row by reduced row: its only
temporaries are the reduced pattern itself (int32 columns, int32 source positions while
the full pattern has fewer than 2^31 entries), not sort keys over the whole pattern (a
3D cuboid at 003's spacing holds 10^8 pattern entries).
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from interfaces.jit import njit


@njit(cache=True)
def _count(indptr, indices, index, pos, nf):
    """Kept entries per reduced row (full row and column both free after the DOF map)."""
    cnt = np.zeros(nf, np.int64)
    for i in range(indptr.shape[0] - 1):
        ri = pos[index[i]]
        if ri < 0:
            continue
        k = 0
        for e in range(indptr[i], indptr[i + 1]):
            if pos[index[indices[e]]] >= 0:
                k += 1
        cnt[ri] += k
    return cnt


@njit(cache=True)
def _fill(indptr, indices, index, pos, rptr, col, src):
    """Reduced columns ``col`` and full-pattern positions ``src`` of the kept entries, grouped
    by reduced row (``rptr``), full rows in increasing order within a reduced row."""
    cursor = rptr[:-1].copy()
    for i in range(indptr.shape[0] - 1):
        ri = pos[index[i]]
        if ri < 0:
            continue
        k = cursor[ri]
        for e in range(indptr[i], indptr[i + 1]):
            c = pos[index[indices[e]]]
            if c >= 0:
                col[k] = c
                src[k] = e
                k += 1
        cursor[ri] = k


@njit(cache=True)
def _sort_rows(rptr, col, src):
    """Sort each reduced row by column (stable: equal columns keep their source order);
    return the number of distinct columns per row. Rows already sorted are left as they are
    (the identity DOF map keeps the pattern's sorted rows)."""
    nf = rptr.shape[0] - 1
    distinct = np.zeros(nf, np.int64)
    for r in range(nf):
        a, b = rptr[r], rptr[r + 1]
        ordered = True
        for k in range(a + 1, b):
            if col[k] < col[k - 1]:
                ordered = False
                break
        if not ordered:
            perm = np.argsort(col[a:b], kind="mergesort")
            c = col[a:b][perm]
            s = src[a:b][perm]
            col[a:b] = c
            src[a:b] = s
        n = 0
        for k in range(a, b):
            if k == a or col[k] != col[k - 1]:
                n += 1
        distinct[r] = n
    return distinct


@njit(cache=True)
def _merge(rptr, col, indptr, indices, target):
    """Distinct columns of each row into ``indices`` (rows ``indptr``) and, for every kept entry,
    the position of its (row, column) in them (``target``: duplicates are summed there)."""
    for r in range(rptr.shape[0] - 1):
        j = indptr[r] - 1
        for k in range(rptr[r], rptr[r + 1]):
            if k == rptr[r] or col[k] != col[k - 1]:
                j += 1
                indices[j] = col[k]
            target[k] = j


class ReducedMatrix:
    """K_ff over the free independent DOFs, refilled from the fixed pattern's CSR data.

    The map is built once; each Newton iteration is one gather (or one scatter-add where the
    compliant overlap identifies DOFs, several full entries then share one reduced entry), so
    the reduced matrix keeps one sparsity pattern for the whole solve and the direct solver's
    symbolic analysis is reused.
    """

    def __init__(self, system, free: np.ndarray):
        pat = system.pattern
        nf = len(free)
        self.free = np.asarray(free, dtype=np.int64)
        pos = np.full(system.dofs.n, -1, dtype=np.int64)
        pos[free] = np.arange(nf)
        index = np.ascontiguousarray(system.dofs.index, dtype=np.int64)
        indptr = np.ascontiguousarray(pat.indptr, dtype=np.int64)
        cnt = _count(indptr, pat.indices, index, pos, nf)
        rptr = np.zeros(nf + 1, dtype=np.int64)
        np.cumsum(cnt, out=rptr[1:])
        del cnt
        col = np.empty(rptr[-1], dtype=np.int32)
        src = np.empty(rptr[-1], dtype=np.int32 if pat.nnz < 2 ** 31 else np.int64)
        _fill(indptr, pat.indices, index, pos, rptr, col, src)
        distinct = _sort_rows(rptr, col, src)
        self.shape = (nf, nf)
        self.injective = bool(distinct.sum() == rptr[-1])
        if self.injective:
            self.indptr, self.indices, self.gather = rptr, col, src
            return
        self.indptr = np.zeros(nf + 1, dtype=np.int64)
        np.cumsum(distinct, out=self.indptr[1:])
        self.indices = np.empty(self.indptr[-1], dtype=np.int32)
        self.target = np.empty(rptr[-1], dtype=np.int64)
        _merge(rptr, col, self.indptr, self.indices, self.target)
        self.source = src

    def __call__(self, data: np.ndarray, out: np.ndarray | None = None) -> sp.csr_matrix:
        """K_ff from the full pattern's ``data``; ``out`` (len(indices)) receives the values
        of an injective map instead of a new array (shared with the returned matrix)."""
        if self.injective:
            vals = np.take(data, self.gather, out=out) if out is not None else data[self.gather]
        else:
            vals = np.bincount(self.target, weights=data[self.source], minlength=len(self.indices))
        return sp.csr_matrix((vals, self.indices, self.indptr), shape=self.shape)
