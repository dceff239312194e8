"""The discretized case: scikit-fem mesh, vector element, basis and DOF bookkeeping.

Quadrilaterals get ``ElementQuad2`` (9-node, default) or ``ElementQuad1`` (``order=1``);
triangles (45-degree polygon edges) ``ElementTriP2`` / ``ElementTriP1``. Curved bodies
(circles, ellipses) are meshed by gmsh (``fem.gmsh_mesh``) into 6-node isoparametric
triangles whose edges follow the curves (``MeshTri2``; ``curved=False``: straight edges).
``mesher``: ``auto`` (gmsh where a shape is curved or a polygon edge is off the grid
directions, the structured mesher otherwise: exact there and faster), ``structured``
or ``gmsh``. DOFs follow
scikit-fem's ``ElementVector`` numbering: every x-DOF is even and its y-DOF is the next
one, which the interface code relies on (checked at construction).
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from skfem import (CellBasis, ElementQuad1, ElementQuad2, ElementTriP1, ElementTriP2, ElementVector, MeshQuad, MeshTri,
                   MeshTri2)

from interfaces.errors import CaseError

from .gmsh_mesh import build_gmsh_mesh, needs_gmsh
from .mesh import BodyMesh, build_mesh, check_size, element_sizes, grid_compatible

MESHERS = ("auto", "structured", "gmsh")


@dataclass
class Discretization:
    """Everything the assembly and post-processing need about the mesh and the DOFs."""

    case: object
    body_mesh: BodyMesh
    mesh: object
    element: object
    basis: CellBasis
    dof_body: np.ndarray          # body index of every DOF
    order: int
    intorder: int
    thickness: float              # out-of-plane thickness (1 per radian when axisymmetric)
    axisymmetric: bool
    ring: float                   # 2 pi for axisymmetric (whole ring), else 1
    tol: float                    # geometric tolerance (mm)
    mesher: str = "structured"    # or "gmsh (curved)", "gmsh (straight-sided)"

    @property
    def ndof(self) -> int:
        return self.basis.N

    @property
    def element_body(self) -> np.ndarray:
        return self.body_mesh.element_body

    def side_facets(self, body_name: str, side: str) -> np.ndarray:
        """Boundary facets on a body's side (body ``"*"``: the bounding-box side)."""
        mesh = self.mesh
        bf = mesh.boundary_facets()
        k = _body_index(self.case, body_name)
        if k is not None:
            bf = bf[self.element_body[mesh.f2t[0, bf]] == k]
        v = mesh.facets[:, bf]
        on = (self.case.side_points_mask(body_name, side, mesh.p[:, v[0]].T, self.tol)
              & self.case.side_points_mask(body_name, side, mesh.p[:, v[1]].T, self.tol))
        if not on.any():
            raise CaseError(f"side {side!r} of body {body_name!r} has no mesh facets")
        return bf[on]

    def side_dofs(self, body_name: str, side: str) -> np.ndarray:
        """DOFs (both components) located on a body's side (sides lie on the mesh boundary:
        every body owns its nodes, so only boundary DOFs are tested)."""
        cand = self.boundary_dofs
        k = _body_index(self.case, body_name)
        if k is not None:
            cand = cand[self.dof_body[cand] == k]
        return cand[self.case.side_points_mask(body_name, side, self.basis.doflocs[:, cand].T, self.tol)]

    @functools.cached_property
    def boundary_dofs(self) -> np.ndarray:
        """Sorted DOFs on boundary facets (vertices and facet nodes)."""
        return np.unique(self.basis.get_dofs(self.mesh.boundary_facets()).flatten())


def _body_index(case, body_name: str):
    return None if body_name == "*" else [b.name for b in case.bodies].index(case.body(body_name).name)


