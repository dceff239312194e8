"""Bulk elasticity and boundary loads with scikit-fem, interface blocks from
:mod:`fem.interface_element`; all assembled as sparse matrices (coo -> csr).

Voigt order as in ``interfaces.materials``: plane ``[xx, yy, xy]`` (engineering shear),
axisymmetric ``[rr, zz, tt, rz]`` with x = r, y = z; axisymmetric integrals are per
radian (weight r), planar ones carry the out-of-plane thickness.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from skfem import BilinearForm, CellBasis, FacetBasis, LinearForm

from interfaces.errors import CaseError

from .interface_element import jump_stiffness_batch


def strain_voigt(grad, value, x, axisymmetric: bool):
    """Engineering strain components from a displacement's gradient (and value, for the
    hoop strain u_r / r of axisymmetric analyses)."""
    e = [grad[0, 0], grad[1, 1]]
    if axisymmetric:
        e.append(value[0] / x[0])
    e.append(grad[0, 1] + grad[1, 0])
    return e


def elasticity_form(pattern, thickness: float, axisymmetric: bool) -> BilinearForm:
    """scikit-fem form of int sigma(u) : eps(v) dV with per-element moduli passed as fields
    ``c{i}{j}`` for the (i, j) in ``pattern``: the reference for :func:`bulk_stiffness`."""

    @BilinearForm
    def form(u, v, w):
        eu = strain_voigt(u.grad, u, w.x, axisymmetric)
        ev = strain_voigt(v.grad, v, w.x, axisymmetric)
        out = 0.0
        for i, j in pattern:        # at most 16 moduli, each over all elements at once
            out = out + w[f"c{i}{j}"] * eu[j] * ev[i]
        return out * (w.x[0] if axisymmetric else thickness)

    return form


def bulk_stiffness(basis: CellBasis, element_body: np.ndarray, moduli: list[np.ndarray],
                   thickness: float, axisymmetric: bool, chunk: int = 4096) -> sp.csr_matrix:
    """int B^T C B dV over all bodies, C per element (its body's ``material.stiffness``).

    The same integral as :func:`elasticity_form` assembled by scikit-fem, evaluated from
    the basis functions scikit-fem tabulated (``basis.basis``) as one batched product
    B^T (C B) per chunk of elements instead of one form call per pair of local functions
    (~10x faster for 9-node quads), integrated once per set of congruent elements
    (:func:`_congruent_elements`); tests check both agree to round-off.
    """
    reps, copy_of = _congruent_elements(basis, element_body, axisymmetric)
    C = np.stack(moduli)[element_body[reps]]                             # (nr, nv, nv)
    x = np.asarray(basis.global_coordinates())
    weight = basis.dx * (x[0] if axisymmetric else thickness)            # (ne, nq)
    nloc = basis.Nbfun
    data = np.empty((len(reps), nloc, nloc))
    for lo in range(0, len(reps), chunk):   # bounded memory; each chunk fully vectorized
        k = slice(lo, min(lo + chunk, len(reps)))
        e = reps[k]
        B = np.stack([np.stack(strain_voigt(np.asarray(phi.grad)[..., e, :], np.asarray(phi)[:, e],
                                            x[:, e], axisymmetric)) for (phi,) in basis.basis])  # (nloc, nv, ec, nq)
        B = B.transpose(2, 0, 1, 3)                                      # (ec, nloc, nv, nq)
        CB = np.einsum("evw,ejwq->ejvq", C[k], B)
        Bw = B * weight[e][:, None, None, :]
        ec = B.shape[0]
        data[k] = np.matmul(Bw.reshape(ec, nloc, -1), CB.reshape(ec, nloc, -1).transpose(0, 2, 1))
    if copy_of is not None:
        data = data[copy_of]
    return _element_matrices_csr(data, basis.element_dofs.T, basis.N)


def mass_matrix(disc, densities: list[float], lumped: bool) -> sp.csr_matrix:
    """int rho N_i N_j dV (per-element rho, thickness or 2 pi r), lumped by row sums."""
    rho = np.asarray(densities, float)[disc.element_body]
    basis = disc.basis

    @BilinearForm
    def form(u, v, w):
        scale = w.x[0] if disc.axisymmetric else disc.thickness
        return w["rho"] * (u[0] * v[0] + u[1] * v[1]) * scale

    M = form.assemble(basis, rho=rho[:, None] * np.ones((1, basis.X.shape[1]))).tocsr()
    if not lumped:
        return M
    d = np.asarray(M.sum(axis=1)).ravel()
    if np.any(d <= 0.0):
        raise CaseError("fem option mass = 'lumped' needs positive row sums of the mass matrix "
                        "(order = 1, or quadrilaterals with order = 2); use mass = 'consistent'")
    return sp.diags(d).tocsr()


def _congruent_elements(basis: CellBasis, element_body: np.ndarray, axisymmetric: bool):
    """Representative elements and, for every element, the index of its representative:
    planar straight-edged elements with the same body and the same vertex offsets (to 1e-12
    of their size) have the same stiffness matrix (a structured grid has a handful), so only
    the representatives are integrated. Returns (all elements, None) where that does not hold
    (axisymmetric: the matrix depends on r; curved isoparametric meshes)."""
    mesh = basis.mesh
    ne = mesh.t.shape[1]
    if axisymmetric or type(mesh).__name__ not in ("MeshQuad1", "MeshTri1"):
        return np.arange(ne), None
    v = mesh.p[:, mesh.t]                                                # (2, nv, ne)
    rel = (v - v[:, :1]).reshape(-1, ne)
    scale = np.abs(rel).max(axis=0)
    key = np.vstack([np.round(rel / (1e-12 * scale.max())), element_body[None, :]]).T
    _, reps, copy_of = np.unique(key, axis=0, return_index=True, return_inverse=True)
    return reps, copy_of.ravel()


def _element_matrices_csr(data: np.ndarray, dofs: np.ndarray, n: int) -> sp.csr_matrix:
    """Sum element matrices ``data`` (ne, k, k) on their ``dofs`` (ne, k) into an (n, n) csr
    matrix; 32-bit indices where they fit (half the memory traffic of the coo -> csr sort)."""
    itype = np.int32 if n < 2**31 - 1 and data.size < 2**31 - 1 else np.int64
    dofs = np.ascontiguousarray(dofs, dtype=itype)
    rows = np.broadcast_to(dofs[:, :, None], data.shape).ravel()
    cols = np.broadcast_to(dofs[:, None, :], data.shape).ravel()
    return sp.coo_matrix((data.ravel(), (rows, cols)), shape=(n, n)).tocsr()


def facet_load(mesh, element, facets: np.ndarray, traction: np.ndarray, thickness: float,
               axisymmetric: bool, intorder: int) -> np.ndarray:
    """Consistent nodal loads of a uniform traction (MPa, global axes) on ``facets``."""
    tx, ty = float(traction[0]), float(traction[1])
    fb = FacetBasis(mesh, element, facets=np.asarray(facets), intorder=intorder)

    @LinearForm
    def load(v, w):
        return (tx * v[0] + ty * v[1]) * (w.x[0] if axisymmetric else thickness)

    return load.assemble(fb)


def jump_operator(pairs, ndof: int) -> sp.csr_matrix:
    """Nodal jumps in the interface frame of each node pair, J = (n.(u_b - u_a), t.(u_b - u_a)):
    a (2k, ndof) matrix for the k pairs of ``pairs`` (``fem.interface_mesh.NodePairs``).
    With u = T q + g, J = (D T) q + D g cancels the shared body-a unknowns exactly."""
    k = len(pairs.a)
    R = np.stack([pairs.n, pairs.t], axis=1)                     # (k, 2 rows n/t, 2 comps)
    rows = np.repeat(np.arange(2 * k), 4)
    cols = np.stack([np.stack([pairs.b + c, pairs.a + c], axis=1) for c in (0, 1)], axis=1)   # (k, 2c, 2)
    cols = np.broadcast_to(cols[:, None], (k, 2, 2, 2)).reshape(-1)
    vals = (R[:, :, :, None] * np.array([1.0, -1.0])).reshape(-1)
    return sp.coo_matrix((vals, (rows, cols)), shape=(2 * k, ndof)).tocsr()


def jump_stiffness(xy: np.ndarray, jump_nodes: np.ndarray, frames: np.ndarray, Dn: np.ndarray,
                   Dt: np.ndarray, thickness: float, axisymmetric: bool, npairs: int) -> sp.csr_matrix:
    """Interface stiffness (002 Eq 15-19) acting on nodal jumps in the node frames
    (``frames`` (m, n, 2, 2), columns n and t): 1/2 J^T K J is the interface energy.
    ``jump_nodes`` (m, n) indexes the node pairs."""
    if len(xy) == 0:
        return sp.csr_matrix((2 * npairs, 2 * npairs))
    n = xy.shape[1]
    Kj = jump_stiffness_batch(xy, Dn, Dt, thickness=thickness, axisymmetric=axisymmetric, node_frames=frames)
    dofs = np.stack([2 * jump_nodes, 2 * jump_nodes + 1], axis=2).reshape(len(xy), -1)
    rows = np.repeat(dofs, 2 * n, axis=1).ravel()
    cols = np.tile(dofs, (1, 2 * n)).ravel()
    return sp.coo_matrix((Kj.ravel(), (rows, cols)), shape=(2 * npairs, 2 * npairs)).tocsr()


__all__ = ["bulk_stiffness", "elasticity_form", "facet_load", "jump_operator", "jump_stiffness", "strain_voigt"]
