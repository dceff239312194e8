"""``fem.solve(case)``: static linear FEM with imperfect interface elements (002 Sec 2).

Bodies are meshed with structured quads (9-node ``ElementQuad2`` by default, 4-node
``ElementQuad1`` with ``order=1``), nodes duplicated along interfaces and joined by the
2n-node interface elements of 002 Eq 15-19 (6-node with quadratic, 4-node with linear
bulk elements). Finite Dn, Dt enter as stiffness blocks; perfect directions (inf) are
imposed exactly by DOF elimination (``fem.constraints``). Reported (002 Sec 3.1):

* ``stiffness``: displacement method k = P / (<u_load> - <u_support>) (002 Eq 43), with
  <.> the traction-consistent average over the measured sides;
* ``stiffness_energy``: energy method k = P^2 / (2 U) (002 Eq 45), U = bulk strain
  energy + interface energy (002 Eq 15);
* ``strain_energy`` (bulk), ``interface_energy``, ``load`` (P, N);
* profiles ``interface_jump`` (first interface) and ``interface_jump[a|b]`` per pair;
  ``line:<name>`` for every case line; fields at mesh vertices for VTK.

Axisymmetric analyses integrate per radian and report whole-ring forces and energies
(x 2 pi). Units: mm, N, MPa.
"""
from __future__ import annotations

import math
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.spatial import cKDTree
from skfem import CellBasis, ElementQuad1, ElementQuad2, ElementTriP1, ElementTriP2, ElementVector, MeshQuad, MeshTri

from interfaces.case import COMPONENTS, InterfacePair
from interfaces.errors import CaseError, SolverError
from interfaces.laws import LinearInterface
from interfaces.result import Result

from .assembly import bulk_stiffness, facet_load, jump_operator, jump_stiffness
from .constraints import build_elimination
from .interface_mesh import check_one_direction_straight, find_interface_elements, node_pairs, pair_index
from .mesh import build_mesh, default_element_size
from .post import interface_profile, line_profile, vertex_stress

OPTIONS = {
    "order": "bulk element order: 2 (ElementQuad2 + 6-node interface, default) or 1",
    "element_size": "target element size in mm, scalar or (hx, hy) in the bodies' frame",
    "h": "alias of element_size (the name used in case.discretization['fem'])",
    "intorder": "bulk quadrature order (default 2 * order)",
    "max_dofs": "refuse meshes above this many DOFs (default 5e6)",
    "line_points": "samples along each case line (default 201)",
    "jump_points": "Gauss points per interface element in the jump profile (default 3)",
    "pin_rigid_modes": "fix the fewest DOFs that remove unrestrained rigid motion (default True)",
    "fields": "store vertex fields and cells (default True)",
}


def _options(case, options: dict) -> dict:
    opts = case.options_for("fem", **options)
    h = opts.pop("h", None)
    if "h" in options or ("element_size" not in opts and h is not None):
        opts["element_size"] = h
    unknown = set(opts) - set(OPTIONS)
    if unknown:
        raise CaseError(f"fem option {sorted(unknown)[0]!r} is unknown; options: "
                        + "; ".join(f"{k}: {v}" for k, v in OPTIONS.items()))
    order = opts.get("order", 2)
    if order not in (1, 2):
        raise CaseError(f"fem option order must be 1 or 2, got {order!r}")
    out = {"order": int(order),
           "element_size": opts.get("element_size", default_element_size(case)),
           "intorder": int(opts.get("intorder", 2 * order)),
           "max_dofs": float(opts.get("max_dofs", 5e6)),
           "line_points": int(opts.get("line_points", 201)),
           "jump_points": int(opts.get("jump_points", 3)),
           "pin_rigid_modes": bool(opts.get("pin_rigid_modes", True)),
           "fields": bool(opts.get("fields", True))}
    if out["line_points"] < 2 or out["jump_points"] < 1:
        raise CaseError("fem options line_points must be >= 2 and jump_points >= 1")
    return out