def discretize(case, element_size, order: int, intorder: int, max_dofs: float, mesher: str = "auto",
               curved: bool = True) -> Discretization:
    """Mesh the case (``fem.mesh`` or ``fem.gmsh_mesh``) and set up the scikit-fem basis."""
    if mesher not in MESHERS:
        raise CaseError(f"fem option mesher must be one of {', '.join(MESHERS)}, got {mesher!r}")
    if mesher == "gmsh" or (mesher == "auto" and (needs_gmsh(case) or not grid_compatible(case))):
        bm, mesh, element = _unstructured(case, element_size, order, max_dofs, curved)
        used = "gmsh (curved)" if order == 2 and curved else "gmsh (straight-sided)"
    else:
        bm, mesh, element = _structured(case, element_size, order, max_dofs)
        used = "structured"
    basis = CellBasis(mesh, element, intorder=intorder)
    for dofs in (basis.nodal_dofs, basis.facet_dofs):
        if dofs.size and not (np.all(dofs[0] % 2 == 0) and np.all(dofs[1] == dofs[0] + 1)):
            raise RuntimeError("scikit-fem changed its ElementVector DOF numbering (x even, y = x + 1)")
    dof_body = np.empty(basis.N, dtype=np.int64)
    dof_body[basis.element_dofs] = bm.element_body[None, :]
    axisym = case.analysis == "axisymmetric"
    return Discretization(case=case, body_mesh=bm, mesh=mesh, element=element, basis=basis, dof_body=dof_body,
                          order=order, intorder=intorder, thickness=1.0 if axisym else case.thickness,
                          axisymmetric=axisym, ring=2.0 * math.pi if axisym else 1.0, tol=1e-9 * bm.size,
                          mesher=used)


def _structured(case, element_size, order: int, max_dofs: float):
    bm = build_mesh(case, element_size, grid_limit=max(2.0 * max_dofs, 1e6))
    check_size(bm.p.shape[1] * (8 if order == 2 else 2), element_size, max_dofs)
    if bm.cell_type == "quad":
        return bm, MeshQuad(bm.p, bm.t), ElementVector(ElementQuad2() if order == 2 else ElementQuad1())
    return bm, MeshTri(bm.p, bm.t), ElementVector(ElementTriP2() if order == 2 else ElementTriP1())


def _unstructured(case, element_size, order: int, max_dofs: float, curved: bool):
    """gmsh 6-node triangles: curved isoparametric P2 (default), straight-sided P2, or P1."""
    hx, hy = element_sizes(element_size)
    if hx != hy:
        raise CaseError(f"element_size: gmsh meshes take one size h, got {element_size!r}")
    gm = build_gmsh_mesh(case, hx, max_dofs)
    if case.analysis == "axisymmetric":
        size = float(np.ptp(gm.nodes, axis=1).max())
        if gm.nodes[0].min() < -1e-9 * size:
            k = int(gm.element_body[np.argmin(gm.nodes[0, gm.t6[:3]].min(axis=0))])
            raise CaseError(f"bodies[{k}]: axisymmetric bodies need r = x >= 0, body {case.bodies[k].name!r} "
                            f"reaches x = {gm.nodes[0].min():g}")
        gm.nodes[0] = np.maximum(gm.nodes[0], 0.0)
    if order == 2 and curved:
        mesh = MeshTri2(gm.nodes, gm.t6)
        element = ElementVector(ElementTriP2())
    else:
        used, local = np.unique(gm.t6[:3], return_inverse=True)
        mesh = MeshTri(gm.nodes[:, used], local.reshape(3, -1))
        element = ElementVector(ElementTriP2() if order == 2 else ElementTriP1())
    p = mesh.p[:, :mesh.nvertices]          # MeshTri2.p also holds the mid-edge nodes
    vertex_body = np.empty(p.shape[1], dtype=np.int64)
    vertex_body[mesh.t] = gm.element_body[None, :]
    lo, hi = p.min(axis=1), p.max(axis=1)
    bm = BodyMesh(p=p, t=mesh.t, element_body=gm.element_body, vertex_body=vertex_body,
                  origin=np.zeros(2), rotation=np.eye(2), size=float(np.hypot(*(hi - lo))))
    return bm, mesh, element


__all__ = ["Discretization", "discretize", "MESHERS"]
