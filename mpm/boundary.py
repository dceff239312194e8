"""Nodal boundary conditions (fixed, prescribed displacement/velocity) per material field.

A condition on side ``s`` of body ``b`` acts on the nodes on or beyond that side (in
the side's own, possibly rotated, frame) within the side's extent, and only on the
field of body ``b`` (mpm/LAYOUT.md: field index = body index). A prescribed
displacement u (or u = H X for ``deformation_gradient``) is imposed as the velocity
u / T over the ramp time T, then zero velocity.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from interfaces.errors import CaseError

from .grid import Grid

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

    @property
    def size(self) -> int:
        return int(self.node.size)


def side_nodes(case, grid: Grid, body_name: str, side: str, depth: int = 3) -> np.ndarray:
    """Nodes on or beyond ``side`` of the body (up to ``depth`` cells beyond it)."""
    shape = case.body(body_name).shape
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
            keep &= (q[:, d] >= -tol) & (q[:, d] <= size[d] + tol)
    nodes = np.flatnonzero(keep)
    if nodes.size == 0:
        raise CaseError(f"no grid node lies on side {side!r} of body {body_name!r}")
    return nodes


def nodal_conditions(case, grid: Grid, default_ramp: float) -> NodalConditions:
    """Collect every fixed/displacement/velocity/deformation_gradient condition."""
    cols = {k: [] for k in ("node", "field", "comp", "vel", "t_end")}
    X = None
    for k, bc in enumerate(case.boundary_conditions):
        if bc.kind == "traction":
            continue
        nodes = side_nodes(case, grid, bc.body, bc.side)
        f = case.body_index(bc.body)
        comps = bc.component_indices()
        if any(c >= grid.D for c in comps):
            raise CaseError(f"boundary_conditions[{k}].components {bc.components} exceed {grid.D}D")
        T = bc.ramp_time if bc.ramp_time is not None else default_ramp
        if bc.kind == "fixed":
            vel = np.zeros((nodes.size, grid.D))
            t_end = np.inf
        elif bc.kind == "velocity":
            vel = np.tile(bc.vector(grid.D), (nodes.size, 1))
            t_end = np.inf
        elif bc.kind in ("displacement", "deformation_gradient"):
            if X is None:
                X = grid.node_positions()
            vel = bc.displacement_at(X[nodes]) / T
            t_end = T
        else:
            raise CaseError(f"boundary_conditions[{k}].kind {bc.kind!r} is not supported by mpm")
        for c in comps:
            cols["node"].append(nodes)
            cols["field"].append(np.full(nodes.size, f))
            cols["comp"].append(np.full(nodes.size, c))
            cols["vel"].append(vel[:, c])
            cols["t_end"].append(np.full(nodes.size, t_end))
    if not cols["node"]:
        return NodalConditions(np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, np.int64),
                               np.zeros(0), np.zeros(0))
    return NodalConditions(*(np.ascontiguousarray(np.concatenate(cols[k])).astype(
        np.int64 if k in ("node", "field", "comp") else np.float64)
        for k in ("node", "field", "comp", "vel", "t_end")))