def _implicit_pairs(case, mesh, element_body, tol) -> list[InterfacePair]:
    """Bodies that touch without a declared interface are bonded perfectly."""
    bf = mesh.boundary_facets()
    body = element_body[mesh.f2t[0, bf]]
    mid = mesh.p[:, mesh.facets[:, bf]].mean(axis=1).T
    pairs = cKDTree(mid).query_pairs(tol, output_type="ndarray")
    if len(pairs) == 0:
        return []
    bp = np.unique(np.sort(body[pairs], axis=1), axis=0)
    bp = bp[bp[:, 0] != bp[:, 1]]
    names = [b.name for b in case.bodies]
    declared = {frozenset((p.a, p.b)) for p in case.interfaces}
    return [InterfacePair(names[i], names[j], LinearInterface(math.inf, math.inf))
            for i, j in bp if frozenset((names[i], names[j])) not in declared]


def _body_filter(case, body_name):
    """Index of the named body, or None for "*" (the side of the bounding box of all bodies)."""
    return None if body_name == "*" else [b.name for b in case.bodies].index(body_name)


def _side_facets(case, mesh, element_body, body_name, side, tol):
    k = _body_filter(case, body_name)
    bf = mesh.boundary_facets()
    if k is not None:
        bf = bf[element_body[mesh.f2t[0, bf]] == k]
    v = mesh.facets[:, bf]
    on = (case.side_points_mask(body_name, side, mesh.p[:, v[0]].T, tol)
          & case.side_points_mask(body_name, side, mesh.p[:, v[1]].T, tol))
    if not on.any():
        raise CaseError(f"side {side!r} of body {body_name!r} has no mesh facets")
    return bf[on]


def _side_dofs(case, basis, dof_body, body_name, side, tol):
    k = _body_filter(case, body_name)
    on = case.side_points_mask(body_name, side, basis.doflocs.T, tol)
    if k is not None:
        on &= dof_body == k
    return np.flatnonzero(on)


def _rigid_modes(doflocs: np.ndarray, axisymmetric: bool) -> np.ndarray:
    """Infinitesimal rigid motions as full DOF vectors (columns): x, y translations and a
    rotation about the centroid (axisymmetric: the axial translation only)."""
    comp = np.arange(doflocs.shape[1]) % 2            # x-DOF even, y-DOF odd (ElementVector)
    ty = (comp == 1).astype(float)
    if axisymmetric:
        return ty[:, None]
    tx = (comp == 0).astype(float)
    c = doflocs.mean(axis=1)
    rot = np.where(comp == 0, -(doflocs[1] - c[1]), doflocs[0] - c[0])
    return np.stack([tx, ty, rot], axis=1)


def _pin_rigid_modes(modes, prescribed, f, candidates):
    """DOFs to fix so that no rigid mode is left free, provided the loads do no work on it."""
    pins = []
    fixed = list(prescribed)
    for _ in range(modes.shape[1]):
        R = modes[np.asarray(fixed, dtype=np.int64)] if fixed else np.zeros((0, modes.shape[1]))
        _, sv, vt = np.linalg.svd(np.vstack([R, np.zeros((1, modes.shape[1]))]), full_matrices=True)
        rank = int(np.sum(sv > 1e-9 * max(1.0, sv.max(initial=0.0))))
        null = vt[rank:]
        if len(null) == 0:
            break
        r = modes @ null[0]
        r /= np.abs(r).max()
        work = abs(f @ r)
        if work > 1e-9 * max(np.abs(f).sum(), 1e-300):
            raise SolverError("the boundary conditions leave a rigid motion free and the loads are not "
                              f"balanced in it (net work {work:g}); fix the body with a 'fixed' condition")
        cand = candidates if np.abs(r[candidates]).max(initial=0.0) > 0.1 else np.arange(len(r))
        d = int(cand[np.argmax(np.abs(r[cand]))])
        pins.append(d)
        fixed.append(d)
    return pins


