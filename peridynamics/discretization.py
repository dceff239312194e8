"""Point grids, boundary layers and the overlap interface of 003 Sec 3-4.1.

* One common uniform grid (spacing h, centred in the bounding box of all bodies; by
  default vertex-centred, 101 x 101 points on the unit square at h = 0.01, or
  cell-centred, 100 x 100) carries every point; a point is a node (DOF carrier). Point volume V = h^2 (2D, per unit thickness) or h^3.
* Each body owns the grid points inside it (holes excluded).
* Overlap interface (003 Sec 3.1, Fig 2): for every interface pair (a, b) the points of
  b within l_ov / 2 of body a, and the points of a within l_ov / 2 of body b, belong to
  both material point sets: the overlap band of total width l_ov (perpendicular to the
  interface) is centred on the sharp interface, and its coincident points of A and B are
  one node, i.e. share their DOFs (003 Sec 3.2). Each material's interactions use only
  its own point set.
* Boundary layers (003 Sec 4.1): every side with a prescribed displacement is extended
  by grid layers of depth delta outside the body; a layer point extends (and inherits
  the material sets of) the body point on the first grid row behind it. Displacements
  are prescribed on the layers and on that outermost grid row of the body.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.spatial import cKDTree

from interfaces.errors import CaseError

from .budget import check_memory

SIDES = ("xmin", "xmax", "ymin", "ymax", "zmin", "zmax")
DISPLACEMENT_KINDS = ("fixed", "displacement", "deformation_gradient")


@dataclass
class Frame:
    """A box frame (origin, rotation R with local axes as columns, size) of a side."""

    origin: np.ndarray
    R: np.ndarray
    size: np.ndarray

    def local(self, X: np.ndarray) -> np.ndarray:
        return (X - self.origin) @ self.R


@dataclass
class PrescribedSet:
    """Nodes and components of one displacement boundary condition."""

    bc: object
    nodes: np.ndarray
    components: list
    layer_nodes: np.ndarray


@dataclass
class TractionSet:
    bc: object
    nodes: np.ndarray
    force_per_node: np.ndarray   # (d,) per unit thickness in 2D


@dataclass
class Discretization:
    """Nodes, material point sets and boundary regions of a CPD model."""

    X: np.ndarray                 # (N, d) reference positions
    vol: np.ndarray               # (N,)
    owner: np.ndarray             # (N,) index of the body owning the point
    member: np.ndarray            # (N, n_bodies) bool: point belongs to body k's point set
    layer: np.ndarray             # (N,) bool: boundary-layer point outside the bodies
    body_names: list
    h: float
    delta: float
    overlap: float
    prescribed: list = field(default_factory=list)
    tractions: list = field(default_factory=list)
    copy_of: np.ndarray | None = None   # (N,) original of a compliant-overlap copy node, -1 otherwise

    @property
    def dim(self) -> int:
        return self.X.shape[1]

    @property
    def material_id(self) -> np.ndarray:
        """Body index for single-material points, n_bodies for shared (overlap) points."""
        nb = self.member.shape[1]
        mid = self.owner.copy()
        mid[self.member.sum(axis=1) > 1] = nb
        return mid


def grid_axes(lo: np.ndarray, hi: np.ndarray, h: float, pad: int, grid: str = "vertex") -> list[np.ndarray]:
    """Grid coordinates per axis, centred in [lo, hi], padded by ``pad`` rows.

    ``"vertex"``: points on the boundaries (and on interfaces through grid lines), n = L/h + 1
    per axis; ``"cell"``: cell centres, n = L/h per axis (100 x 100 for the unit square).
    """
    axes = []
    for a, b, n in zip(lo, hi, axis_points(lo, hi, h, 0, grid)):
        off = a + 0.5 * (b - a - (n - 1) * h)
        axes.append(off + h * np.arange(-pad, n + pad))
    return axes


def axis_points(lo, hi, h: float, pad: int, grid: str = "vertex") -> list[int]:
    """Number of grid points per axis of :func:`grid_axes` (nothing allocated)."""
    counts = []
    for a, b in zip(lo, hi):
        r = (b - a) / h
        n = int(round(r)) if abs(r - round(r)) < 1e-6 else int(math.floor(r))
        counts.append(max(n, 1) + (1 if grid == "vertex" else 0) + 2 * pad)
    return counts


def distance_to_shape(shape, P: np.ndarray) -> np.ndarray:
    """Euclidean distance of points to a shape (0 inside); None if the shape is unknown."""
    kind = getattr(shape, "kind", "")
    if hasattr(shape, "to_local") and hasattr(shape, "size"):
        q = shape.to_local(P)
        return np.linalg.norm(q - np.clip(q, 0.0, shape.size), axis=1)
    if hasattr(shape, "vertices"):
        v = np.asarray(shape.vertices, dtype=float)
        a, b = v, np.roll(v, -1, axis=0)
        ab = b - a
        t = np.clip(np.einsum("pkd,kd->pk", P[:, None, :] - a[None], ab) / np.einsum("kd,kd->k", ab, ab), 0, 1)
        dist = np.linalg.norm(P[:, None, :] - (a[None] + t[..., None] * ab[None]), axis=2).min(axis=1)
        dist[shape.contains(P)] = 0.0
        return dist
    if kind in ("circle", "sphere"):
        c = np.array([shape.cx, shape.cy] + ([shape.cz] if kind == "sphere" else []), dtype=float)
        return np.maximum(np.linalg.norm(P - c, axis=1) - shape.r, 0.0)
    return None


def side_frame(case, bc) -> Frame:
    """Frame of the side named by a boundary condition (body ``*`` = bounding box)."""
    d = case.dimension
    if bc.body == "*":
        lo, hi = case.bounds()
        return Frame(np.asarray(lo, float), np.eye(d), np.asarray(hi, float) - np.asarray(lo, float))
    shape = case.body(bc.body).shape
    if not (hasattr(shape, "to_local") and hasattr(shape, "size")):
        raise CaseError(f"boundary_conditions: body {bc.body!r} needs a rectangle/box shape for named sides")
    origin = np.asarray(shape.origin, dtype=float)
    # rows of R: local coordinates of the global unit vectors (local = (X - origin) @ R)
    R = shape.to_local(origin + np.eye(d))
    return Frame(origin, R, np.asarray(shape.size, dtype=float))


def discretize(case, h: float, delta: float, overlap: float, grid: str = "vertex") -> Discretization:
    """Build the CPD point cloud of ``case`` (003 Sec 3.2, 4.1).

    ``grid="vertex"`` puts grid points on the outer boundary and on straight interfaces
    along grid lines; then an overlap of delta/4 holds exactly one interfacial layer, as
    003 Sec 4.3 (Fig 10) describes. ``"cell"`` uses cell centres.
    """
    if grid not in ("vertex", "cell"):
        raise CaseError(f"cpd.grid must be 'vertex' or 'cell', got {grid!r}")
    d = case.dimension
    names = [b.name for b in case.bodies]
    lo, hi = case.bounds()
    pad = int(math.ceil(delta / h)) + 1
    check_memory(axis_points(lo, hi, h, pad, grid), h, delta)
    axes = grid_axes(np.asarray(lo, float), np.asarray(hi, float), h, pad, grid)
    G = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, d)
    tol = 1e-9 * h
    owner = np.full(len(G), -1, dtype=np.int64)
    for k in range(len(case.bodies) - 1, -1, -1):       # first body wins on shared boundaries
        owner[case.bodies[k].contains(G, tol)] = k
    body_pts = owner >= 0
    Xb, ob = G[body_pts], owner[body_pts]
    nb = len(names)
    member = np.zeros((len(Xb), nb), dtype=bool)
    member[np.arange(len(Xb)), ob] = True
    # ---- overlap band (003 Sec 3.1): points within l_ov / 2 of the other body ----
    half = 0.5 * overlap
    for pair in case.interfaces:
        ia, ib = names.index(pair.a), names.index(pair.b)
        for this, other in ((ib, ia), (ia, ib)):
            sel = np.flatnonzero(ob == this)
            # points of the other body's closed region (points on the common boundary count)
            other_pts = Xb[case.bodies[other].contains(Xb, tol)]
            if len(sel) == 0 or len(other_pts) == 0:
                continue
            dn = cKDTree(other_pts).query(Xb[sel])[0] - 0.5 * h * math.sqrt(d)
            ds = distance_to_shape(case.bodies[other].shape, Xb[sel])
            dist = np.maximum(dn, ds) if ds is not None else np.maximum(dn, 0.0)
            member[sel[dist <= half * (1 + 1e-9) + tol], other] = True
        shared = member[:, ia] & member[:, ib]
        touching = np.any(cKDTree(Xb[ob == ia]).query(Xb[ob == ib], distance_upper_bound=1.01 * h * math.sqrt(d))[0] < np.inf) \
            if np.any(ob == ia) and np.any(ob == ib) else False
        if touching and not shared.any():
            raise CaseError(f"cpd.overlap: the overlap band of width {overlap:g} between bodies {pair.a!r} and "
                            f"{pair.b!r} holds no grid point at h = {h:g}; use an overlap of at least ~h "
                            "(003 Sec 4.3: the overlap should not be much smaller than delta) or a finer h")
    # ---- boundary layers of depth delta on prescribed sides (003 Sec 4.1) ----
    tree_b = cKDTree(Xb)
    layer_X, layer_src, layer_bc = [], [], []
    prescribed_raw = []
    tractions = []
    for ibc, bc in enumerate(case.boundary_conditions):
        if bc.kind == "velocity":
            raise CaseError(f"boundary_conditions[{ibc}].kind 'velocity' is dynamic; CPD is quasi-static "
                            "(use displacement, fixed, deformation_gradient or traction)")
        fr = side_frame(case, bc)
        axis = SIDES.index(bc.side) // 2
        is_max = bc.side.endswith("max")
        target = fr.size[axis] if is_max else 0.0
        inward = -1.0 if is_max else 1.0
        qb = fr.local(Xb)
        others = [j for j in range(d) if j != axis]
        in_span = np.all((qb[:, others] >= -tol) & (qb[:, others] <= fr.size[others] + tol), axis=1)
        depth = (qb[:, axis] - target) * inward                    # >= 0 inside
        if bc.body != "*":
            in_span &= ob == names.index(bc.body)
        first_row = in_span & (depth >= -tol) & (depth < h * (1 - 1e-9))
        rows = np.flatnonzero(first_row)
        if len(rows) == 0:
            raise CaseError(f"boundary_conditions[{ibc}]: no grid point on side {bc.side} of {bc.body!r} at h = {h:g}")
        if bc.kind == "traction":
            t = np.zeros(d)
            t[:len(bc.value)] = bc.value
            meas = float(np.prod(fr.size[others]))
            tractions.append(TractionSet(bc, rows, t * meas / len(rows)))
            continue
        prescribed_raw.append((ibc, rows))
        qg = fr.local(G)
        g_span = np.all((qg[:, others] >= -tol) & (qg[:, others] <= fr.size[others] + tol), axis=1)
        g_depth = (qg[:, axis] - target) * inward
        cand = np.flatnonzero(g_span & (g_depth < -tol) & (g_depth >= -delta * (1 + 1e-9)) & ~body_pts)
        if len(cand) == 0:
            continue
        # the body point this layer point extends: first-row point behind it along the normal
        step = (qg[cand, axis] - target) * inward               # negative: outside
        Rn = np.zeros(d)
        Rn[axis] = inward
        shift = (-step + (qb[rows, axis] - target).mean() * inward)[:, None] * (fr.R @ Rn)[None, :]
        dist, src = tree_b.query(G[cand] + shift, distance_upper_bound=0.5 * h)
        ok = np.isfinite(dist) & np.isin(src, rows)
        layer_X.append(G[cand[ok]])
        layer_src.append(src[ok])
        layer_bc.append(np.full(ok.sum(), ibc))
    if layer_X:
        LX = np.concatenate(layer_X)
        Lsrc = np.concatenate(layer_src)
        Lbc = np.concatenate(layer_bc)
        # a layer point reached from two sides (corners) is kept once
        _, first = np.unique(np.round(LX / (tol * 1e3)).astype(np.int64), axis=0, return_index=True)
        first = np.sort(first)
        LX, Lsrc, Lbc = LX[first], Lsrc[first], Lbc[first]
    else:
        LX = np.zeros((0, d))
        Lsrc = np.zeros(0, np.int64)
        Lbc = np.zeros(0, np.int64)
    nbody = len(Xb)
    X = np.vstack([Xb, LX])
    owner_all = np.concatenate([ob, ob[Lsrc]])
    member_all = np.vstack([member, member[Lsrc]])
    layer = np.zeros(len(X), dtype=bool)
    layer[nbody:] = True
    prescribed = []
    for ibc, rows in prescribed_raw:
        bc = case.boundary_conditions[ibc]
        lay = nbody + np.flatnonzero(Lbc == ibc)
        nodes = np.unique(np.concatenate([rows, lay]))
        comps = [("x", "y", "z").index(c) for c in bc.components]
        prescribed.append(PrescribedSet(bc, nodes, comps, lay))
    return Discretization(X=X, vol=np.full(len(X), h ** d), owner=owner_all, member=member_all,
                          layer=layer, body_names=names, h=h, delta=delta, overlap=overlap,
                          prescribed=prescribed, tractions=tractions)
