"""Sparse assembly of the CPD residual and tangent with a fixed sparsity pattern.

The pattern is block structured (d x d blocks per node pair). A node pair (a, b) can
be coupled only if both lie in {p} + horizon(p) of a common central point p of one
material, i.e. |X_a - X_b| <= 2 delta for materials with multi-neighbour interactions and
<= delta for pair-only materials (003 Sec 3.2, Fig 3: the shared overlap DOFs receive
contributions of both materials, 003 Eq 19, 24). Of these candidates only the pairs that
a non-degenerate tuple couples are kept (on a grid, pairs at 2 delta and those whose
common central points are all on their line carry exact zeros: 17 % of the candidates at
delta = 3.01 h). The (row, col) index arrays are built once; every Newton iteration only
refills the values.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from .budget import SLOT_BUDGET
from .reduction import ReducedMatrix
from .kernels import assemble_blocks, block_slots, coupled_blocks, dof_columns, full_layout, horizon_radius2, within


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


def colour_blocks(X: np.ndarray, blk: MaterialBlock, delta: float) -> tuple[MaterialBlock, np.ndarray, np.ndarray]:
    """Central points regrouped into spatial blocks coloured for race-free parallel assembly.

    Cells of side s > 2 delta; colour = parity of the cell indices (4 colours in 2D, 8 in
    3D). Two blocks of one colour are a full cell apart (> 2 delta), so the node sets
    {p} + horizon(p) of their central points never meet. Returns the block with its
    central points sorted by (colour, cell), and the colour and block pointers.
    """
    P = X[blk.centers]
    d = X.shape[1]
    s = 2.0 * delta * (1.0 + 1e-6)
    idx = np.floor((P - P.min(axis=0)) / s).astype(np.int64) if len(P) else np.zeros((0, d), np.int64)
    ncell = idx.max(axis=0) + 1 if len(P) else np.ones(d, np.int64)
    colour = np.zeros(len(P), np.int64)
    cell = np.zeros(len(P), np.int64)
    for k in range(d):
        colour += (idx[:, k] % 2) << k
        cell = cell * ncell[k] + idx[:, k]
    perm = np.lexsort((blk.centers, cell, colour))
    counts = np.diff(blk.nptr)[perm]
    nptr = np.zeros(len(perm) + 1, dtype=np.int64)
    np.cumsum(counts, out=nptr[1:])
    take = np.repeat(blk.nptr[perm] - nptr[:-1], counts) + np.arange(nptr[-1])
    sorted_blk = MaterialBlock(blk.name, blk.centers[perm], nptr, blk.nidx[take], blk.C)
    key = colour[perm] * (int(np.prod(ncell)) + 1) + cell[perm]
    starts = np.flatnonzero(np.r_[True, key[1:] != key[:-1]]) if len(key) else np.zeros(0, np.int64)
    block_ptr = np.r_[starts, len(key)].astype(np.int64)
    col_of_block = colour[perm][starts] if len(key) else np.zeros(0, np.int64)
    color_ptr = np.searchsorted(col_of_block, np.arange(2 ** d + 1)).astype(np.int64)
    return sorted_blk, color_ptr, block_ptr


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
        self.indices = dof_columns(self.rowptr, self.cols, d, self.indptr)

    @property
    def nnz(self) -> int:
        return int(self.indptr[-1])

    def matrix(self, data: np.ndarray) -> sp.csr_matrix:
        n = self.n_nodes * self.d
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(n, n))


def build_pattern(X: np.ndarray, blocks: list[MaterialBlock], delta: float,
                  extra: tuple[np.ndarray, np.ndarray] | None = None, prune: bool = True) -> Pattern:
    """Node pairs that some interaction couples, union over materials, plus the ``extra``
    node pairs (spring ties of the compliant overlap): the candidates within 2 delta (delta
    for pair-only materials), reduced by :func:`prune_pattern` unless ``prune`` is False."""
    n, d = X.shape
    rows = [np.arange(n, dtype=np.int64)]
    cols = [np.arange(n, dtype=np.int64)]
    if extra is not None:
        rows += [extra[0], extra[1]]
        cols += [extra[1], extra[0]]
    for blk in blocks:
        members = _members(n, blk)
        radius = (2.0 if blk.multi else 1.0) * delta * (1.0 + 1e-9)
        pairs = cKDTree(X[members]).query_pairs(radius, output_type="ndarray")
        a = members[pairs[:, 0]]
        b = members[pairs[:, 1]]
        rows += [a, b]
        cols += [b, a]
    r = np.concatenate(rows)
    c = np.concatenate(cols)
    key = np.sort(r * n + c)                    # sort + mask: numpy's hashing unique is 10x slower here
    key = key[np.r_[True, key[1:] != key[:-1]]]
    r = key // n
    c = key % n
    rowptr = np.zeros(n + 1, dtype=np.int64)
    np.add.at(rowptr, r + 1, 1)
    np.cumsum(rowptr, out=rowptr)
    if not prune:
        return Pattern(n, d, rowptr, c.astype(np.int64))
    return prune_pattern(X, rowptr, c.astype(np.int64), blocks, extra, d)


def _members(n: int, blk: MaterialBlock) -> np.ndarray:
    """Sorted node ids of the central points of ``blk`` and their neighbours."""
    mask = np.zeros(n, dtype=np.bool_)
    mask[blk.centers] = True
    mask[blk.nidx] = True
    return np.flatnonzero(mask)


def prune_pattern(X: np.ndarray, rowptr: np.ndarray, cols: np.ndarray, blocks: list[MaterialBlock],
                  extra: tuple[np.ndarray, np.ndarray] | None, d: int) -> Pattern:
    """The candidate node pairs (within 2 delta, rows sorted) reduced to those some tuple
    couples (:func:`kernels.coupled_blocks`), the diagonal and the ``extra`` pairs: the dropped
    entries are structural zeros that would cost every scatter, product and factorisation."""
    n = len(rowptr) - 1
    rows = np.repeat(np.arange(n, dtype=np.int64), np.diff(rowptr))
    flat = rows * n + cols                       # sorted: rows ascending, columns sorted per row
    keep = np.zeros(len(cols), dtype=np.bool_)
    keep[np.searchsorted(flat, np.arange(n, dtype=np.int64) * (n + 1))] = True
    if extra is not None:
        a, b = np.asarray(extra[0], np.int64), np.asarray(extra[1], np.int64)
        keep[np.searchsorted(flat, np.concatenate([a * n + b, b * n + a]))] = True
    for blk in blocks:
        coupled_blocks(X, blk.centers, blk.nptr, blk.nidx, blk.multi, rowptr, cols, keep)
    new_ptr = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(rows[keep], minlength=n), out=new_ptr[1:])
    return Pattern(n, d, new_ptr, np.ascontiguousarray(cols[keep]))


@dataclass
class Evaluation:
    """``energy`` = bulk + spring energy (what Newton minimises), ``point_energy`` the bulk
    energy per node, ``spring_energy`` (m,) per spring of the compliant overlap."""

    energy: float
    residual: np.ndarray            # (N, d) dW/dx
    point_energy: np.ndarray        # (N,) energy of the interactions of each central point
    tangent: sp.csr_matrix | None   # in the layout of the target it was assembled into
    tuples: dict
    spring_energy: np.ndarray = field(default_factory=lambda: np.zeros(0))
    #: the pair part of the tangent when it was asked for (``CPDSystem.evaluate(pairs=...)``)
    pair_tangent: sp.csr_matrix | None = None


class DofMap:
    """Independent DOFs of the nodes: full DOF k (node * d + component) is independent
    DOF ``index[k]``; ``ties`` (t, 2) identify full DOF t[0] with t[1] (perfect directions
    of the compliant overlap). Without ties it is the identity."""

    def __init__(self, n_full: int, ties: np.ndarray | None = None):
        idx = np.arange(n_full, dtype=np.int64)
        if ties is not None and len(ties):
            idx[ties[:, 0]] = ties[:, 1]
            idx = idx[idx]                      # ties point at originals, which are not tied
        uniq, self.index = np.unique(idx, return_inverse=True)
        self.n = len(uniq)
        self.identity = self.n == n_full

    def expand(self, u: np.ndarray) -> np.ndarray:
        return u if self.identity else u[self.index]

    def reduce(self, f: np.ndarray) -> np.ndarray:
        return f if self.identity else np.bincount(self.index, weights=f, minlength=self.n)


class SpringBlock:
    """The compliant-overlap springs: energy, residual and constant tangent data
    (the tangent entries are scattered into the fixed pattern once, at construction)."""

    def __init__(self, springs, pattern: Pattern):
        self.springs = springs
        d = pattern.d
        a, b, S = springs.node_a, springs.node_b, springs.S
        data = np.zeros(pattern.nnz)
        for r, c, sgn in ((a, a, 1.0), (b, b, 1.0), (a, b, -1.0), (b, a, -1.0)):
            for al in range(d):
                for be in range(d):
                    np.add.at(data, dof_position(pattern, r, c, al, be), sgn * S[:, al, be])
        self.data = data

    def add(self, u: np.ndarray, f: np.ndarray) -> np.ndarray:
        """Add the spring forces to f (N, d); return the energy per spring."""
        sp_ = self.springs
        g = u[sp_.node_b] - u[sp_.node_a]
        t = np.einsum("mab,mb->ma", sp_.S, g)
        np.add.at(f, sp_.node_b, t)
        np.subtract.at(f, sp_.node_a, t)
        return 0.5 * np.einsum("ma,ma->m", g, t)


def dof_position(pattern: Pattern, r: np.ndarray, c: np.ndarray, al: int, be: int) -> np.ndarray:
    """Index in the CSR data of entry (r*d + al, c*d + be) for node pairs in the pattern."""
    d = pattern.d
    pos = np.empty(len(r), dtype=np.int64)
    for k, (a, b) in enumerate(zip(r, c)):
        lo, hi = pattern.rowptr[a], pattern.rowptr[a + 1]
        kk = lo + np.searchsorted(pattern.cols[lo:hi], b)
        if kk >= hi or pattern.cols[kk] != b:
            raise ValueError("spring tie outside the sparsity pattern")
        nb = hi - lo
        pos[k] = d * d * lo + al * d * nb + (kk - lo) * d + be
    return pos


def tangent_slots(blocks: list[MaterialBlock], pattern: Pattern, boff: np.ndarray,
                  budget: int = SLOT_BUDGET, multi: bool | None = None) -> list:
    """Per material block the (slots, sptr) of :func:`kernels.block_slots` with the block
    offsets ``boff`` of a target layout, or empty arrays for every block when all of them
    together would take more than ``budget`` bytes. ``multi`` None: each block's own."""
    need = sum(4 * int(np.sum((np.diff(b.nptr) + 1) ** 2)) for b in blocks)
    if need > budget:
        return [(np.zeros(0, np.int32), np.zeros(1, np.int64)) for _ in blocks]
    return [block_slots(b.centers, b.nptr, b.nidx, pattern.rowptr, pattern.cols, boff,
                        b.multi if multi is None else multi) for b in blocks]


