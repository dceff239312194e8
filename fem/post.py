"""Post-processing of a FEM solution: nodal stresses, interface jump profiles (002 Fig 7),
displacements along the case's lines, side averages for the stiffness of 002 Eq 43."""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.spatial import cKDTree
from skfem import CellBasis

from .assembly import strain_voigt
from .interface_element import frame, shape_functions


def vertex_stress(mesh, element, u: np.ndarray, element_body: np.ndarray, moduli: list[np.ndarray],
                  axisymmetric: bool) -> np.ndarray:
    """Stress (Voigt of the analysis) at mesh vertices: values at each element's corners,
    averaged over the elements of the vertex's own body (bodies have separate vertices)."""
    nv = mesh.t.shape[0]
    if nv == 4:
        corners = np.array([[0.0, 1.0, 1.0, 0.0], [0.0, 0.0, 1.0, 1.0]])   # reference quad corners
    else:
        corners = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])             # reference triangle corners
    if axisymmetric:   # at r = 0 the hoop strain u_r/r is 0/0: sample just inside the cell instead
        centre = corners.mean(axis=1, keepdims=True)
        corners = centre + (corners - centre) * (1.0 - 1e-6)
    basis = CellBasis(mesh, element, quadrature=(corners, np.full(nv, 1.0 / nv)))
    field = basis.interpolate(u)
    eps = np.stack(strain_voigt(field.grad, np.asarray(field), np.asarray(basis.global_coordinates()), axisymmetric))
    C = np.stack(moduli)[element_body]                                    # (ne, nv, nv)
    sig = np.einsum("eij,jeq->eqi", C, eps)                               # (ne, corners, nv)
    nvert = mesh.p.shape[1]
    acc = np.zeros((nvert, sig.shape[-1]))
    cnt = np.bincount(mesh.t.T.ravel(), minlength=nvert).astype(float)
    for c in range(sig.shape[-1]):
        acc[:, c] = np.bincount(mesh.t.T.ravel(), weights=sig[:, :, c].ravel(), minlength=nvert)
    return acc / np.maximum(cnt, 1.0)[:, None]


def interface_profile(el, nodal_jumps: np.ndarray, nodal_tractions: np.ndarray,
                      points_per_element: int = 3) -> dict[str, np.ndarray]:
    """Jumps [u_n], [u_t] (u_b - u_a, normal from a to b, 002 Eq 6 and 9) and tractions
    T_n, T_t along one interface, at Gauss points of its elements, ordered by the arc length
    ``s`` from one end, with Gauss weights ``weight`` (mm) so that sum(weight * g) integrates
    g along the interface (exactly for polynomial g). ``nodal_jumps`` / ``nodal_tractions``
    (m, n, 2) are given at the elements' side-1 nodes in global x, y components. T_t and
    [u_t] are signed along increasing s; T_n > 0 is tension."""
    xi, wq = np.polynomial.legendre.leggauss(points_per_element)
    N, _ = shape_functions(el.xy.shape[1], xi)
    pos, n1, t1, dl = frame(el.xy, xi)
    ds = (wq[None, :] * dl).ravel()                     # arc-length quadrature weight of each point

    def components(nodal):
        v = np.einsum("qi,mia->mqa", N, nodal)
        return np.einsum("mqa,mqa->mq", v, n1).ravel(), np.einsum("mqa,mqa->mq", v, t1).ravel()

    jn, jt = components(nodal_jumps)
    Tn, Tt = components(nodal_tractions)
    pos = pos.reshape(-1, 2)
    ends = el.xy[:, [0, -1]].reshape(-1, 2)
    k = int(np.argmax(ends.max(axis=0) - ends.min(axis=0)))
    start = ends[np.argmin(ends[:, k])]
    chord = ends[np.argmax(ends[:, k])] - start
    chord /= np.linalg.norm(chord)
    s = (pos - start) @ chord
    order = np.argsort(s, kind="stable")
    sign = np.sign(np.einsum("qa,a->q", t1.reshape(-1, 2), chord))   # tangent along increasing s
    return {"s": s[order], "x": pos[order, 0], "y": pos[order, 1], "jump_n": jn[order],
            "jump_t": (jt * sign)[order], "traction_n": Tn[order], "traction_t": (Tt * sign)[order],
            "Dn": np.repeat(el.Dn, len(xi))[order], "Dt": np.repeat(el.Dt, len(xi))[order],
            "weight": ds[order]}


