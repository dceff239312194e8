"""``fem.solve(case)``: static linear FEM with imperfect interface elements (002 Sec 2);
dynamic cases (a ``transmitted_energy`` wave measurement) or ``dynamics = newmark |
central`` go to the transient solver (``fem.transient``).

Bodies are meshed on one structured grid (``fem.mesh``: quads, or triangles for 45-degree
polygon edges), or by gmsh into curved 6-node triangles where shapes are curved
(``fem.gmsh_mesh``; 9-node ``ElementQuad2`` / 6-node ``ElementTriP2`` by default, linear
with ``order=1``), nodes duplicated along interfaces and joined by the 2n-node interface
elements of 002 Eq 15-19 (6-node with quadratic, 4-node with linear bulk elements),
assembled on jump unknowns in the interface frame. Finite Dn, Dt enter as stiffness;
perfect directions (inf) are imposed exactly by DOF elimination (``fem.constraints``).
Reported (002 Sec 3.1):

* ``stiffness``: displacement method k = P / (<u_load> - <u_support>) (002 Eq 43), with
  <.> the traction-consistent average over the measured sides;
* ``stiffness_energy``: energy method k = P^2 / (2 U) (002 Eq 45), U = bulk strain
  energy + interface energy (002 Eq 15);
* ``strain_energy`` (bulk), ``interface_energy``, ``load`` (P, N);
* ``bulk_modulus`` where the case measures it (000 Eq 34-35: K = 2 U / (d^2 V eps0^2), d = 3
  axisymmetric, d = 2 plane: the transverse bulk modulus);
* profiles ``interface_jump`` (first interface) and ``interface_jump[a|b]`` per pair
  (``s, x, y, jump_n, jump_t, traction_n, traction_t, Dn, Dt, weight``), one profile per
  case line keyed by its name (``s, x, y, ux, uy``); fields at mesh vertices for VTK
  (``position, displacement, stress`` (Voigt of the analysis), ``material, body``).

A ``BilinearNormalInterface`` (different Dn in tension and compression, e.g. perfect in
compression: 002 Fig 6-7 "inf/1") is solved by an active-set iteration over the
interface elements (002 Sec 3.1 suggests this iterative FEA), reported in
``diagnostics["history"]``.

Axisymmetric analyses integrate per radian and report whole-ring forces and energies
(x 2 pi). Units: mm, N, MPa.
"""
from __future__ import annotations

import math
import time

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from interfaces.case import InterfacePair
from interfaces.errors import CaseError, SolverError, check_flag, check_integer, check_number
from interfaces.laws import LinearInterface
from interfaces.materials import small_strain_refusal
from interfaces.result import Result
from interfaces.sparse import KINDS as SOLVER_KINDS
from interfaces.sparse import DirectSolver, SingularMatrixError

from .assembly import bulk_stiffness, jump_operator, jump_stiffness, mass_matrix
from .boundary import (apply_boundary_conditions, at_rest_gauge, free_rigid_motions, pin_rigid_modes,
                       rigid_modes)
from .constraints import build_elimination
from .discretization import discretize
from .interface_mesh import check_one_direction_straight, find_interface_elements, node_pairs, pair_index
from .measure import bulk_modulus as measure_bulk_modulus
from .measure import stiffness as measure_stiffness
from .mesh import default_element_size
from .post import interface_profile, line_profile, recover_tractions, vertex_stress

#: the highest bulk quadrature order scikit-fem has for every element (triangles: 19)
MAX_INTORDER = 19