def solve(case, **options) -> Result:
    """Static FEM solution of ``case`` (see module docstring); options override
    ``case.discretization["fem"]`` (``fem.solver.OPTIONS`` lists them)."""
    t_start = time.perf_counter()
    opts = _options(case, options)
    order = opts["order"]
    axisym = case.analysis == "axisymmetric"
    thickness = 1.0 if axisym else case.thickness
    ring = 2.0 * math.pi if axisym else 1.0
    timings = {}
    warnings = []

    # ---- mesh and DOFs -------------------------------------------------------------
    t0 = time.perf_counter()
    bm = build_mesh(case, opts["element_size"])
    if bm.p.shape[1] * (8 if order == 2 else 2) > opts["max_dofs"]:
        raise CaseError(f"element_size = {opts['element_size']} gives about {bm.p.shape[1] * 8:.3g} DOFs, "
                        f"above max_dofs = {opts['max_dofs']:.3g}: use a larger element_size or raise max_dofs")
    if bm.cell_type == "quad":
        mesh = MeshQuad(bm.p, bm.t)
        element = ElementVector(ElementQuad2() if order == 2 else ElementQuad1())
    else:
        mesh = MeshTri(bm.p, bm.t)
        element = ElementVector(ElementTriP2() if order == 2 else ElementTriP1())
    basis = CellBasis(mesh, element, intorder=opts["intorder"])
    ndof = basis.N
    dof_body = np.empty(ndof, dtype=np.int64)
    dof_body[basis.element_dofs] = bm.element_body[None, :]
    tol = 1e-9 * bm.size
    timings["mesh"] = time.perf_counter() - t0

    # ---- assembly ------------------------------------------------------------------
    t0 = time.perf_counter()
    moduli = [np.asarray(case.material_of(b.name).stiffness(case.analysis), dtype=float) for b in case.bodies]
    K_bulk = bulk_stiffness(mesh, element, opts["intorder"], bm.element_body, moduli, thickness, axisym, ndof)
    implicit = _implicit_pairs(case, mesh, bm.element_body, tol)
    for p in implicit:
        warnings.append(f"bodies {p.a!r} and {p.b!r} touch without a declared interface: bonded perfectly")
    pair_case = case if not implicit else _with_pairs(case, implicit)
    ielems = find_interface_elements(pair_case, mesh, basis, bm.element_body, order, tol)
    pairs = node_pairs(ielems)
    check_one_direction_straight(pairs, ielems)
    jumps = jump_operator(pairs, ndof)
    K_jump = sp.csr_matrix((2 * len(pairs.a), 2 * len(pairs.a)))
    for el in ielems:   # one vectorized block per interface pair
        idx = pair_index(pairs, el.node_b)
        frames = np.stack([pairs.n[idx], pairs.t[idx]], axis=-1)         # (m, n, 2, 2) columns n, t
        K_jump = K_jump + jump_stiffness(el.xy, idx, frames, el.finite_Dn, el.finite_Dt,
                                         thickness, axisym, len(pairs.a))

    f = np.zeros(ndof)
    presc_d, presc_v = [], []
    for i, bc in enumerate(case.boundary_conditions):
        where = f"boundary_conditions[{i}]"
        if bc.kind == "traction":
            tr = np.zeros(2)
            comps = bc.components if len(bc.value) == len(bc.components) else COMPONENTS[:2]
            for c, v in zip(comps, bc.value):
                tr[COMPONENTS.index(c)] = v
            facets = _side_facets(case, mesh, bm.element_body, bc.body, bc.side, tol)
            f += facet_load(mesh, element, facets, tr, thickness, axisym, opts["intorder"])
        elif bc.kind in ("fixed", "displacement", "deformation_gradient"):
            dofs = _side_dofs(case, basis, dof_body, bc.body, bc.side, tol)
            if len(dofs) == 0:
                raise CaseError(f"{where}: side {bc.side!r} of body {bc.body!r} has no mesh nodes")
            comp = dofs % 2
            vals = bc.displacement_at(basis.doflocs[:, dofs].T)[np.arange(len(dofs)), comp]
            keep = np.isin(comp, bc.component_indices())
            presc_d.append(dofs[keep])
            presc_v.append(vals[keep])
        else:
            raise CaseError(f"{where}.kind: fem is static; a {bc.kind!r} condition needs a dynamic "
                            "method (mpm), or use 'displacement'")
    presc_d = np.concatenate(presc_d) if presc_d else np.zeros(0, dtype=np.int64)
    presc_v = np.concatenate(presc_v) if presc_v else np.zeros(0)
    timings["assembly"] = time.perf_counter() - t0

    # ---- exact constraints: perfect directions, supports, rigid modes --------------
    t0 = time.perf_counter()
    meas = case.measurements.get("stiffness")
    cand = np.arange(ndof)
    if meas and meas.get("support"):
        cand = np.concatenate([_side_dofs(case, basis, dof_body, b, s, tol) for b, s in meas["support"]])
    pins = []
    if opts["pin_rigid_modes"]:
        pins = _pin_rigid_modes(_rigid_modes(basis.doflocs, axisym), presc_d, f, cand)
        if pins:
            warnings.append(f"pinned {len(pins)} DOF(s) against free rigid motion (loads balanced)")
    scale = max(np.abs(presc_v).max(initial=0.0), 1e-300)
    elim = build_elimination(ndof, pairs, prescribed=np.concatenate([presc_d, pins]).astype(np.int64),
                             values=np.concatenate([presc_v, np.zeros(len(pins))]), scale=scale)
    Kr, fr = elim.reduce(K_bulk, f, jumps, K_jump)
    timings["constraints"] = time.perf_counter() - t0

    # ---- solve ---------------------------------------------------------------------
    t0 = time.perf_counter()
    if Kr.shape[0] == 0:
        q = np.zeros(0)
    else:
        try:
            # symmetric mode + minimum degree on A^T + A: ~20x faster than the default for this SPD K
            lu = spla.splu(Kr.tocsc(), permc_spec="MMD_AT_PLUS_A",
                           options={"SymmetricMode": True, "DiagPivotThresh": 0.01})
            q = lu.solve(fr)
            q = q + lu.solve(fr - Kr @ q)           # one step of iterative refinement
        except RuntimeError as e:  # SuperLU: exactly singular
            raise SolverError(f"the stiffness matrix is singular ({e}): a body or part of it can move "
                              "freely; add supports or give debonded interfaces some stiffness") from None
    res = _backward_error(Kr, q, fr)
    if not np.all(np.isfinite(q)) or res > 1e-8:
        raise SolverError(f"linear solve failed (componentwise backward error {res:.2e}): the structure is "
                          "probably under-constrained (free rigid motion of a body, or a debonded part); "
                          "add supports or non-zero interface stiffness")
    u = elim.expand(np.atleast_1d(q))
    G, h = elim.jump_map(jumps)
    J = G @ q + h                   # nodal jumps (normal, tangential) u_b - u_a, without cancellation
    timings["solve"] = time.perf_counter() - t0

    # ---- quantities ----------------------------------------------------------------
    t0 = time.perf_counter()
    U_bulk = 0.5 * ring * float(u @ (K_bulk @ u))
    U_int = 0.5 * ring * float(J @ (K_jump @ J))
    quantities = {"strain_energy": U_bulk, "interface_energy": U_int, "total_energy": U_bulk + U_int,
                  "external_work": 0.5 * ring * float(f @ u)}
    if meas:
        f_int = K_bulk @ u + jumps.T @ (K_jump @ J)
        quantities.update(_stiffness(case, meas, mesh, element, basis, dof_body, bm.element_body, f_int, u,
                                     thickness, axisym, ring, opts["intorder"], tol, U_bulk + U_int))
    profiles = {}
    for el in ielems:
        idx = pair_index(pairs, el.node_b)
        Jxy = J.reshape(-1, 2)[:, :1] * pairs.n + J.reshape(-1, 2)[:, 1:] * pairs.t   # back to x, y
        prof = interface_profile(el, Jxy[idx], opts["jump_points"])
        profiles[f"interface_jump[{el.a}|{el.b}]"] = prof
        if "interface_jump" not in profiles:
            profiles["interface_jump"] = prof
    for name, seg in case.lines.items():
        profiles[name] = line_profile(case, basis, u, seg, opts["line_points"])
    fields, cells = {}, None
    if opts["fields"]:
        mat_names = list(case.materials)
        body_mat = np.array([mat_names.index(b.material) for b in case.bodies])
        fields = {"position": mesh.p.T.copy(),
                  "displacement": u[basis.nodal_dofs].T.copy(),
                  "stress": vertex_stress(mesh, element, u, bm.element_body, moduli, axisym),
                  "material": body_mat[bm.vertex_body],
                  "body": bm.vertex_body.copy()}
        cells = {"type": bm.cell_type, "connectivity": mesh.t.T.copy()}
    timings["post"] = time.perf_counter() - t0
    timings["total"] = time.perf_counter() - t_start

    diagnostics = {
        "dofs": int(ndof), "free_dofs": int(Kr.shape[0]), "elements": int(mesh.t.shape[1]),
        "interface_elements": {f"{el.a}|{el.b}": int(len(el.xy)) for el in ielems},
        "order": order, "element_size": opts["element_size"], "interface_node_pairs": int(len(pairs.a)),
        "perfect_normal_nodes": int(pairs.perfect_n.sum()), "perfect_tangential_nodes": int(pairs.perfect_t.sum()), "prescribed_dofs": int(len(presc_d)),
        "pinned_dofs": [int(d) for d in pins], "backward_error": float(res),
        "stress_components": ["rr", "zz", "tt", "rz"] if axisym else ["xx", "yy", "xy"],
        "warnings": warnings,
    }
    return Result(method="fem", case_name=case.name, quantities=quantities, fields=fields, cells=cells,
                  profiles=profiles, timings=timings, diagnostics=diagnostics)


