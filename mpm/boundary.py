"""Nodal boundary conditions (fixed, prescribed displacement/velocity) per material field.

A condition on side ``s`` of body ``b`` acts on the nodes on or beyond that side (in
the side's own, possibly rotated, frame) within the side's extent, and only on the
field of body ``b`` (mpm/LAYOUT.md: field index = body index). Body ``"*"`` is the
whole specimen: the side of the bounding box of all bodies, on every field (e.g. the
symmetry planes of a particle and its matrix, 000 Fig 4C). Every condition
follows its ramp (``interfaces.case.RAMPS``) over its ramp time T (the run's load ramp
when the case gives none): a linear displacement u (or u = H X for
``deformation_gradient``) is the velocity u / T over T, then zero velocity; a cosine
displacement follows u (1 - cos(pi t / T)) / 2 (the pulse of 002 Eq 49); a velocity
with a ramp time rises linearly or as the cosine to its value over T (without one it
applies at once). :func:`mpm.kernels.step_velocities` turns these into step velocities.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from interfaces.case import ALL_BODIES
from interfaces.errors import CaseError
from interfaces.geometry import Box, Rectangle

from . import kernels as K
from .grid import Grid

#: kernel code of each ramp name of ``interfaces.case.RAMPS``
RAMP_CODES = {"linear": K.RAMP_LINEAR, "cosine": K.RAMP_COSINE}
_VELOCITY_RAMPS = {"linear": K.VEL_LINEAR, "cosine": K.VEL_COSINE}

_SIDES = {"xmin": (0, False), "xmax": (0, True), "ymin": (1, False), "ymax": (1, True),
          "zmin": (2, False), "zmax": (2, True)}


@dataclass
class NodalConditions:
    """Flat arrays consumed by :func:`mpm.kernels.grid_update`."""

    node: np.ndarray    # int64 node index
    field: np.ndarray   # int64 field (body) index
    comp: np.ndarray    # int64 component
    vel: np.ndarray     # float64 prescribed velocity (mm/s)
    t_end: np.ndarray   # float64 velocity applies while t < t_end, then 0
    ramp: np.ndarray    # int64 history code (mpm.kernels.HOLD, DISP_COSINE, VEL_LINEAR, VEL_COSINE)
    t_ramp: np.ndarray  # float64 ramp time of the ramped histories (s)
    ghosts: "GhostNodes | None" = None   # B2 only: reflected nodes beyond the sides

    @property
    def size(self) -> int:
        return int(self.node.size)


@dataclass
class GhostNodes:
    """Symmetry about the sides with conditions, for the quadratic B-spline (B2).

    B2 particles next to a side reach the node line one cell beyond it, so a condition
    on the side's node line alone neither prescribes the displacement on the side (the
    spline there mixes three node lines) nor gives the nodes inside the forces of the
    material a symmetry plane stands for. The side is treated as a plane of symmetry:
    the body is continued by reflection, a prescribed component odd about its
    prescribed value (v_g = 2 v_bc - v_m, so the spline takes v_bc on the side), every
    other component even (v_g = v_m: the shear-free roller or symmetry plane), m the
    mirror node of the ghost g across the side. The reflected material is folded onto
    the nodes inside after P2G, plane after plane (so that the images across an edge
    of two planes are counted once each): a ghost's mass, momentum and force are
    added to its mirror's (reflected), then the plane's own nodes count twice; after
    the momentum update the ghosts take the reflected velocities. Each plane covers
    its side and a one-cell band around it (the tails beyond free edges).
    """

    node: np.ndarray        # int64 ghost node (one entry per component)
    field: np.ndarray       # int64 field
    comp: np.ndarray        # int64 component
    mirror: np.ndarray      # int64 mirror node across the side
    ref: np.ndarray         # int64 plain condition prescribing v_bc on the side (odd), -1 (even)
    plane: np.ndarray       # int64 plane of the entry (folded in plane order)
    plane_node: np.ndarray  # int64 nodes on the planes (their fields count twice)
    plane_field: np.ndarray
    plane_of: np.ndarray    # int64 plane of each plane-node entry


def _sided_shape(case, body_name: str):
    """The shape whose sides a condition names: the body's, or for ``"*"`` the bounding
    box of all bodies."""
    if body_name != ALL_BODIES:
        return case.body(body_name).shape
    lo, hi = case.bounds()
    return Rectangle(lo[0], lo[1], *(hi - lo)) if lo.size == 2 else Box(*lo, *(hi - lo))


def condition_fields(case, body_name: str) -> list[int]:
    """Field indices a condition acts on: the body's, or every field for ``"*"``."""
    if body_name == ALL_BODIES:
        return list(range(len(case.bodies)))
    return [case.body_index(body_name)]