@dataclass
class ScatterTarget:
    """Where the kernels add the tangent (:func:`kernels._scatter`): a CSR matrix (``indptr``,
    ``indices``, ``shape``) whose DOF row (a, al) starts at ``rows[a, al]`` of its data and
    holds the column DOF (b, be) at ``coff[b, be]`` within node b's block, the blocks at the
    offsets ``slots`` (per material block, :func:`tangent_slots`; or found by binary search in
    ``pattern``: full layout only); ``constant`` (or None) is added after the kernels (the
    compliant-overlap springs). The full block pattern and the tangent reduced to the free
    DOFs (:func:`reduced_target`) are both targets."""

    pattern: Pattern
    indptr: np.ndarray
    indices: np.ndarray
    shape: tuple
    rows: np.ndarray
    coff: np.ndarray
    slots: list
    constant: np.ndarray | None = None

    @property
    def nnz(self) -> int:
        return int(self.indptr[-1])

    def matrix(self, data: np.ndarray) -> sp.csr_matrix:
        return sp.csr_matrix((data, self.indices, self.indptr), shape=self.shape)

    def kernel_args(self, data: np.ndarray, k: int) -> tuple:
        """The tuple :func:`kernels._scatter` takes, for material block ``k``."""
        slots, sptr = self.slots[k]
        return data, self.rows, self.coff, slots, sptr, self.pattern.rowptr, self.pattern.cols

    def buffer(self, out: np.ndarray | None) -> np.ndarray:
        """``out`` checked and zeroed (a Newton loop refills one buffer: no page faults of a fresh
        10^7-entry array), or a new zero array."""
        if out is None:
            return np.zeros(self.nnz)
        if out.shape != (self.nnz,) or out.dtype != np.float64:
            raise ValueError(f"out must be a float64 array of {self.nnz} entries")
        out.fill(0.0)
        return out