def recover_tractions(K_bulk, u: np.ndarray, f: np.ndarray, pairs, M) -> np.ndarray:
    """Interface tractions (T_n, T_t) at the node pairs, also where D = inf (constraint
    reactions): the interface force on body b, F_b = f_b - (K u)_b, equals -int N_i T ds in
    the weak form, so M T = -R^T (K u - f)_b with M = int N_i N_j ds (the jump-space matrix
    of unit D). For a finite D this returns exactly D [u] (M^-1 D M J = D J)."""
    r = (K_bulk @ u - f)
    Fb = np.stack([r[pairs.b], r[pairs.b + 1]], axis=1)
    rhs = -np.stack([np.einsum("ka,ka->k", Fb, pairs.n), np.einsum("ka,ka->k", Fb, pairs.t)], axis=1).ravel()
    return spla.splu(M.tocsc()).solve(rhs).reshape(-1, 2)


def _affine_inverse(mesh, x: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Reference coordinates of points in cells with an affine map (triangles and the
    parallelogram quads of the structured meshes): x = p0 + (p1 - p0) X + (p_last - p0) Y."""
    p0 = mesh.p[:, mesh.t[0, cells]]
    e1 = mesh.p[:, mesh.t[1, cells]] - p0
    e2 = mesh.p[:, mesh.t[-1, cells]] - p0
    det = e1[0] * e2[1] - e1[1] * e2[0]
    d = x - p0
    return np.stack([(d[0] * e2[1] - d[1] * e2[0]) / det, (e1[0] * d[1] - e1[1] * d[0]) / det])


def _locate(basis, x: np.ndarray, candidates: int = 8, tol: float = 1e-8):
    """Cell and reference coordinates of points ``x`` (2, N): nearest cell centroids first,
    the first whose inverse mapping lands in the reference cell (within ``tol``); -1 if none
    (points on boundaries are found despite round-off, unlike an exact point-in-cell test)."""
    mesh = basis.mesh
    cent = mesh.p[:, mesh.t].mean(axis=1).T
    k = min(candidates, cent.shape[0])
    _, cand = cKDTree(cent).query(x.T, k=k)
    cand = cand.reshape(x.shape[1], k)
    cells = np.full(x.shape[1], -1)
    ref = np.zeros((2, x.shape[1]))
    quad = mesh.t.shape[0] == 4
    for c in range(k):      # a fixed handful of candidate rounds, each vectorized over all points
        todo = np.flatnonzero(cells < 0)
        if len(todo) == 0:
            break
        X = _affine_inverse(mesh, x[:, todo], cand[todo, c])
        if quad:
            inside = np.all((X >= -tol) & (X <= 1 + tol), axis=0)
        else:
            inside = (X[0] >= -tol) & (X[1] >= -tol) & (X[0] + X[1] <= 1 + tol)
        cells[todo[inside]] = cand[todo[inside], c]
        ref[:, todo[inside]] = X[:, inside]
    return cells, ref


def probe_matrix(basis, x: np.ndarray) -> tuple[sp.csr_matrix, np.ndarray]:
    """Sparse matrix mapping the DOF vector to [ux(points), uy(points)] (like
    ``CellBasis.probes`` but with a round-off tolerant cell search) and the found mask."""
    cells, ref = _locate(basis, x)
    found = cells >= 0
    xf, cf = ref[:, found], cells[found]
    npts = int(found.sum())
    phis = np.array([basis.elem.gbasis(basis.mapping, xf[:, :, None], k, tind=cf)[0]
                     for k in range(basis.Nbfun)])          # (Nbfun, 2, npts, 1)
    rows = np.tile(np.arange(2 * npts), basis.Nbfun)
    cols = basis.element_dofs[:, np.tile(cf, 2)].ravel()
    P = sp.coo_matrix((phis.ravel(), (rows, cols)), shape=(2 * npts, basis.N)).tocsr()
    return P, found


def line_profile(case, basis, u: np.ndarray, segment, npoints: int) -> dict[str, np.ndarray]:
    """Displacements sampled at ``npoints`` equally spaced points of a case line (NaN where
    the point lies outside every body)."""
    seg = np.asarray(segment, dtype=float)
    s = np.linspace(0.0, 1.0, npoints)
    pts = seg[0] + s[:, None] * (seg[1] - seg[0])
    disp = np.full((npoints, 2), np.nan)
    P, found = probe_matrix(basis, pts.T)
    if found.any():
        disp[found] = (P @ u).reshape(2, -1).T
    length = float(np.linalg.norm(seg[1] - seg[0]))
    return {"s": s * length, "x": pts[:, 0], "y": pts[:, 1], "ux": disp[:, 0], "uy": disp[:, 1]}


__all__ = ["vertex_stress", "interface_profile", "recover_tractions", "line_profile", "probe_matrix"]