def side_nodes(case, grid: Grid, body_name: str, side: str, depth: int = 3,
               band: int = 0) -> np.ndarray:
    """Nodes on or beyond ``side`` of the body (up to ``depth`` cells beyond it), within
    the side's extent widened by ``band`` cells (B2: the tails beyond its edges)."""
    shape = _sided_shape(case, body_name)
    if not hasattr(shape, "to_local"):
        raise CaseError(f"boundary side {side!r} of body {body_name!r}: sides exist only on "
                        f"Rectangle/Box shapes, got {type(shape).__name__}")
    axis, is_max = _SIDES[side]
    if axis >= grid.D:
        raise CaseError(f"boundary side {side!r} does not exist in {grid.D}D")
    X = grid.node_positions()
    q = shape.to_local(X)
    size = np.asarray(shape.size, float)
    h = float(np.min(grid.cell))
    tol = 1e-6 * h
    along = q[:, axis] - (size[axis] if is_max else 0.0)
    if not is_max:
        along = -along
    keep = (along >= -tol) & (along <= depth * float(np.max(grid.cell)) + tol)
    for d in range(grid.D):
        if d != axis:
            wide = band * float(grid.cell[d]) + tol
            keep &= (q[:, d] >= -wide) & (q[:, d] <= size[d] + wide)
    nodes = np.flatnonzero(keep)
    if nodes.size == 0:
        raise CaseError(f"no grid node lies on side {side!r} of body {body_name!r}")
    return nodes


def ramp_code(ramp: str, where: str) -> int:
    """Kernel code of a ramp name, or a CaseError naming ``where``."""
    if ramp not in RAMP_CODES:
        raise CaseError(f"{where}.ramp must be one of {', '.join(RAMP_CODES)}, got {ramp!r}")
    return RAMP_CODES[ramp]


def history(bc, default_ramp: float, where: str) -> tuple[float, int, float, float]:
    """(divisor of the prescribed vector, history code, t_end, ramp time) of a fixed,
    velocity or displacement condition: the kernel velocity is the vector / divisor."""
    T = bc.ramp_time if bc.ramp_time is not None else default_ramp
    code = ramp_code(bc.ramp, where)
    if bc.kind == "fixed":
        return 1.0, K.HOLD, np.inf, T
    if bc.kind == "velocity":
        if bc.ramp_time is None:
            return 1.0, K.HOLD, np.inf, T
        return 1.0, _VELOCITY_RAMPS[bc.ramp], np.inf, T
    if code == K.RAMP_LINEAR:
        return T, K.HOLD, T, T
    return 1.0, K.DISP_COSINE, T, T


def empty_conditions() -> NodalConditions:
    i, f = np.zeros(0, np.int64), np.zeros(0)
    return NodalConditions(i, i.copy(), i.copy(), f, f.copy(), i.copy(), f.copy())


def with_axis_conditions(bcs: NodalConditions, axis_nodes: np.ndarray, M: int) -> NodalConditions:
    """Add the symmetry of the axis r = 0 of an axisymmetric run (000 Sec 2.3): zero
    radial velocity of every field on the axis nodes."""
    n = axis_nodes.size * M
    if n == 0:
        return bcs
    node = np.repeat(axis_nodes, M)
    field = np.tile(np.arange(M, dtype=np.int64), axis_nodes.size)
    zi, zf = np.zeros(n, np.int64), np.zeros(n)
    add = (node, field, zi, zf, np.full(n, np.inf), np.full(n, K.HOLD, np.int64), zf.copy())
    old = (bcs.node, bcs.field, bcs.comp, bcs.vel, bcs.t_end, bcs.ramp, bcs.t_ramp)
    return NodalConditions(*(np.ascontiguousarray(np.concatenate([a, b])) for a, b in zip(old, add)))


#: which conditions cover the one-cell band around their side (:func:`nodal_conditions`)
BANDS = ("none", "normal", "all")


def nodal_conditions(case, grid: Grid, default_ramp: float, band: str = "none") -> NodalConditions:
    """Collect every fixed/displacement/velocity/deformation_gradient condition on the
    nodes of its side (:func:`side_nodes`); ``band`` ("none", "normal": the conditions
    on the side's normal component only, i.e. symmetry faces, "all") widens the side's
    extent by one cell for those conditions."""
    if band not in BANDS:
        raise ValueError(f"nodal_conditions: band must be one of {BANDS}, got {band!r}")
    keys = ("node", "field", "comp", "vel", "t_end", "ramp", "t_ramp")
    cols = {k: [] for k in keys}
    X = None
    for k, bc in enumerate(case.boundary_conditions):
        if bc.kind == "traction":
            continue
        normal_only = tuple(bc.component_indices()) == (_SIDES[bc.side][0],)
        wide = band == "all" or (band == "normal" and normal_only)
        nodes = side_nodes(case, grid, bc.body, bc.side, band=int(wide))
        fields = condition_fields(case, bc.body)
        comps = bc.component_indices()
        if any(c >= grid.D for c in comps):
            raise CaseError(f"boundary_conditions[{k}].components {bc.components} exceed {grid.D}D")
        if bc.kind not in ("fixed", "velocity", "displacement", "deformation_gradient"):
            raise CaseError(f"boundary_conditions[{k}].kind {bc.kind!r} is not supported by mpm")
        divisor, code, t_end, t_ramp = history(bc, default_ramp, f"boundary_conditions[{k}]")
        if bc.kind == "deformation_gradient":
            if X is None:
                X = grid.node_positions()
            vel = bc.displacement_at(X[nodes]) / divisor
        else:
            vel = np.tile(bc.vector(grid.D) / divisor, (nodes.size, 1))
        for f in fields:
            for c in comps:
                cols["node"].append(nodes)
                cols["field"].append(np.full(nodes.size, f))
                cols["comp"].append(np.full(nodes.size, c))
                cols["vel"].append(vel[:, c])
                cols["t_end"].append(np.full(nodes.size, t_end))
                cols["ramp"].append(np.full(nodes.size, code))
                cols["t_ramp"].append(np.full(nodes.size, t_ramp))
    if not cols["node"]:
        return empty_conditions()
    return NodalConditions(*(np.ascontiguousarray(np.concatenate(cols[k])).astype(
        np.int64 if k in ("node", "field", "comp", "ramp") else np.float64) for k in keys))