def _with_pairs(case, extra):
    c = case.replace()
    c.interfaces = list(case.interfaces) + list(extra)
    return c


def _backward_error(A, x, b) -> float:
    """Componentwise backward error max_i |b - A x|_i / (|A| |x| + |b|)_i (Oettli-Prager):
    independent of the scaling of rows, so stiff interface unknowns do not distort it."""
    if A.shape[0] == 0:
        return 0.0
    r = np.abs(b - A @ x)
    denom = abs(A) @ np.abs(x) + np.abs(b)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(denom > 0, r / denom, np.where(r > 0, np.inf, 0.0))
    return float(ratio.max())


def _stiffness(case, meas, mesh, element, basis, dof_body, element_body, f_int, u, thickness, axisym, ring,
               intorder, tol, U_total):
    """002 Eq 43 (displacement method) and Eq 45 (energy method)."""
    unit = case.stiffness_direction()

    def average(sides):
        w = sum(facet_load(mesh, element, _side_facets(case, mesh, element_body, b, s, tol), unit,
                           thickness, axisym, intorder) for b, s in sides)
        return float(w @ u) / float(w @ unit[np.arange(len(w)) % 2])

    load = meas.get("load", [])
    if not load:
        raise CaseError("measurements.stiffness.load must list at least one [body, side]")
    load_dofs = np.unique(np.concatenate([_side_dofs(case, basis, dof_body, b, s, tol) for b, s in load]))
    P = ring * float(f_int[load_dofs] @ unit[load_dofs % 2])
    u_load = average(load)
    u_sup = average(meas["support"]) if meas.get("support") else 0.0
    delta = u_load - u_sup
    out = {"load": P, "displacement_load": u_load, "displacement_support": u_sup}
    out["stiffness"] = P / delta if delta != 0 else math.nan
    out["stiffness_energy"] = P * P / (2.0 * U_total) if U_total > 0 else math.nan
    return out


__all__ = ["solve", "OPTIONS"]
