"""Structured meshes of a case's bodies with duplicated nodes along every shared edge
(each body owns its nodes, so interfaces can open).

One structured grid covers all bodies in a common frame (the frame of the first
rectangle, so a rotated specimen such as the 000 DLS is meshed along its own axes). Grid
lines pass through every corner of every body and hole; each interval between two such
breakpoints is split into ceil(length / h) equal parts. Cells are assigned to the first
body containing their centroid, then every body gets its own copy of its nodes, so the
meshes are conforming along shared edges. Quadrilaterals by default; triangles (cells
split along one diagonal) when a polygon has 45-degree edges (003 diagonal interface).
Bodies whose boundaries do not follow the grid lines (circles, arbitrary polygons) are
rejected (a body boundary crossing a cell is detected) rather than meshed with staircase
boundaries; ``fem.gmsh_mesh`` meshes those.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from interfaces.errors import CaseError
from interfaces.resources import available_memory


@dataclass
class BodyMesh:
    """Vertices ``p`` (2, Np), cells ``t`` (3 or 4, Ne) counter-clockwise, per-cell and
    per-vertex body index (``case.bodies`` order), the common frame and a length scale."""

    p: np.ndarray
    t: np.ndarray
    element_body: np.ndarray
    vertex_body: np.ndarray
    origin: np.ndarray          # common frame: x_global = origin + R @ x_local
    rotation: np.ndarray
    size: float                 # bounding-box diagonal, for tolerances

    @property
    def cell_type(self) -> str:
        return "quad" if self.t.shape[0] == 4 else "triangle"


def _outline(shape, origin, R, where: str) -> np.ndarray:
    """Vertices of a rectangle or polygon in the common frame."""
    kind = getattr(shape, "kind", type(shape).__name__)
    if kind == "rectangle":
        pts = shape.corners()
    elif kind == "polygon":
        pts = np.asarray(shape.vertices, dtype=float)
    else:
        raise CaseError(f"{where}: fem meshes rectangles and polygons, got a {kind} "
                        "(use mpm or cpd for curved shapes)")
    return (pts - origin) @ R


def _frame(case) -> tuple[np.ndarray, np.ndarray]:
    for body in case.bodies:
        if getattr(body.shape, "kind", None) == "rectangle":
            return np.array([body.shape.x0, body.shape.y0], dtype=float), body.shape._rotation()
    return np.zeros(2), np.eye(2)


def _merge(values: np.ndarray, tol: float) -> np.ndarray:
    v = np.sort(values)
    keep = np.concatenate([[True], np.diff(v) > tol])
    return v[keep]


def _subdivide(breaks: np.ndarray, h: float) -> np.ndarray:
    """Grid lines: every interval between breakpoints split into ceil(len/h) equal parts."""
    lengths = np.diff(breaks)
    counts = np.maximum(1, np.ceil(lengths / h - 1e-9).astype(int))
    parts = [breaks[k] + lengths[k] * np.arange(counts[k]) / counts[k] for k in range(len(lengths))]
    return np.concatenate(parts + [breaks[-1:]])


def element_sizes(element_size) -> tuple[float, float]:
    """``element_size`` as (hx, hy) in the common frame (a scalar means square cells)."""
    flat = element_size if isinstance(element_size, (list, tuple)) else [element_size]
    if any(isinstance(v, (bool, str)) or v is None for v in flat):
        raise CaseError(f"element_size (h) must be a positive length in mm or a pair (hx, hy), "
                        f"got {element_size!r}")
    h = np.atleast_1d(np.asarray(element_size, dtype=float))
    if h.size == 1:
        h = np.repeat(h, 2)
    if h.shape != (2,) or not np.all(np.isfinite(h)) or np.any(h <= 0):
        raise CaseError(f"element_size (h) must be a positive length in mm or a pair (hx, hy), "
                        f"got {element_size!r}")
    return float(h[0]), float(h[1])


def _diagonal(outlines, tol) -> int:
    """0: all edges axis-aligned (quads); +1 / -1: triangles split along y = x / y = -x."""
    slopes = set()
    for loc in outlines:
        d = np.roll(loc, -1, axis=0) - loc
        skew = (np.abs(d[:, 0]) > tol) & (np.abs(d[:, 1]) > tol)
        for dx, dy in d[skew]:
            if abs(abs(dx) - abs(dy)) > 1e-9 * max(abs(dx), abs(dy)):
                raise CaseError("bodies: fem meshes edges along the grid axes or at 45 degrees only, "
                                f"found an edge of slope {dy / dx:g} (use mpm or cpd for such shapes)")
            slopes.add(1 if dx * dy > 0 else -1)
    if len(slopes) > 1:
        raise CaseError("bodies: fem meshes 45-degree edges of one orientation only")
    return slopes.pop() if slopes else 0


def _owner(case, points: np.ndarray) -> np.ndarray:
    """Index of the first body containing each point (-1: none, e.g. in a hole)."""
    owner = np.full(len(points), -1)
    for k in range(len(case.bodies) - 1, -1, -1):
        owner[case.bodies[k].contains(points)] = k
    return owner


def _check_cells_uncut(case, grid, cells, owner, origin, R) -> None:
    """Every cell must lie in one body: points just inside each corner and each edge
    midpoint belong to the same body as the centroid (no boundary crosses a cell)."""
    corners = grid[cells]                                   # (nv, ne, 2)
    centre = corners.mean(axis=0)
    mids = 0.5 * (corners + np.roll(corners, -1, axis=0))
    for pts in np.concatenate([corners, mids]):
        probe = centre + (1.0 - 1e-6) * (pts - centre)
        other = _owner(case, origin + probe @ R.T)
        bad = other != owner
        if bad.any():
            c = origin + centre[np.argmax(bad)] @ R.T
            raise CaseError(f"bodies: a body boundary crosses the structured mesh cells (near x = {c[0]:g}, "
                            f"y = {c[1]:g}); fem meshes rectangles and polygons whose edges are axis-aligned "
                            "or at 45 degrees, with holes of the same kind (use mpm or cpd for curved shapes)")


def build_mesh(case, element_size, grid_limit: float = 2e8) -> BodyMesh:
    """Conforming structured mesh for all bodies, nodes duplicated between bodies. A grid of
    more than ``grid_limit`` nodes over the bounding box is refused before it is allocated."""
    if case.dimension != 2:
        raise CaseError(f"analysis: fem solves 2D problems (plane stress, plane strain, "
                        f"axisymmetric), got {case.analysis!r}")
    origin, R = _frame(case)
    hx, hy = element_sizes(element_size)
    outlines, holes = [], []
    for i, body in enumerate(case.bodies):
        outlines.append(_outline(body.shape, origin, R, f"bodies[{i}].shape"))
        holes.append([_outline(h, origin, R, f"bodies[{i}].holes[{j}]") for j, h in enumerate(body.holes)])
    allpts = np.concatenate(outlines + [h for hs in holes for h in hs])
    lo, hi = allpts.min(axis=0), allpts.max(axis=0)
    size = float(np.hypot(*(hi - lo)))
    tol = 1e-9 * size
    diag = _diagonal(outlines + [h for hs in holes for h in hs], tol)
    if diag and abs(hx - hy) > 1e-12 * max(hx, hy):
        raise CaseError("element_size: 45-degree edges need square cells, give a scalar h")
    bx, by = _merge(allpts[:, 0], tol), _merge(allpts[:, 1], tol)
    grid_nodes = float(np.ceil(np.diff(bx) / hx - 1e-9).sum() + 1) * float(np.ceil(np.diff(by) / hy - 1e-9).sum() + 1)
    if grid_nodes > grid_limit:   # before any grid array exists (each grid node costs ~100 bytes here)
        raise CaseError(f"element_size = {element_size} mm gives a grid of about {grid_nodes:.3g} nodes "
                        f"over the bodies' extent, above {grid_limit:.3g}: use a larger element_size (h) "
                        "or raise max_dofs")
    xs = _subdivide(bx, hx)
    ys = _subdivide(by, hy)
    if diag:   # the same lines in x and y so that the diagonals pass through grid nodes
        xs = ys = _merge(np.concatenate([xs, ys]), tol)
    nx, ny = len(xs), len(ys)
    X, Y = np.meshgrid(xs, ys, indexing="ij")                 # node (i, j) -> i * ny + j
    grid = np.stack([X.ravel(), Y.ravel()], axis=1)
    i, j = np.meshgrid(np.arange(nx - 1), np.arange(ny - 1), indexing="ij")
    n00 = (i * ny + j).ravel()
    n10, n11, n01 = n00 + ny, n00 + ny + 1, n00 + 1
    if diag == 0:
        cells = np.stack([n00, n10, n11, n01])                  # counter-clockwise
    elif diag > 0:
        cells = np.concatenate([np.stack([n00, n10, n11]), np.stack([n00, n11, n01])], axis=1)
    else:
        cells = np.concatenate([np.stack([n00, n10, n01]), np.stack([n10, n11, n01])], axis=1)
    owner = _owner(case, origin + grid[cells].mean(axis=0) @ R.T)
    _check_cells_uncut(case, grid, cells, owner, origin, R)
    ps, ts, eb, vb = [], [], [], []
    offset = 0
    for k, body in enumerate(case.bodies):
        mine = owner == k
        if not mine.any():
            raise CaseError(f"bodies[{k}] ({body.name!r}) gets no cells: element_size is too coarse")
        used, local = np.unique(cells[:, mine], return_inverse=True)
        glob = origin + grid[used] @ R.T
        if case.analysis == "axisymmetric":
            if glob[:, 0].min() < -tol:
                raise CaseError(f"bodies[{k}]: axisymmetric bodies need r = x >= 0, body {body.name!r} "
                                f"reaches x = {glob[:, 0].min():g}")
            glob[:, 0] = np.maximum(glob[:, 0], 0.0)
        ps.append(glob)
        ts.append(local.reshape(cells.shape[0], -1) + offset)
        eb.append(np.full(mine.sum(), k))
        vb.append(np.full(len(used), k))
        offset += len(used)
    return BodyMesh(p=np.ascontiguousarray(np.concatenate(ps).T), t=np.ascontiguousarray(np.concatenate(ts, axis=1)),
                    element_body=np.concatenate(eb), vertex_body=np.concatenate(vb),
                    origin=origin, rotation=R, size=size)


def grid_compatible(case) -> bool:
    """True when every body, hole and clipping shape is a rectangle or polygon whose edges the
    structured mesher follows exactly (axis-aligned in the common frame, or 45 degrees)."""
    origin, R = _frame(case)
    try:
        outlines = [_outline(s, origin, R, "shape") for b in case.bodies
                    for s in [b.shape, *b.holes] + ([b.within] if b.within is not None else [])]
        allpts = np.concatenate(outlines)
        _diagonal(outlines, 1e-9 * float(np.hypot(*np.ptp(allpts, axis=0))))
    except CaseError:
        return False
    return True


BYTES_PER_DOF = 4.5e3     # measured peak: 1.04 GB at 266k DOFs (9-node quads), 0.93 GB at 241k (curved triangles)


def check_size(estimate: float, element_size, max_dofs: float) -> None:
    """Refuse, before anything large is allocated, a mesh of about ``estimate`` DOFs above
    ``max_dofs`` or needing more memory than is available (one line naming element_size)."""
    if estimate > max_dofs:
        raise CaseError(f"element_size = {element_size} mm gives about {estimate:.3g} DOFs, above max_dofs = "
                        f"{max_dofs:.3g}: use a larger element_size (h) or raise max_dofs")
    free = available_memory()
    need = BYTES_PER_DOF * estimate
    if free is not None and need > 0.8 * free:
        raise CaseError(f"element_size = {element_size} mm gives about {estimate:.3g} DOFs, needing about "
                        f"{need / 1e9:.3g} GB, more than the {free / 1e9:.3g} GB of memory available: use a "
                        "larger element_size (h)")


def default_element_size(case) -> float:
    """A quarter of the thinnest body dimension (in the common frame; curved shapes: of
    their bounding boxes)."""
    origin, R = _frame(case)
    dims = []
    for b in case.bodies:
        if getattr(b.shape, "kind", "") in ("rectangle", "polygon"):
            loc = _outline(b.shape, origin, R, "shape")
            extent = loc.max(axis=0) - loc.min(axis=0)
        else:
            lo, hi = b.bounds()
            extent = hi - lo
        dims.append(float(np.min(extent)))
    return min(dims) / 4.0


__all__ = ["BodyMesh", "build_mesh", "check_size", "default_element_size", "element_sizes", "grid_compatible"]