def ghost_nodes(case, grid: Grid, bcs: NodalConditions) -> GhostNodes:
    """The reflected nodes of :class:`GhostNodes` for every side with fixed /
    displacement / velocity conditions (shape B2); the sides must lie on grid node lines."""
    X = grid.node_positions()
    plain = {(int(n), int(f), int(c)): k for k, (n, f, c) in
             enumerate(zip(bcs.node, bcs.field, bcs.comp))}
    sides: dict[tuple[str, str], list[int]] = {}
    for k, bc in enumerate(case.boundary_conditions):
        if bc.kind != "traction":
            sides.setdefault((bc.body, bc.side), []).append(k)
    rows, plane_rows = [], []
    for pid, ((body, side), ks) in enumerate(sides.items()):
        bc = case.boundary_conditions[ks[0]]
        axis, outward, lo, hi = _grid_side(case, grid, bc, ks[0])
        comps = {c for k in ks for c in case.boundary_conditions[k].component_indices()}
        g, mirror, on_plane = _reflected(grid, X, axis, outward, lo, hi)
        for f in condition_fields(case, body):
            plane_rows += [(int(n), f, pid) for n in on_plane]
            for gi, mi, pi in zip(g, mirror, on_plane):
                for c in range(grid.D):
                    ref = plain.get((int(pi), f, c), -1) if c in comps else -1
                    if c in comps and ref < 0:
                        continue     # no condition on the side's node there (outside it)
                    rows.append((int(gi), f, c, int(mi), ref, pid))
    col = lambda vals: np.ascontiguousarray(np.array(vals, dtype=np.int64).reshape(-1))  # noqa: E731
    return GhostNodes(*(col([r[j] for r in rows]) for j in range(6)),
                      *(col([r[j] for r in plane_rows]) for j in range(3)))


def _grid_side(case, grid: Grid, bc, k: int):
    """(axis, outward sign, lower and upper bounds of the sided shape) of a condition's
    side, which must lie on a grid node line."""
    shape = _sided_shape(case, bc.body)
    axis, is_max = _SIDES[bc.side]
    lo, hi = (np.asarray(b, float) for b in shape.bounds())
    plane = hi[axis] if is_max else lo[axis]
    q = (plane - grid.origin[axis]) / grid.cell[axis]
    if abs(q - round(q)) > 1e-6:
        raise CaseError(f"boundary_conditions[{k}]: mpm shape 'b2' needs the side {bc.side!r} "
                        f"of {bc.body!r} on a grid node line (it is at {plane:g} mm); set "
                        "grid_anchor or the cell size so that it is, or use shape ugimp")
    return axis, (1 if is_max else -1), lo, hi


def _reflected(grid: Grid, X: np.ndarray, axis: int, outward: int, lo, hi):
    """Ghost nodes one cell beyond the side (in the one-cell band around its extent),
    their mirror nodes and their projections on the side."""
    h = grid.cell
    plane = hi[axis] if outward > 0 else lo[axis]
    keep = np.abs((X[:, axis] - plane) * outward - h[axis]) <= 1e-6 * h[axis]
    for d in range(grid.D):
        if d != axis:
            tol = 1e-6 * h[d]
            keep &= (X[:, d] >= lo[d] - h[d] - tol) & (X[:, d] <= hi[d] + h[d] + tol)
    g = np.flatnonzero(keep)
    ijk = np.rint((X[g] - grid.origin) / h).astype(np.int64)
    mir, onp = ijk.copy(), ijk.copy()
    mir[:, axis] -= 2 * outward
    onp[:, axis] -= outward
    return g, grid.node_index(mir), grid.node_index(onp)


def no_ghosts() -> GhostNodes:
    i = np.zeros(0, np.int64)
    return GhostNodes(*(i.copy() for _ in range(9)))
