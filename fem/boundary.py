"""Boundary conditions of a case on the FEM discretization: consistent nodal loads of
tractions, prescribed displacements (fixed, displacement, deformation_gradient), and the
removal of rigid motions left free by the supports."""
from __future__ import annotations

import numpy as np

from interfaces.case import COMPONENTS
from interfaces.errors import CaseError, SolverError

from .assembly import facet_load


def apply_boundary_conditions(disc) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Load vector f (N) and prescribed DOFs with their values (mm)."""
    case = disc.case
    f = np.zeros(disc.ndof)
    presc_d, presc_v = [], []
    for i, bc in enumerate(case.boundary_conditions):   # a handful of conditions, each vectorized
        where = f"boundary_conditions[{i}]"
        if bc.kind == "traction":
            tr = np.zeros(2)
            comps = bc.components if len(bc.value) == len(bc.components) else COMPONENTS[:2]
            for c, v in zip(comps, bc.value):
                tr[COMPONENTS.index(c)] = v
            f += facet_load(disc.mesh, disc.element, disc.side_facets(bc.body, bc.side), tr,
                            disc.thickness, disc.axisymmetric, disc.intorder)
        elif bc.kind in ("fixed", "displacement", "deformation_gradient"):
            dofs = disc.side_dofs(bc.body, bc.side)
            if len(dofs) == 0:
                raise CaseError(f"{where}: side {bc.side!r} of body {bc.body!r} has no mesh nodes")
            comp = dofs % 2
            vals = bc.displacement_at(disc.basis.doflocs[:, dofs].T)[np.arange(len(dofs)), comp]
            keep = np.isin(comp, bc.component_indices())
            presc_d.append(dofs[keep])
            presc_v.append(vals[keep])
        else:
            raise CaseError(f"{where}.kind: fem is static; a {bc.kind!r} condition needs a dynamic "
                            "method (mpm), or use 'displacement'")
    presc_d = np.concatenate(presc_d) if presc_d else np.zeros(0, dtype=np.int64)
    presc_v = np.concatenate(presc_v) if presc_v else np.zeros(0)
    return f, presc_d, presc_v


def rigid_modes(doflocs: np.ndarray, axisymmetric: bool) -> np.ndarray:
    """Infinitesimal rigid motions as DOF vectors (columns): x, y translations and a rotation
    about the centroid (axisymmetric: the axial translation only)."""
    comp = np.arange(doflocs.shape[1]) % 2            # x-DOF even, y-DOF odd (ElementVector)
    ty = (comp == 1).astype(float)
    if axisymmetric:
        return ty[:, None]
    tx = (comp == 0).astype(float)
    c = doflocs.mean(axis=1)
    rot = np.where(comp == 0, -(doflocs[1] - c[1]), doflocs[0] - c[0])
    return np.stack([tx, ty, rot], axis=1)


def free_rigid_motions(modes: np.ndarray, prescribed) -> np.ndarray:
    """The rigid motions (columns, combinations of ``modes``) that the ``prescribed`` DOFs
    leave free."""
    fixed = np.asarray(prescribed, dtype=np.int64)
    R = modes[fixed] if fixed.size else np.zeros((0, modes.shape[1]))
    # the zero rows make vt square (every null vector) without the n_fixed^2 factor U of
    # full_matrices (12.8 GB for the 40000 axis DOFs of a 10 m axisymmetric sleeve)
    _, sv, vt = np.linalg.svd(np.vstack([R, np.zeros((modes.shape[1], modes.shape[1]))]),
                              full_matrices=False)
    rank = int(np.sum(sv > 1e-9 * max(1.0, sv.max(initial=0.0))))
    return modes @ vt[rank:].T


def pin_rigid_modes(modes: np.ndarray, prescribed: np.ndarray, f: np.ndarray, candidates: np.ndarray) -> list[int]:
    """Fewest DOFs to fix so that no rigid mode is left free by ``prescribed`` (chosen among
    ``candidates`` where possible, e.g. the support side). Pinning does not change the
    deformation only if the loads do no work on the free mode: otherwise SolverError."""
    pins: list[int] = []
    fixed = list(prescribed)
    for _ in range(modes.shape[1]):
        free = free_rigid_motions(modes, fixed)
        if free.shape[1] == 0:
            break
        r = free[:, 0] / np.abs(free[:, 0]).max()
        work = abs(f @ r)
        if work > 1e-9 * max(np.abs(f).sum(), 1e-300):
            raise SolverError("the boundary conditions leave a rigid motion free and the loads are not "
                              f"balanced in it (net work {work:g}); add a 'fixed' condition")
        cand = candidates if np.abs(r[candidates]).max(initial=0.0) > 0.1 else np.arange(len(r))
        d = int(cand[np.argmax(np.abs(r[cand]))])
        pins.append(d)
        fixed.append(d)
    return pins


def at_rest_gauge(u: np.ndarray, free: np.ndarray, M) -> np.ndarray:
    """``u`` less the rigid motion (of the ``free`` columns) that makes it mass-orthogonal
    to them: free^T M u = 0, no mean translation or rotation. A free body loaded from rest
    by balanced loads keeps that gauge (zero momentum and angular momentum): an explicit
    run (MPM) ends in it, whereas the pinned DOFs of :func:`pin_rigid_modes` pick one
    arbitrarily (the DCB's pinned support arm showed the whole opening at its load point
    and a rigid rotation along the bond)."""
    if free.shape[1] == 0:
        return u
    Mf = M @ free
    return u - free @ np.linalg.solve(free.T @ Mf, Mf.T @ u)


__all__ = ["apply_boundary_conditions", "rigid_modes", "free_rigid_motions", "pin_rigid_modes", "at_rest_gauge"]