def full_target(blocks: list[MaterialBlock], pattern: Pattern, constant: np.ndarray | None = None,
                budget: int = SLOT_BUDGET) -> ScatterTarget:
    """The full block-CSR pattern as a scatter target (block offset d (kk - rowptr[a]))."""
    d = pattern.d
    rows, coff = full_layout(pattern.rowptr, d)
    boff = d * (np.arange(len(pattern.cols), dtype=np.int64) - np.repeat(pattern.rowptr[:-1], np.diff(pattern.rowptr)))
    n = pattern.n_nodes * d
    return ScatterTarget(pattern, pattern.indptr, pattern.indices, (n, n), rows, coff,
                         tangent_slots(blocks, pattern, boff, budget), constant)


def reduced_target(system: "CPDSystem", red: ReducedMatrix) -> ScatterTarget | None:
    """The tangent over the free DOFs (the :class:`~peridynamics.reduction.ReducedMatrix`
    ``red``) as a scatter target: the kernels add into K_ff directly, without the full tangent
    and its gather (None where that does not apply: DOFs identified by the compliant overlap,
    or no block slots within the memory budget).

    With the identity DOF map and free DOFs in increasing order, reduced row (a, al) holds, for
    every node b of pattern row a in order, the free components of b: both rows of a node
    share their columns, and block (a, b) starts after the free components of the nodes
    before b in the row."""
    pat = system.pattern
    full = system.target
    if not (system.dofs.identity and red.injective and np.all(np.diff(red.free) > 0)
            and all(len(s) for s, _ in full.slots)):
        return None
    d, n = pat.d, pat.n_nodes
    pos = np.full(n * d, -1, dtype=np.int64)
    pos[red.free] = np.arange(len(red.free))
    is_free = (pos >= 0).reshape(n, d)
    coff = np.where(is_free, np.cumsum(is_free, axis=1) - 1, -1).astype(np.int64)
    starts = np.where(is_free, red.indptr[np.maximum(pos, 0)].reshape(n, d), -1).astype(np.int64)
    cum = np.zeros(len(pat.cols) + 1, dtype=np.int64)    # free columns before each pattern block
    np.cumsum(is_free.sum(axis=1)[pat.cols], out=cum[1:])
    boff = cum[:-1] - np.repeat(cum[pat.rowptr[:-1]], np.diff(pat.rowptr))     # ... within its row
    row_len = cum[pat.rowptr[1:]] - cum[pat.rowptr[:-1]]
    if not np.array_equal(np.diff(red.indptr), np.repeat(row_len, d)[red.free]):
        raise ValueError("reduced tangent pattern does not follow the block pattern")
    constant = None if full.constant is None else red(full.constant).data.copy()
    slots = [block_slots(b.centers, b.nptr, b.nidx, pat.rowptr, pat.cols, boff, b.multi) for b in system.blocks]
    return ScatterTarget(pat, red.indptr, red.indices, red.shape, starts, coff, slots, constant)


