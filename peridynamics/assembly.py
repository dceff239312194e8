"""Sparse assembly of the CPD residual and tangent with a fixed sparsity pattern.

The pattern is block structured (d x d blocks per node pair). A node pair (a, b) can
be coupled only if both lie in {p} + horizon(p) of a common central point p of one
material, i.e. |X_a - X_b| <= 2 delta for materials with multi-neighbour interactions and
<= delta for pair-only materials (003 Sec 3.2, Fig 3: the shared overlap DOFs receive
contributions of both materials, 003 Eq 19, 24). The (row, col) index arrays are built
once; every Newton iteration only refills the values.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from .kernels import assemble, horizon_radius2, within


@dataclass
class MaterialBlock:
    """Central points of one material with their horizons (same material only).

    ``centers`` node ids, ``nptr``/``nidx`` neighbour lists in CSR form, ``C`` (3,)
    the constants (C1, C2, C3) of 003 Eq 10.
    """

    name: str
    centers: np.ndarray
    nptr: np.ndarray
    nidx: np.ndarray
    C: np.ndarray

    @property
    def multi(self) -> bool:
        return bool(self.C[1] != 0.0 or self.C[2] != 0.0)


def neighbour_lists(X: np.ndarray, members: np.ndarray, delta: float):
    """Horizon of every member node within the members (cKDTree, 003 Algorithm 1).

    Returns (nptr, nidx) with nidx global node ids, sorted per central point, the
    central point itself excluded. A small relative tolerance keeps grid points lying
    exactly on the horizon radius inside it.
    """
    members = np.asarray(members, dtype=np.int64)
    pairs = cKDTree(X[members]).query_pairs(delta * (1.0 + 1e-9), output_type="ndarray").astype(np.int64)
    # exact membership by the same compiled test the kernels use for the other tuple edges
    pairs = pairs[within(X, members[pairs[:, 0]], members[pairs[:, 1]], horizon_radius2(delta))]
    a = np.concatenate([pairs[:, 0], pairs[:, 1]]).astype(np.int64)
    b = np.concatenate([pairs[:, 1], pairs[:, 0]]).astype(np.int64)
    order = np.lexsort((members[b], a))
    a, b = a[order], b[order]
    nptr = np.zeros(len(members) + 1, dtype=np.int64)
    np.cumsum(np.bincount(a, minlength=len(members)), out=nptr[1:])
    return nptr, members[b]


@dataclass
class Pattern:
    """Block CSR pattern over nodes and the matching dof-level CSR structure."""

    n_nodes: int
    d: int
    rowptr: np.ndarray      # node-level CSR row pointer (n_nodes + 1)
    cols: np.ndarray        # node-level column ids, sorted per row
    indptr: np.ndarray = field(init=False)
    indices: np.ndarray = field(init=False)

    def __post_init__(self):
        d = self.d
        nb = np.diff(self.rowptr)
        row_len = np.repeat(nb * d, d)                      # per dof row
        self.indptr = np.zeros(self.n_nodes * d + 1, dtype=np.int64)
        np.cumsum(row_len, out=self.indptr[1:])
        # dof row r = a*d + al holds, for every block column b of node row a, the
        # columns b*d .. b*d + d-1; entry t of row r is entry rowptr[a]*d + t of blk_cols
        blk_cols = np.repeat(self.cols, d) * d + np.tile(np.arange(d), len(self.cols))
        seg_start = np.repeat(self.rowptr[:-1] * d, d)
        idx = np.repeat(seg_start - self.indptr[:-1], row_len) + np.arange(self.indptr[-1])
        self.indices = blk_cols[idx].astype(np.int32)

    @property
    def nnz(self) -> int:
        return int(self.indptr[-1])

    def matrix(self, data: np.ndarray) -> sp.csr_matrix:
        n = self.n_nodes * self.d
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(n, n))


def build_pattern(X: np.ndarray, blocks: list[MaterialBlock], delta: float) -> Pattern:
    """Node pairs that can be coupled by some interaction, union over materials."""
    n, d = X.shape
    rows = [np.arange(n, dtype=np.int64)]
    cols = [np.arange(n, dtype=np.int64)]
    for blk in blocks:
        members = np.unique(np.concatenate([blk.centers, blk.nidx]))
        radius = (2.0 if blk.multi else 1.0) * delta * (1.0 + 1e-9)
        pairs = cKDTree(X[members]).query_pairs(radius, output_type="ndarray")
        a = members[pairs[:, 0]]
        b = members[pairs[:, 1]]
        rows += [a, b]
        cols += [b, a]
    r = np.concatenate(rows)
    c = np.concatenate(cols)
    key = np.unique(r * n + c)
    r = key // n
    c = key % n
    rowptr = np.zeros(n + 1, dtype=np.int64)
    np.add.at(rowptr, r + 1, 1)
    np.cumsum(rowptr, out=rowptr)
    return Pattern(n, d, rowptr, c.astype(np.int64))


@dataclass
class Evaluation:
    energy: float
    residual: np.ndarray            # (N, d) dW/dx
    point_energy: np.ndarray        # (N,) energy of the interactions of each central point
    tangent: sp.csr_matrix | None
    tuples: dict


class CPDSystem:
    """Total energy, residual and tangent of all materials on shared nodes.

    ``X`` (N, d) reference positions of the nodes (DOF carriers; coincident points of
    two materials in the overlap are one node), ``vol`` (N,) point volumes.
    """

    def __init__(self, X: np.ndarray, vol: np.ndarray, blocks: list[MaterialBlock], delta: float):
        self.X = np.ascontiguousarray(X, dtype=np.float64)
        self.vol = np.ascontiguousarray(vol, dtype=np.float64)
        self.blocks = blocks
        self.delta = float(delta)
        self.pattern = build_pattern(self.X, blocks, delta)
        self._cpar = [
            tuple(np.full(len(b.centers), b.C[k], dtype=np.float64) for k in range(3)) for b in blocks
        ]

    @property
    def n_nodes(self) -> int:
        return self.X.shape[0]

    @property
    def dim(self) -> int:
        return self.X.shape[1]

    def evaluate(self, u: np.ndarray, tangent: bool = True) -> Evaluation:
        """Energy W(u), residual dW/du and (optionally) tangent d2W/du2."""
        u = np.ascontiguousarray(u, dtype=np.float64).reshape(self.X.shape)
        f = np.zeros_like(self.X)
        data = np.zeros(self.pattern.nnz if tangent else 0)
        energy = 0.0
        e_node = np.zeros(self.n_nodes)
        counts = {"pairs": 0, "triples": 0, "quadruples": 0}
        for blk, (c1, c2, c3) in zip(self.blocks, self._cpar):
            e, n1, n2, n3 = assemble(self.X, u, blk.centers, blk.nptr, blk.nidx, c1, c2, c3,
                                     self.vol, tangent, self.pattern.rowptr, self.pattern.cols,
                                     data, f, e_node, horizon_radius2(self.delta))
            energy += e
            counts["pairs"] += n1
            counts["triples"] += n2
            counts["quadruples"] += n3
        K = self.pattern.matrix(data) if tangent else None
        return Evaluation(energy, f, e_node, K, counts)