OPTIONS = {
    "order": "bulk element order: 2 (ElementQuad2 + 6-node interface, default) or 1",
    "element_size": "target element size in mm, scalar or (hx, hy) in the bodies' frame",
    "h": "alias of element_size (the name used in case.discretization['fem'])",
    "intorder": "bulk quadrature order (default 2 * order)",
    "max_dofs": "refuse meshes above this many DOFs (default 5e6)",
    "line_points": "samples along each case line (default 201)",
    "jump_points": "Gauss points per interface element in the jump profile (default 3)",
    "pin_rigid_modes": "fix the fewest DOFs that remove unrestrained rigid motion, then report the "
                       "displacement without mean rigid motion in the mass metric, as a free body "
                       "comes to rest from rest (default True)",
    "fields": "store vertex fields and cells (default True)",
    "max_contact_iterations": "active-set iterations for bilinear normal laws (default 50)",
    "mesher": "auto (gmsh for curved shapes or off-grid polygon edges, else structured; default), structured or gmsh",
    "curved": "gmsh meshes: quadratic edges follow the curves (default True); False: straight-sided triangles",
    "solver": "sparse direct solver: auto (PARDISO when it loads, else SuperLU; default), pardiso or superlu",
    "dynamics": "static, newmark (average acceleration, implicit) or central (explicit differences); "
                "default newmark for a dynamic case (one with a transmitted_energy measurement), else static",
    "mass": "transient mass matrix: consistent (default for newmark) or lumped (default and required for central)",
    "dt": "transient time step in s (default: cfl x the stable limit for central, cfl x h / c for newmark)",
    "cfl": "time-step fraction (default 0.5 for newmark, 0.9 for central)",
    "duration": "transient end time in s (default measurements.transmitted_energy.duration)",
}


def _options(case, options: dict) -> dict:
    opts = case.options_for("fem", **options)
    h = opts.pop("h", None)
    if "h" in options or ("element_size" not in opts and h is not None):
        opts["element_size"] = h
    unknown = set(opts) - set(OPTIONS)
    if unknown:
        raise CaseError(f"fem option {sorted(unknown)[0]!r} is unknown; options: {', '.join(OPTIONS)}")
    order = opts.get("order", 2)
    if isinstance(order, bool) or order not in (1, 2):
        raise CaseError(f"fem option order must be 1 or 2, got {order!r}")
    out = {"order": int(order),
           "element_size": opts.get("element_size", default_element_size(case)),
           "intorder": check_integer("fem option intorder", opts.get("intorder", 2 * order),
                                     low=1, high=MAX_INTORDER),
           "max_dofs": check_number("fem option max_dofs", opts.get("max_dofs", 5e6), low=1.0),
           "line_points": check_integer("fem option line_points", opts.get("line_points", 201),
                                        low=2),
           "jump_points": check_integer("fem option jump_points", opts.get("jump_points", 3),
                                        low=1),
           "max_contact_iterations": check_integer("fem option max_contact_iterations",
                                                   opts.get("max_contact_iterations", 50), low=1)}
    for flag in ("pin_rigid_modes", "fields", "curved"):
        out[flag] = check_flag(f"fem option {flag}", opts.get(flag, True))
    out["solver"] = opts.get("solver", "auto")
    out["mesher"] = opts.get("mesher", "auto")
    if out["solver"] not in SOLVER_KINDS:
        raise CaseError(f"fem option solver must be one of {', '.join(SOLVER_KINDS)}, got {out['solver']!r}")
    dynamic = "transmitted_energy" in case.measurements
    out["dynamics"] = str(opts.get("dynamics", "newmark" if dynamic else "static"))
    if out["dynamics"] not in ("static", "newmark", "central"):
        raise CaseError(f"fem option dynamics must be static, newmark or central, got {out['dynamics']!r}")
    if dynamic and out["dynamics"] == "static":
        raise CaseError("fem option dynamics = 'static' cannot measure transmitted_energy (a wave); "
                        "use newmark or central")
    out["mass"] = str(opts.get("mass", "lumped" if out["dynamics"] == "central" else "consistent"))
    out["dt"] = None if opts.get("dt") is None else check_number("fem option dt", opts["dt"], low=0, low_open=True)
    out["cfl"] = check_number("fem option cfl", opts.get("cfl", 0.9 if out["dynamics"] == "central" else 0.5),
                              low=0, high=1, low_open=True)
    out["duration"] = None if opts.get("duration") is None else \
        check_number("fem option duration", opts["duration"], low=0, low_open=True)
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


