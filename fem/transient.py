"""Transient FEM with imperfect interface elements: M u'' + K u = f(t) (002 Sec 3.3).

The same discretization as the static solver (``fem.solver``: scikit-fem bulk elements,
002 Eq 15-19 interface elements, perfect directions and prescribed displacements by
exact DOF elimination u = T q + g(t), ``fem.constraints``) with a mass matrix and a
time integrator:

* mass ``consistent`` (int rho N_i N_j dV, scikit-fem) or ``lumped`` (row sums: positive
  for Q1 / Q2 / P1 elements, refused where a row sum is not);
* ``newmark``: Newmark average acceleration (beta = 1/4, gamma = 1/2; implicit,
  unconditionally stable, conserves the energy of a linear system exactly), the
  effective matrix T^T (K + 4 M / dt^2) T factorised once;
* ``central``: explicit central differences (lumped mass), stable for
  dt <= 2 / omega_max with omega_max^2 the largest eigenvalue of (K_r, M_r); a larger
  dt is refused with a message naming the limit.

Loads follow the case's ramps (``BoundaryCondition.ramp_factor``: linear, cosine = the
pulse of 002 Eq 49): tractions f(t) = R(t) f, prescribed displacements
g(t) = sum_k R_k(t) g_k; the prescribed DOFs' velocities and accelerations follow from
the integrator (no derivative of the ramp is needed). Energies: kinetic 1/2 v.M v,
strain 1/2 u.K u, interface 1/2 J.K_J J, and the work of the loads and of the
reactions at prescribed DOFs (trapezoidal in time, exact for Newmark average
acceleration). Stress gauges of ``measurements.transmitted_energy`` give the 002
Sec 3.3 measures (``interfaces.wave_gauges``). The bilinear law of 002 Fig 10 "NL"
(Dn in tension, perfect in compression) runs with central differences: the tension
spring is in K, and node pairs that would interpenetrate are closed on the explicit
step by forward-increment Lagrange multipliers (``_close``); other bilinear laws, and
bilinear laws with Newmark, are refused.
Units: mm, N, MPa, s, tonne/mm^3.
"""
from __future__ import annotations

import dataclasses
import math
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from skfem import CellBasis

from interfaces.errors import CaseError, SolverError
from interfaces.result import Result
from interfaces.sparse import DirectSolver
from interfaces.wave_gauges import (GAUGE_KEYS, body_at, gauge_spec, longitudinal_impedance,
                                    pulse_measures, reflection_arrival)

from .assembly import bulk_stiffness, mass_matrix
from .boundary import apply_boundary_conditions
from .constraints import build_elimination
from .discretization import discretize
from .interface_mesh import pair_index
from .post import line_profile

SCHEMES = ("newmark", "central")
MASSES = ("consistent", "lumped")
#: history samples kept in the Result
HISTORY_POINTS = 2000


def ramp_derivatives(bc, t: float) -> tuple[float, float, float]:
    """R, dR/dt, d2R/dt2 of a condition's ramp (``BoundaryCondition.ramp_factor``):
    linear t / T (right derivatives at the kinks t = 0, T) or the cosine
    (1 - cos(pi t / T)) / 2 of 002 Eq 49; a condition without ramp time applies at once."""
    T = bc.ramp_time
    if T is None or t >= T:
        return 1.0, 0.0, 0.0
    if t < 0.0:
        return 0.0, 0.0, 0.0
    if bc.ramp == "linear":
        return t / T, 1.0 / T, 0.0
    w = math.pi / T
    return 0.5 * (1.0 - math.cos(w * t)), 0.5 * w * math.sin(w * t), 0.5 * w * w * math.cos(w * t)