class CPDSystem:
    """Total energy, residual and tangent of all materials on shared nodes.

    ``X`` (N, d) reference positions of the nodes (DOF carriers; coincident points of
    two materials in the overlap are one node), ``vol`` (N,) point volumes.
    """

    def __init__(self, X: np.ndarray, vol: np.ndarray, blocks: list[MaterialBlock], delta: float,
                 springs=None, ties: np.ndarray | None = None):
        self.X = np.ascontiguousarray(X, dtype=np.float64)
        self.vol = np.ascontiguousarray(vol, dtype=np.float64)
        self.delta = float(delta)
        coloured = [colour_blocks(self.X, b, self.delta) for b in blocks]
        self.blocks = [c[0] for c in coloured]
        self._colours = [(c[1], c[2]) for c in coloured]
        blocks = self.blocks
        has_springs = springs is not None and springs.count > 0
        extra = (springs.node_a, springs.node_b) if has_springs else None
        self.pattern = build_pattern(self.X, blocks, delta, extra)
        self.springs = SpringBlock(springs, self.pattern) if has_springs else None
        self.target = full_target(blocks, self.pattern, self.springs.data if has_springs else None)
        self.dofs = DofMap(self.X.size, ties)
        self._cpar = [
            tuple(np.full(len(b.centers), b.C[k], dtype=np.float64) for k in range(3)) for b in blocks
        ]

    @property
    def n_nodes(self) -> int:
        return self.X.shape[0]

    @property
    def dim(self) -> int:
        return self.X.shape[1]

    def evaluate(self, u: np.ndarray, tangent: bool = True, out: np.ndarray | None = None,
                 target: ScatterTarget | None = None,
                 pairs: tuple[ScatterTarget, np.ndarray] | None = None) -> Evaluation:
        """Energy W(u), residual dW/du and (optionally) tangent d2W/du2.

        The tangent goes into ``target`` (default: the full block pattern, ``self.target``; a
        :func:`reduced_target` gives K_ff directly). ``out`` (target.nnz float64) receives its
        values instead of a new array (a Newton loop refilling one buffer spares the page
        faults of a fresh 10^7-entry array); the returned tangent then shares it and is
        overwritten by the next call. ``pairs`` = (target, buffer): the tangent of the
        one-neighbour interactions alone (the pair part preconditioning the Newton steps,
        :mod:`peridynamics.preconditioner`; its target built for the materials with constants
        (C1, 0, 0)) is evaluated in the same pass into the buffer (``pair_tangent``).
        """
        u = np.ascontiguousarray(u, dtype=np.float64).reshape(self.X.shape)
        f = np.zeros_like(self.X)
        target = self.target if target is None else target
        data = target.buffer(out) if tangent else np.zeros(0)
        pdata = pairs[0].buffer(pairs[1]) if tangent and pairs is not None else np.zeros(0)
        energy = 0.0
        e_node = np.zeros(self.n_nodes)
        counts = {"pairs": 0, "triples": 0, "quadruples": 0}
        for k, (blk, (c1, c2, c3), (cptr, bptr)) in enumerate(zip(self.blocks, self._cpar, self._colours)):
            into = target.kernel_args(data, k)
            into_pairs = pairs[0].kernel_args(pdata, k) if len(pdata) else (pdata,) + into[1:]
            e, n1, n2, n3 = assemble_blocks(self.X, u, blk.centers, blk.nptr, blk.nidx, c1, c2, c3, self.vol,
                                            tangent, f, e_node, horizon_radius2(self.delta), cptr, bptr,
                                            into, into_pairs)
            energy += e
            counts["pairs"] += n1
            counts["triples"] += n2
            counts["quadruples"] += n3
        e_spring = np.zeros(0)
        if self.springs is not None:
            e_spring = self.springs.add(u, f)
            energy += float(e_spring.sum())
        K = P = None
        if tangent:
            K = target.matrix(_plus(data, target.constant))
            if len(pdata):
                P = pairs[0].matrix(_plus(pdata, pairs[0].constant))
        return Evaluation(energy, f, e_node, K, counts, e_spring, P)


def _plus(data: np.ndarray, constant: np.ndarray | None) -> np.ndarray:
    """data += constant (in place) where there is one."""
    if constant is not None:
        data += constant
    return data