def solve(case, **options) -> Result:
    """Static FEM solution of ``case`` (see module docstring); options override
    ``case.discretization["fem"]`` (``fem.solver.OPTIONS`` lists them)."""
    t_start = time.perf_counter()
    reason = small_strain_refusal(case, "fem")
    if reason is not None:
        raise CaseError(f"fem: {reason}")
    opts = _options(case, options)
    timings = {"mesh": 0.0, "assembly": 0.0, "constraints": 0.0, "solve": 0.0, "post": 0.0}
    warnings: list[str] = []
    if opts["dynamics"] != "static":
        from .transient import solve as transient_solve
        return transient_solve(case, opts, timings, warnings)

    t0 = time.perf_counter()
    disc = discretize(case, opts["element_size"], opts["order"], opts["intorder"], opts["max_dofs"],
                      opts["mesher"], bool(opts["curved"]))
    timings["mesh"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    moduli = [np.asarray(case.material_of(b.name).stiffness(case.analysis), dtype=float) for b in case.bodies]
    K_bulk = bulk_stiffness(disc.basis, disc.element_body, moduli, disc.thickness, disc.axisymmetric)
    ielems = _interface_elements(case, disc, warnings)
    f, presc_d, presc_v = apply_boundary_conditions(disc)
    meas = case.measurements.get("stiffness")
    pins: list[int] = []
    if opts["pin_rigid_modes"]:
        cand = (np.concatenate([disc.side_dofs(b, s) for b, s in meas["support"]])
                if meas and meas.get("support") else np.arange(disc.ndof))
        modes = rigid_modes(disc.basis.doflocs, disc.axisymmetric)
        pins = pin_rigid_modes(modes, presc_d, f, cand)
        if pins:
            warnings.append(f"pinned {len(pins)} DOF(s) against free rigid motion (loads balanced)")
    prescribed = np.concatenate([presc_d, pins]).astype(np.int64)
    values = np.concatenate([presc_v, np.zeros(len(pins))])
    timings["assembly"] = time.perf_counter() - t0

    # linear solve; with bilinear normal laws an active-set iteration on the element branches
    # (002 Sec 3.1: "an iterative FEA procedure could prevent interpenetration")
    bilinear = any(el.bilinear for el in ielems)
    history = []
    try:
        linear_solver = DirectSolver(opts["solver"], ordering="minimum_degree")
    except ValueError as e:         # 'pardiso' asked for but MKL missing
        raise CaseError(f"fem option solver: {e}") from None
    for iteration in range(opts["max_contact_iterations"] if bilinear else 1):
        sol = _linear_solution(disc, ielems, K_bulk, f, prescribed, values, timings, linear_solver)
        if not bilinear:
            break
        changed = sum(_update_branches(el, sol) for el in ielems if el.bilinear)
        history.append({"iteration": iteration + 1, "elements_switched": changed,
                        "compressed_elements": int(sum(np.sum(el.compressed) for el in ielems if el.bilinear))})
        if changed == 0:
            break
    else:
        raise SolverError(f"the bilinear normal-law iteration did not settle in {opts['max_contact_iterations']} "
                          "iterations (elements keep switching between tension and compression); raise "
                          "max_contact_iterations or refine the mesh")

    t0 = time.perf_counter()
    u, J, pairs = sol["u"], sol["J"], sol["pairs"]
    if pins:        # a free body: report it as it comes to rest from rest (no jump changes)
        u = at_rest_gauge(u, free_rigid_motions(modes, presc_d),
                          mass_matrix(disc, [case.material_of(b.name).rho for b in case.bodies], False))
    U_bulk = 0.5 * disc.ring * float(u @ (K_bulk @ u))
    U_int = 0.5 * disc.ring * float(J @ (sol["K_jump"] @ J))
    quantities = {"strain_energy": U_bulk, "interface_energy": U_int, "total_energy": U_bulk + U_int,
                  "external_work": 0.5 * disc.ring * float(f @ u)}
    if sol["negative_D"]:
        warnings.append(f"negative interface parameters (002 Eq 52 stiff interphase): saddle-point equilibrium "
                        f"with {sol['negative_pivots']} negative pivots; meaningful only above the "
                        "rigid-interphase limit")
        if U_bulk + U_int <= 0:
            warnings.append("total energy <= 0: the negative interface parameters exceed the stable limit, "
                            "the result is not physical")
    elif U_bulk < 0 or U_int < 0:
        # all moduli and interface parameters >= 0: a negative quadratic form is round-off
        # of an ill-conditioned matrix, not a result
        raise SolverError(f"the solve lost all precision (strain energy {U_bulk:.3g}, interface energy "
                          f"{U_int:.3g} N mm < 0): the material constants or interface parameters span "
                          "too many orders of magnitude for double precision; check them (e.g. a "
                          "modulus of 1e-12 MPa beside 1e4)")
    per_volume = (case.measurements.get("interface_energy") or {}).get("per_volume")
    if per_volume:      # 000 Fig 5: interfacial energy per unit specimen volume
        quantities["interface_energy_per_volume"] = U_int / float(per_volume)
    if "bulk_modulus" in case.measurements:      # 000 Eq 34-35, composite spheres / cylinders
        quantities["bulk_modulus"] = measure_bulk_modulus(case.measurements["bulk_modulus"], U_bulk + U_int,
                                                          case.analysis)
    if meas:
        f_int = K_bulk @ u + sol["jumps"].T @ (sol["K_jump"] @ J)
        quantities.update(measure_stiffness(disc, meas, f_int, u, U_bulk + U_int))
    profiles = {}
    for el in ielems:
        idx = pair_index(pairs, el.node_b)
        prof = interface_profile(el, sol["Jxy"][idx], sol["Txy"][idx], opts["jump_points"])
        profiles[f"interface_jump[{el.a}|{el.b}]"] = prof
        profiles.setdefault("interface_jump", prof)
    for name, seg in case.lines.items():
        profiles[name] = line_profile(case, disc.basis, u, seg, opts["line_points"])
    fields, cells = {}, None
    bm = disc.body_mesh
    if opts["fields"]:
        mat_names = list(case.materials)
        body_mat = np.array([mat_names.index(b.material) for b in case.bodies])
        fields = {"position": bm.p.T.copy(),
                  "displacement": u[disc.basis.nodal_dofs].T.copy(),
                  "stress": vertex_stress(disc.mesh, disc.element, u, bm.element_body, moduli, disc.axisymmetric),
                  "material": body_mat[bm.vertex_body],
                  "body": bm.vertex_body.copy()}
        cells = {"type": bm.cell_type, "connectivity": disc.mesh.t.T.copy()}
    timings["post"] = time.perf_counter() - t0
    timings["total"] = time.perf_counter() - t_start

    diagnostics = {
        "dofs": int(disc.ndof), "free_dofs": int(sol["free_dofs"]), "elements": int(disc.mesh.t.shape[1]),
        "cell_type": bm.cell_type, "mesher": disc.mesher, "order": disc.order, "element_size": opts["element_size"],
        "interface_elements": {f"{el.a}|{el.b}": int(len(el.xy)) for el in ielems},
        "interface_node_pairs": int(len(pairs.a)), "perfect_normal_nodes": int(pairs.perfect_n.sum()),
        "perfect_tangential_nodes": int(pairs.perfect_t.sum()), "prescribed_dofs": int(len(presc_d)),
        "pinned_dofs": [int(d) for d in pins], "backward_error": sol["backward_error"],
        "negative_pivots": sol["negative_pivots"], "solver": linear_solver.name,
        "stress_components": ["rr", "zz", "tt", "rz"] if disc.axisymmetric else ["xx", "yy", "xy"],
        "warnings": warnings,
    }
    if bilinear:
        diagnostics["iterations"] = len(history)
        diagnostics["history"] = history
    return Result(method="fem", case_name=case.name, quantities=quantities, fields=fields, cells=cells,
                  profiles=profiles, timings=timings, diagnostics=diagnostics)


def _linear_solution(disc, ielems, K_bulk, f, prescribed, values, timings, linear_solver) -> dict:
    """One linear solve with the elements' current Dn, Dt: interface operators, exact
    elimination (fem.constraints), the sparse direct solve, nodal jumps and recovered
    tractions. ``linear_solver`` (``interfaces.sparse.DirectSolver``) is kept across the
    active-set iterations, so PARDISO reuses its symbolic analysis."""
    t0 = time.perf_counter()
    pairs, jumps, K_jump, M_jump = _interface_operators(disc, ielems)
    elim = build_elimination(disc.ndof, pairs, prescribed=prescribed, values=values,
                             scale=max(np.abs(values).max(initial=0.0), 1e-300))
    Kr, fr = elim.reduce(K_bulk, f, jumps, K_jump)
    timings["constraints"] += time.perf_counter() - t0
    t0 = time.perf_counter()
    negative_D = any(np.any(el.finite_Dn < 0) or np.any(el.finite_Dt < 0) for el in ielems)
    q, backward_error, negative_pivots = _solve_symmetric(Kr, fr, negative_D, linear_solver)
    u = elim.expand(q)
    G, h = elim.jump_map(jumps)
    J = G @ q + h                   # nodal jumps (normal, tangential) u_b - u_a, without cancellation
    timings["solve"] += time.perf_counter() - t0
    to_xy = lambda v: v[:, :1] * pairs.n + v[:, 1:] * pairs.t          # noqa: E731 (n, t) -> (x, y)
    T = recover_tractions(K_bulk, u, f, pairs, M_jump) if len(pairs.a) else np.zeros((0, 2))
    return {"pairs": pairs, "jumps": jumps, "K_jump": K_jump, "u": u, "J": J, "T": T,
            "Jxy": to_xy(J.reshape(-1, 2)), "Txy": to_xy(T), "free_dofs": Kr.shape[0],
            "backward_error": backward_error, "negative_pivots": negative_pivots, "negative_D": negative_D}


def _update_branches(el, sol) -> int:
    """Active set of a bilinear normal law: an element in its tension branch switches to the
    compression branch when its mean normal jump is negative (interpenetration); an element in
    compression returns when its mean normal traction becomes tensile. Returns the switches."""
    n = el.xy.shape[1]
    w = np.array([0.5, 0.5]) if n == 2 else np.array([1.0, 4.0, 1.0]) / 6.0   # int N_i dxi / 2
    idx = pair_index(sol["pairs"], el.node_b)
    jn = sol["J"].reshape(-1, 2)[idx, 0] @ w
    tn = sol["T"][idx, 0] @ w
    new = np.where(el.compressed, tn < 0, jn < 0)
    changed = int(np.sum(new != el.compressed))
    el.set_compressed(new)
    return changed


def _interface_elements(case, disc, warnings):
    """Interface elements of all pairs, plus perfect bonds between touching bodies without a
    declared interface."""
    implicit = _implicit_pairs(case, disc.mesh, disc.element_body, disc.tol)
    for p in implicit:
        warnings.append(f"bodies {p.a!r} and {p.b!r} touch without a declared interface: bonded perfectly")
    pair_case = case if not implicit else _with_pairs(case, implicit)
    return find_interface_elements(pair_case, disc.mesh, disc.basis, disc.element_body, disc.order, disc.tol)


def _interface_operators(disc, ielems):
    """Node pairs, the jump operator, the jump-space stiffness and the unit-D matrix M."""
    pairs = node_pairs(ielems)
    check_one_direction_straight(pairs, ielems)
    jumps = jump_operator(pairs, disc.ndof)
    k = len(pairs.a)
    K_jump = sp.csr_matrix((2 * k, 2 * k))
    M_jump = sp.csr_matrix((2 * k, 2 * k))      # int N_i N_j ds (unit D), for traction recovery
    for el in ielems:   # one vectorized block per interface pair
        idx = pair_index(pairs, el.node_b)
        frames = np.stack([pairs.n[idx], pairs.t[idx]], axis=-1)         # (m, n, 2, 2) columns n, t
        K_jump = K_jump + jump_stiffness(el.xy, idx, frames, el.finite_Dn, el.finite_Dt,
                                         disc.thickness, disc.axisymmetric, k)
        one = np.ones(len(el.xy))
        M_jump = M_jump + jump_stiffness(el.xy, idx, frames, one, one, disc.thickness, disc.axisymmetric, k)
    return pairs, jumps, K_jump.tocsr(), M_jump.tocsr()


def _solve_symmetric(Kr: sp.csr_matrix, fr: np.ndarray, allow_indefinite: bool,
                     linear_solver: DirectSolver) -> tuple[np.ndarray, float, int]:
    """Sparse direct solve (``interfaces.sparse``: PARDISO LDL^T, or SuperLU in symmetric
    mode) with one step of iterative refinement. Returns the solution, the componentwise
    backward error and the number of negative pivots (-1 if SuperLU pivoted off the
    diagonal). Negative interface parameters (002 Eq 52) make the equilibrium a saddle
    point (``allow_indefinite``); otherwise a negative pivot means a material error."""
    if Kr.shape[0] == 0:
        return np.zeros(0), 0.0, 0
    try:
        linear_solver.factorize(Kr)
    except SingularMatrixError as e:
        raise SolverError(f"the stiffness matrix is singular ({e}): a body or part of it can move "
                          "freely; add supports or give debonded interfaces some stiffness") from None
    # symmetric pivoting keeps the inertia of Kr in the pivots (Sylvester's law)
    negative_pivots = linear_solver.negative_pivots()
    if negative_pivots > 0 and not allow_indefinite:
        raise SolverError(f"the stiffness matrix has {negative_pivots} negative pivots although all interface "
                          "parameters are >= 0: a body or part of it can move freely (add supports or give "
                          "debonded interfaces some stiffness), the elements are too coarse for the bodies (a "
                          "smaller element_size), or the material constants are not positive definite")
    q = linear_solver.solve(fr)
    q = q + linear_solver.solve(fr - Kr @ q)
    res = _backward_error(Kr, q, fr)
    if not np.all(np.isfinite(q)) or res > 1e-8:
        raise SolverError(f"linear solve failed (componentwise backward error {res:.2e}): the structure is "
                          "probably under-constrained (free rigid motion of a body, or a debonded part); "
                          "add supports or non-zero interface stiffness")
    return q, res, negative_pivots


def _with_pairs(case, extra):
    c = case.replace()
    c.interfaces = list(case.interfaces) + list(extra)
    return c


def _backward_error(A, x, b) -> float:
    """Componentwise backward error max_i |b - A x|_i / (|A| |x| + |b|)_i (Oettli-Prager):
    independent of the scaling of rows, so stiff interface unknowns do not distort it."""
    if A.shape[0] == 0:
        return 0.0
    A = sp.csr_matrix(A)
    r = np.abs(b - A @ x)
    absA = sp.csr_matrix((np.abs(A.data), A.indices, A.indptr), shape=A.shape)  # duplicates sum the same
    denom = absA @ np.abs(x) + np.abs(b)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(denom > 0, r / denom, np.where(r > 0, np.inf, 0.0))
    return float(ratio.max())


__all__ = ["solve", "OPTIONS"]
