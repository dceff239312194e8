"""Independent FEM reference for the perfect-interface DCB of 002 Sec 3.2 (Dn = inf).

With a perfect bond the specimen is one cracked orthotropic strip, so it needs no
interface element at all: a plain scikit-fem plane-stress model whose crack is a row
of duplicated nodes on y = h for x < a, the bonded part sharing its nodes. Nothing of
``fem/`` is used (mesh, constraints, loads, measurement, solver are all written here),
so the stiffness it gives is an independent check of ``fem.solve``'s perfect-interface
path and of the foundation stiffness kb back-computed from it (002 Eq 46-47).

Load as in ``cases.library.dcb``: uniform shear tractions +-P/(h W) on the left ends
of the arms, right end free (three DOFs pinned; the load is self-equilibrated, so the
pins carry nothing). k = P / opening, the opening being the traction-weighted average
of u_y over the upper left end minus that over the lower one (002 Eq 43).
Units: mm, N, MPa.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse.linalg as spla
from skfem import (Basis, BilinearForm, ElementQuad2, ElementVector, FacetBasis, LinearForm, MeshQuad, asm,
                   condense)
from skfem.helpers import ddot, sym_grad


def orthotropic_plane_stress(E_x: float, E_y: float, G_xy: float, nu_xy: float) -> np.ndarray:
    """Voigt (xx, yy, engineering xy) plane-stress stiffness, the inverse of the compliance
    [[1/E_x, -nu_xy/E_x, 0], [-nu_xy/E_x, 1/E_y, 0], [0, 0, 1/G_xy]]."""
    S = np.array([[1.0 / E_x, -nu_xy / E_x, 0.0], [-nu_xy / E_x, 1.0 / E_y, 0.0], [0.0, 0.0, 1.0 / G_xy]])
    return np.linalg.inv(S)


def cracked_strip_mesh(length: float, a: float, h: float, size: float) -> MeshQuad:
    """Two arms of depth h on [0, length], nodes shared on y = h only for x >= a."""
    nx, ny = round(length / size), round(h / size)
    if not all(abs(v / size - round(v / size)) < 1e-9 for v in (length, a, h)):
        raise ValueError(f"size = {size:g} must divide length, a and h (a node at the crack tip)")
    x = np.linspace(0.0, length, nx + 1)
    y = np.linspace(0.0, 2.0 * h, 2 * ny + 1)
    X, Y = np.meshgrid(x, y, indexing="ij")
    node = np.arange(X.size).reshape(X.shape)                    # node[i, j]
    cracked = np.flatnonzero(x < a - 1e-9 * size)
    twin = X.size + np.arange(len(cracked))                      # upper-face copies of y = h, x < a
    p = np.hstack([np.vstack([X.ravel(), Y.ravel()]), np.vstack([x[cracked], np.full(len(cracked), h)])])
    upper_node = node.copy()
    upper_node[cracked, ny] = twin
    i, j = np.meshgrid(np.arange(nx), np.arange(2 * ny), indexing="ij")
    i, j = i.ravel(), j.ravel()
    corners = lambda n: np.vstack([n[i, j], n[i + 1, j], n[i + 1, j + 1], n[i, j + 1]])  # noqa: E731
    t = np.where(j >= ny, corners(upper_node), corners(node))   # upper arm: its own face on y = h
    return MeshQuad(p, t)


def dcb_perfect_stiffness(E_x: float, E_y: float, G_xy: float, nu_xy: float, length: float = 50.0,
                          a: float = 25.0, h: float = 0.6, W: float = 10.0, size: float = 0.1) -> float:
    """Load-point stiffness (N/mm) of the perfectly bonded DCB, biquadratic quads of edge ``size``."""
    C = orthotropic_plane_stress(E_x, E_y, G_xy, nu_xy)
    mesh = cracked_strip_mesh(length, a, h, size)
    basis = Basis(mesh, ElementVector(ElementQuad2()))

    def stress(e):
        ev = [e[0, 0], e[1, 1], e[0, 1] + e[1, 0]]
        s = [sum(C[r, c] * ev[c] for c in range(3)) for r in range(3)]
        return np.array([[s[0], s[2]], [s[2], s[1]]])

    @BilinearForm
    def elasticity(u, v, w):
        return W * ddot(stress(sym_grad(u)), sym_grad(v))

    @LinearForm
    def unit_ty(v, w):
        return W * v[1]

    K = asm(elasticity, basis)
    tol = 1e-9 * size
    end = {arm: FacetBasis(mesh, basis.elem, facets=mesh.facets_satisfying(
        lambda X, lo=lo: (np.abs(X[0]) < tol) & (X[1] > lo - tol) & (X[1] < lo + h + tol)))
        for arm, lo in (("lower", 0.0), ("upper", h))}
    w = {arm: asm(unit_ty, fb) for arm, fb in end.items()}            # work of a unit traction t_y
    P = 1.0
    f = (P / h) * (w["upper"] / W - w["lower"] / W)                    # t_y = +-P/(h W), times W
    right = basis.get_dofs(lambda X: (np.abs(X[0] - length) < tol) & (np.abs(X[1] - h) < tol))
    bottom = basis.get_dofs(lambda X: (np.abs(X[0] - length) < tol) & (np.abs(X[1]) < tol))
    pinned = np.concatenate([right.nodal["u^1"], right.nodal["u^2"], bottom.nodal["u^1"]])
    u = np.zeros(K.shape[0])
    u[np.setdiff1d(np.arange(K.shape[0]), pinned)] = spla.spsolve(*condense(K, f, D=pinned, expand=False))
    mean = {arm: float(w[arm] @ u) / (W * h) for arm in w}
    return P / (mean["upper"] - mean["lower"])
