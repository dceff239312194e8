"""Nodal boundary conditions (fixed, prescribed displacement/velocity) per material field.

A condition on side ``s`` of body ``b`` acts on the nodes on or beyond that side (in
the side's own, possibly rotated, frame) within the side's extent, and only on the
field of body ``b`` (mpm/LAYOUT.md: field index = body index). Every condition
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

from interfaces.errors import CaseError

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


def nodal_conditions(case, grid: Grid, default_ramp: float) -> NodalConditions:
    """Collect every fixed/displacement/velocity/deformation_gradient condition."""
    keys = ("node", "field", "comp", "vel", "t_end", "ramp", "t_ramp")
    cols = {k: [] for k in keys}
    X = None
    for k, bc in enumerate(case.boundary_conditions):
        if bc.kind == "traction":
            continue
        nodes = side_nodes(case, grid, bc.body, bc.side)
        f = case.body_index(bc.body)
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