@dataclasses.dataclass
class Loads:
    """f(t) = sum_i R_i(t) f_i and g(t) = sum_k R_k(t) g_k (one term per condition)."""

    f: list
    f_ramps: list
    g: list
    g_ramps: list

    def force(self, t: float, n: int) -> np.ndarray:
        out = np.zeros(n)
        for fi, bc in zip(self.f, self.f_ramps):
            out += float(bc.ramp_factor(t)) * fi
        return out

    def prescribed(self, t: float, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """g(t) and its first two time derivatives."""
        out = np.zeros((3, n))
        for gk, bc in zip(self.g, self.g_ramps):
            out += np.outer(ramp_derivatives(bc, t), gk)
        return out[0], out[1], out[2]

    def kinks(self) -> list[float]:
        """Times where a prescribed velocity jumps (ends of linear ramps)."""
        return sorted({bc.ramp_time for bc in self.g_ramps
                       if bc.ramp == "linear" and bc.ramp_time is not None})


def _loads_and_elimination(disc, pairs):
    """Per-condition load vectors and prescribed-displacement fields, and the elimination
    (its T is the same for every condition: the prescribed DOF set does not change)."""
    for i, bc in enumerate(disc.case.boundary_conditions):
        if bc.kind == "velocity":
            raise CaseError(f"boundary_conditions[{i}].kind: transient fem prescribes displacements, "
                            "not velocities; give the displacement history (kind 'displacement' with a ramp)")
    f_all, presc_all, _ = apply_boundary_conditions(disc)
    elim = build_elimination(disc.ndof, pairs, prescribed=presc_all, values=np.zeros(len(presc_all)))
    loads = Loads([], [], [], [])
    for bc in disc.case.boundary_conditions:
        sub = dataclasses.replace(disc, case=disc.case.replace(boundary_conditions=[bc]))
        f, d, v = apply_boundary_conditions(sub)
        if np.any(f != 0.0):
            loads.f.append(f)
            loads.f_ramps.append(bc)
        if np.any(v != 0.0):
            values = np.zeros(len(presc_all))
            pos = {int(dof): k for k, dof in enumerate(presc_all)}
            for dof, val in zip(d, v):
                values[pos[int(dof)]] = val
            g = build_elimination(disc.ndof, pairs, prescribed=presc_all, values=values,
                                  scale=max(np.abs(values).max(), 1e-300)).g
            loads.g.append(g)
            loads.g_ramps.append(bc)
    return elim, loads, f_all


def gauge_rows(disc, spec: dict) -> dict:
    """Row vectors s with sigma_xx = s . u, averaged over points (x_gauge, y) across the
    middle half of the specimen, each evaluated just left and right of x_gauge
    (centred when the gauge lies on an element edge)."""
    case, mesh = disc.case, disc.mesh
    lo, hi = case.bounds()
    mid, quarter = 0.5 * (lo[1] + hi[1]), 0.25 * (hi[1] - lo[1])
    centres = mesh.p[:, mesh.t].mean(axis=1)
    ys = np.unique(np.round(centres[1][np.abs(centres[1] - mid) <= quarter], 9))
    if ys.size == 0:
        ys = np.array([mid])
    h = float(np.min(np.ptp(mesh.p[:, mesh.t], axis=1)[0]))
    finder = mesh.element_finder()
    rows = {}
    for key in GAUGE_KEYS:
        xg = spec[key]
        row = np.zeros(disc.ndof)
        pts = [(xg + s * 1e-6 * h, y) for s in (-1.0, 1.0) for y in ys]
        for x, y in pts:
            e = finder(np.array([x]), np.array([y]))
            X = mesh.mapping().invF(np.array([[x], [y]])[:, :, None], tind=e)[:, 0, :]
            b = CellBasis(mesh, disc.element, quadrature=(X, np.array([1.0])), elements=e)
            C = np.asarray(case.material_of(case.bodies[disc.element_body[e[0]]].name).stiffness(case.analysis))
            for i, (phi,) in enumerate(b.basis):
                g = np.asarray(phi.grad)[:, :, 0, 0]
                sxx = C[0, 0] * g[0, 0] + C[0, 1] * g[1, 1] + C[0, -1] * (g[0, 1] + g[1, 0])
                row[b.element_dofs[i, 0]] += sxx / len(pts)
        rows[key] = row
    return rows


def _factorized(A: sp.spmatrix) -> DirectSolver:
    """The project's run-time-chosen direct solver (interfaces.sparse), factorised once."""
    solver = DirectSolver()
    solver.factorize(A)
    return solver


def stable_time_step(Kr: sp.csr_matrix, Mr: sp.csr_matrix) -> float:
    """2 / omega_max of the reduced system (largest generalized eigenvalue, ARPACK)."""
    lu = _factorized(Mr)
    Minv = spla.LinearOperator(Mr.shape, matvec=lu.solve, dtype=float)
    lam = spla.eigsh(Kr, k=1, M=Mr, Minv=Minv, which="LM", tol=1e-8, return_eigenvectors=False,
                     maxiter=20000)
    return 2.0 / math.sqrt(float(lam.max()))


def _reduced(K_bulk, jumps, K_jump, elim, M):
    """K = K_bulk + J^T K_J J (u space) and the reduced T^T K T, T^T M T."""
    K_int = (jumps.T @ (K_jump @ jumps)).tocsr()
    K = (K_bulk + K_int).tocsr()
    T = elim.T
    Kr = (T.T @ (K @ T)).tocsr()
    Mr = (T.T @ (M @ T)).tocsr()
    return K, Kr, Mr


def solve(case, opts: dict, timings: dict, warnings: list) -> Result:
    """Transient solution of ``case`` (module docstring); ``opts`` from ``fem.solver``."""
    from .solver import _interface_elements, _interface_operators

    t_start = time.perf_counter()
    scheme, mass_kind = opts["dynamics"], opts["mass"]
    if mass_kind not in MASSES:
        raise CaseError(f"fem option mass must be one of {', '.join(MASSES)}, got {mass_kind!r}")
    if scheme == "central" and mass_kind != "lumped":
        raise CaseError("fem option dynamics = 'central' (explicit) needs mass = 'lumped'")
    duration = opts["duration"] if opts["duration"] is not None else \
        (case.measurements.get("transmitted_energy") or {}).get("duration")
    if duration is None:
        raise CaseError("fem option duration (s) is required for a transient run (or "
                        "measurements.transmitted_energy.duration)")
    duration = float(duration)
    disc = discretize(case, opts["element_size"], opts["order"], opts["intorder"], opts["max_dofs"])
    moduli = [np.asarray(case.material_of(b.name).stiffness(case.analysis), float) for b in case.bodies]
    K_bulk = bulk_stiffness(disc.basis, disc.element_body, moduli, disc.thickness, disc.axisymmetric)
    ielems = _interface_elements(case, disc, warnings)
    _check_bilinear(ielems, scheme)
    pairs, jumps, K_jump, _ = _interface_operators(disc, ielems)
    elim, loads, _ = _loads_and_elimination(disc, pairs)
    M = mass_matrix(disc, [case.material_of(b.name).rho for b in case.bodies], mass_kind == "lumped")
    K, Kr, Mr = _reduced(K_bulk, jumps, K_jump, elim, M)
    timings["assembly"] = time.perf_counter() - t_start

    dt, nsteps, dt_limit = _time_step(case, disc, opts, Kr, Mr, duration)

    spec = gauge_spec(case) if "transmitted_energy" in case.measurements else None
    rows = gauge_rows(disc, spec) if spec else {}
    t0 = time.perf_counter()
    closing = _closing_rows(ielems, pairs)
    run = _integrate(scheme, disc, K, Kr, Mr, M, elim, loads, jumps, K_jump, K_bulk, dt, nsteps, rows,
                     closing)
    timings["solve"] = time.perf_counter() - t0

    q = {"strain_energy": run["strain"][-1], "interface_energy": run["interface"][-1],
         "kinetic_energy": run["kinetic"][-1], "external_work": run["work"][-1]}
    total = run["kinetic"] + run["strain"] + run["interface"]
    scale = max(np.abs(total).max(), np.abs(run["work"]).max(), 1e-300)
    q["energy_balance_error"] = float(np.max(np.abs(total - run["work"])) / scale)
    diagnostics = {"dynamics": scheme, "mass": mass_kind, "dt": dt, "time_steps": nsteps,
                   "duration": duration, "dt_stable_limit": dt_limit, "dofs": int(disc.ndof),
                   "free_dofs": int(Kr.shape[0]), "elements": int(disc.mesh.t.shape[1]),
                   "warnings": warnings}
    if spec:
        arrival = reflection_arrival(case, spec)
        Z = [longitudinal_impedance(body_at(case, spec[k]), case.analysis) for k in GAUGE_KEYS]
        lo, hi = case.bounds()
        q.update(pulse_measures(run["time"], run["gauges"][:, 0], run["gauges"][:, 1], arrival,
                                Z[0], Z[1], float(hi[1] - lo[1]) * case.thickness))
        diagnostics["gauges"] = {"time": run["time"].tolist(),
                                 "positions": {k: spec[k] for k in GAUGE_KEYS},
                                 **{f"sigma_xx_{k}": run["gauges"][:, j].tolist()
                                    for j, k in enumerate(GAUGE_KEYS)}}
    step = max(1, len(run["time"]) // HISTORY_POINTS)
    diagnostics["history"] = {k: np.asarray(run[k])[::step].tolist()
                              for k in ("time", "kinetic", "strain", "interface", "work")}
    u = run["u"]
    fields = {"position": disc.mesh.p.T.copy(), "displacement": u[disc.basis.nodal_dofs].T.copy(),
              "velocity": run["v"][disc.basis.nodal_dofs].T.copy()}
    profiles = {name: line_profile(case, disc.basis, u, seg, opts["line_points"])
                for name, seg in case.lines.items()}
    timings["total"] = time.perf_counter() - t_start
    return Result(method="fem", case_name=case.name, quantities=q, fields=fields, profiles=profiles,
                  timings=timings, diagnostics=diagnostics)


def _time_step(case, disc, opts, Kr, Mr, duration: float) -> tuple[float, int, float | None]:
    """(dt, steps, stable limit): central differences at cfl x 2/omega_max (a larger given
    dt is refused), Newmark at cfl x h_min / c_max; dt shortened to divide the duration."""
    dt_limit = None
    if opts["dynamics"] == "central":
        dt_limit = stable_time_step(Kr, Mr)
        dt = opts["dt"] if opts["dt"] is not None else opts["cfl"] * dt_limit
        if dt > dt_limit:
            raise CaseError(f"fem option dt = {dt:.4g} s exceeds the stable central-difference limit "
                            f"2/omega_max = {dt_limit:.4g} s of this mesh: use dt <= {dt_limit:.4g} s "
                            "or dynamics = 'newmark'")
    else:
        c_max = max(m.wave_speed(case.analysis) for m in case.materials.values())
        h_min = float(np.min(np.ptp(disc.mesh.p[:, disc.mesh.t], axis=1)))
        dt = opts["dt"] if opts["dt"] is not None else opts["cfl"] * h_min / c_max
    nsteps = int(math.ceil(duration / dt - 1e-9))
    return duration / nsteps, nsteps, dt_limit


def _check_bilinear(ielems, scheme: str) -> None:
    """Bilinear normal laws: only the 002 "NL" law (Dn in tension, perfect in compression)
    with central differences (a contact constraint on the explicit step)."""
    bilinear = [el for el in ielems if el.bilinear]
    if not bilinear:
        return
    if scheme != "central" or any(np.any(np.isfinite(el.Dn_compression)) for el in bilinear):
        raise CaseError("fem: transient analysis supports bilinear normal interface laws only as "
                        "perfect in compression (Dn_compression = inf) with dynamics = 'central'; use "
                        "that or mpm")


def _closing_rows(ielems, pairs) -> np.ndarray:
    """Rows of the normal jumps (J = jumps @ u) of node pairs on bilinear elements."""
    rows = [2 * np.unique(pair_index(pairs, el.node_b)) for el in ielems if el.bilinear]
    return np.unique(np.concatenate(rows)).astype(np.int64) if rows else np.zeros(0, np.int64)


def _close(G, lu_M, rows, q, v, h, hdot):
    """Perfect in compression (002 "NL"): node pairs whose normal jump would be negative
    after the explicit step are closed, [u_n] = 0 and zero relative normal velocity, by
    the smallest change of q and v in the mass metric (forward-increment Lagrange
    multipliers: q -= M_r^-1 C^T (C M_r^-1 C^T)^-1 (C q + h)); open pairs keep the
    tension spring."""
    jn = G[rows] @ q + h[rows]
    active = jn < 0.0
    if not np.any(active):
        return q, v
    C = G[rows[active]]
    X = lu_M.solve(np.ascontiguousarray(C.T.toarray()))
    S = np.atleast_2d(C @ X)
    q = q - X @ np.linalg.solve(S, jn[active])
    v = v - X @ np.linalg.solve(S, C @ v + hdot[rows[active]])
    return q, v


def _integrate(scheme, disc, K, Kr, Mr, M, elim, loads, jumps, K_jump, K_bulk, dt, nsteps, rows,
               closing=np.zeros(0, np.int64)):
    """Time loop in the reduced unknowns: u = T q + g(t), v = T q' + g'(t), a = T q'' + g''(t)
    with M_r q'' + K_r q = T^T (f - K g - M g''). Newmark average acceleration:
    (K_r + 4 M_r / dt^2) q+ = T^T (f+ - K g+ - M g''+) + M_r (4 (q + dt q') / dt^2 + q'');
    central differences in velocity-Verlet form. A velocity jump of a prescribed motion
    (linear ramp at t = 0 and at its end) gives the free unknowns the impulse that keeps
    T^T M v continuous. Returns histories (work: trapezoidal int (M a + K u) . du)."""
    n = disc.ndof
    T = elim.T
    R = np.stack([rows[k] for k in GAUGE_KEYS]) if rows else np.zeros((0, n))
    out = {k: np.zeros(nsteps + 1) for k in ("time", "kinetic", "strain", "interface", "work")}
    out["gauges"] = np.zeros((nsteps + 1, R.shape[0]))
    lu_M = _factorized(Mr)
    G = (jumps @ T).tocsr()
    if scheme == "newmark":
        lu = _factorized(Kr + (4.0 / dt ** 2) * Mr)

    def rhs(t):
        g, gd, gdd = loads.prescribed(t, n)
        return T.T @ (loads.force(t, n) - K @ g - M @ gdd), (g, gd, gdd)

    def full(q, vq, aq, gs):
        return T @ q + gs[0], T @ vq + gs[1], T @ aq + gs[2]

    def impulse(t_kink):
        """Free-velocity jump for a jump of g' at t_kink (T^T M v continuous)."""
        _, before, _ = loads.prescribed(t_kink - 1e-12 * max(t_kink, dt), n)
        _, after, _ = loads.prescribed(t_kink, n)
        return -lu_M.solve(T.T @ (M @ (after - before)))

    q = np.zeros(T.shape[1])
    vq = impulse(0.0)
    b, gs = rhs(0.0)
    aq = lu_M.solve(b - Kr @ q)
    u, v, a = full(q, vq, aq, gs)
    _record(out, 0, 0.0, u, v, M, K_bulk, jumps, K_jump, R)
    kinks = [tk for tk in loads.kinks() if tk > 0.0]
    work = 0.0
    for s in range(1, nsteps + 1):
        t = s * dt
        for tk in [tk for tk in kinks if t - dt < tk <= t]:
            vq = vq + impulse(tk)
        if scheme == "newmark":
            b, gs = rhs(t)
            q_new = lu.solve(b + Mr @ ((4.0 / dt ** 2) * (q + dt * vq) + aq))
            aq_new = (4.0 / dt ** 2) * (q_new - q - dt * vq) - aq
            vq = vq + 0.5 * dt * (aq + aq_new)
            q, aq = q_new, aq_new
        else:
            v_half = vq + 0.5 * dt * aq
            q = q + dt * v_half
            if closing.size:
                g, gd, _ = loads.prescribed(t, n)
                q, v_half = _close(G, lu_M, closing, q, v_half, jumps @ g, jumps @ gd)
            b, gs = rhs(t)
            aq = lu_M.solve(b - Kr @ q)
            vq = v_half + 0.5 * dt * aq
        u_new, v, a_new = full(q, vq, aq, gs)
        work += 0.5 * float((M @ (a + a_new) + K @ (u + u_new)) @ (u_new - u))
        u, a = u_new, a_new
        _record(out, s, t, u, v, M, K_bulk, jumps, K_jump, R)
        out["work"][s] = work
        if not math.isfinite(out["kinetic"][s]):
            raise SolverError(f"fem transient diverged at t = {t:.4g} s: reduce dt")
    out["u"], out["v"] = u, v
    return out


def _record(out, s, t, u, v, M, K_bulk, jumps, K_jump, R):
    J = jumps @ u
    out["time"][s] = t
    out["kinetic"][s] = 0.5 * float(v @ (M @ v))
    out["strain"][s] = 0.5 * float(u @ (K_bulk @ u))
    out["interface"][s] = 0.5 * float(J @ (K_jump @ J))
    if R.shape[0]:
        out["gauges"][s] = R @ u
