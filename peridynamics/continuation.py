"""Arc-length continuation of the CPD equilibrium path (Riks normal-plane, Crisfield step control).

The equilibrium equations G(v, lam) = R_f(v) - lam f_ext,f = 0 (:class:`~peridynamics.newton.Equations`:
free DOFs v, fixed DOFs at lam u_bar) are followed as a curve in (v, lam) instead of at given
load factors (E. Riks, "An incremental approach to the solution of snapping and buckling
problems", Int. J. Solids Struct. 15 (1979) 529-551; M. A. Crisfield, Non-linear Finite Element
Analysis of Solids and Structures, vol. 1, Wiley 1991, Sec 9.3-9.5). Where a tangent eigenvalue
passes through zero along the path (a limit point), load control has no solution beyond it
while the arc length still has one (the path may turn back, pass through negative load factors
as in a snap-through, and rise again).

Per arc, from the converged point (v_n, lam_n):

- tangent: b = -K^-1 dG/dlam (the path's dv/dlam), t = (b / U, 1) / |(b / U, 1)| in the scaled
  norm |(dv, dlam)|^2 = |dv|^2 / U^2 + dlam^2 (U = |b| at the reference state, so both parts
  weigh alike at the start); its sign keeps t . t_previous > 0 (Crisfield's angle criterion,
  which follows the path through limit points without a determinant);
- predictor: (v, lam) = (v_n, lam_n) + ds t;
- corrector (Riks): Newton on G with the constraint t . (dv / U, dlam) = 0 (the iterates stay in
  the plane normal to t through the predictor), by the bordering algorithm: K a = -G,
  K b = -dG/dlam with the same factors, dlam = -(t_v . a / U) / (t_v . b / U + t_lam), dv = a + dlam b;
  converged at |G| <= ``arc_tol`` |dG/dlam| ds;
- step control: ds *= clip(sqrt(``arc_iterations`` / iterations used), 1/2, 2); a failing
  corrector (residual growing, ``max_iter``) halves ds and retries from (v_n, lam_n)
  (``max_cuts`` times in a row).

When the predictor would pass load factor 1 on a rising path, the arc is shortened to land on
lam = 1 and the corrector is plain Newton at lam = 1 (:func:`~peridynamics.newton.newton_at_load`,
``tol``, normalised by |dG/dlam| (1 - lam_n), the linearised residual of the remaining boundary
increment, 003 Table 3): the final iterations are those of load control from a tangent predictor.
"""
from __future__ import annotations

import math

import numpy as np

from interfaces.errors import SolverError

from .newton import (Equations, NewtonOptions, NewtonOutcome, StepFailure, forcing, newton_at_load,
                     not_converged, step_record)


class _Tangent:
    """Unit path tangent t = (t_v, t_lam) at a converged point in the scaled norm."""

    def __init__(self, b: np.ndarray, U: float, previous: "_Tangent | None"):
        n = math.sqrt(float(b @ b) / U**2 + 1.0)
        self.v, self.lam = b / (U * n), 1.0 / n
        if previous is not None and self.dot(previous) < 0.0:
            self.v, self.lam = -self.v, -self.lam

    def dot(self, other: "_Tangent") -> float:
        return float(self.v @ other.v) + self.lam * other.lam


def _riks(eq: Equations, v: np.ndarray, lam: float, t: _Tangent, U: float, scale: float,
          opts: NewtonOptions):
    """Riks corrector from the predictor (v, lam): (v, lam, residuals, ev) or a StepFailure."""
    free, fixed = eq.free, eq.fixed
    hist = []
    for it in range(opts.max_iter + 1):
        v[fixed] = lam * eq.ubar[fixed]
        try:
            ev = eq.evaluate(v, True)
        except ValueError as e:
            return eq.failure(lam, hist, f"arc corrector: {e}")
        G = eq.residual(ev, lam)
        r = float(np.linalg.norm(G)) / scale
        hist.append(r)
        eq.note(f"arc at load {lam:.5g} iteration {it}: normalised residual {r:.3e}")
        if r <= opts.arc_tol:
            return v, lam, hist, ev
        if not np.isfinite(r) or r > 10.0 * hist[0] or (it >= 2 and r >= hist[-2]) or it == opts.max_iter:
            return eq.failure(lam, hist, "arc corrector does not contract")
        eta = forcing(r, opts.arc_tol)
        try:
            a = eq.solve(ev, -G, eta)
            b = eq.solve(ev, -eq.load_derivative(ev), eta)
        except RuntimeError as e:
            return eq.failure(lam, hist, f"singular tangent ({e})")
        dlam = -float(t.v @ a / U) / (float(t.v @ b / U) + t.lam)
        if not (np.isfinite(dlam) and np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
            return eq.failure(lam, hist, "non-finite arc correction (singular bordered system)")
        v = v.copy()
        v[free] += a + dlam * b
        lam += dlam


def _path_tangent(eq: Equations, ev) -> tuple[np.ndarray, np.ndarray]:
    """dG/dlam and b = dv/dlam = -K^-1 dG/dlam at a converged point (tangent of ``ev``)."""
    g = eq.load_derivative(ev)
    return g, eq.solve(ev, -g, 1e-8)


def _first_arc(opts: NewtonOptions) -> float:
    lam1 = opts.load_factors[0] if opts.load_factors else 1.0 / opts.load_steps
    return math.sqrt(2.0) * lam1          # t_lam = 1 / sqrt(2) at the reference state (U = |b|)


def arc_length(eq: Equations, opts: NewtonOptions, u: np.ndarray, out: NewtonOutcome,
               failures: list) -> np.ndarray:
    """Follow the path from (u, 0) to load factor 1 (module docstring); fills ``out.history``
    (one entry per arc: load factor, residuals, arc length, the path tangent's t_lam at the
    converged point (at the start for the final load step), whether a limit point was passed
    (t_lam changed sign), |v_f|, negative pivots of the last factorisation) and returns the
    independent DOFs at lam = 1."""
    free, fixed = eq.free, eq.fixed
    v = u.copy()
    v[fixed] = 0.0
    lam = 0.0
    ds = _first_arc(opts)
    ev = eq.evaluate(v, True)
    g, b = _path_tangent(eq, ev)
    U = max(float(np.linalg.norm(b)), 1e-300)
    t = _Tangent(b, U, None)
    contraction = [1e-2]
    cuts = 0
    for _ in range(opts.max_arcs):
        gn = float(np.linalg.norm(g))
        final = t.lam > 0 and lam + ds * t.lam >= 1.0 - 1e-9
        step = (1.0 - lam) / t.lam if final else ds
        trial = v.copy()
        trial[free] += step * U * t.v
        if final:
            trial[fixed] = eq.ubar[fixed]
            got = newton_at_load(eq, trial, 1.0, gn * (1.0 - lam), opts, contraction)
        else:
            got = _riks(eq, trial, lam + step * t.lam, t, U, gn * step, opts)
        if isinstance(got, StepFailure):
            failures.append(got)
            cuts += 1
            if cuts > opts.max_cuts:
                raise not_converged(got, opts, f"{opts.max_cuts} arc-length cuts")
            ds = 0.5 * step
            eq.note(f"arc to load {got.load:.5g} failed ({got.reason}): arc length halved to {ds:.3g}")
            continue
        cuts = 0
        pivots = eq.negative_pivots()
        if final:
            v, hist, ev, (alphas, times) = got
            out.history.append(step_record(1.0, hist, alphas, times, arc_length=step, t_lam=t.lam,
                                           negative_pivots=pivots, limit_point=False,
                                           displacement_norm=float(np.linalg.norm(v[free])),
                                           path="final load step"))
            out.iterations += len(hist) - 1
            out.last = ev
            return v
        v, lam, hist, ev = got
        g, b = _path_tangent(eq, ev)
        t_new = _Tangent(b, U, t)
        # t_lam changes sign across a limit point (a tangent eigenvalue through zero: the
        # negative-pivot count changes by one there)
        limit = t_new.lam * t.lam < 0.0
        out.history.append(step_record(lam, hist, [], [], arc_length=step, t_lam=t_new.lam,
                                       negative_pivots=pivots, limit_point=limit,
                                       displacement_norm=float(np.linalg.norm(v[free])), path="arc"))
        out.iterations += len(hist) - 1
        eq.note(f"arc converged at load {lam:.5g} (path tangent t_lam {t_new.lam:.3g}, {pivots} negative "
                f"pivots{'; limit point passed' if limit else ''})")
        t = t_new
        ds = step * min(2.0, max(0.5, math.sqrt(opts.arc_iterations / max(len(hist) - 1, 1))))
    loads = [h["load"] for h in out.history]
    limits = [f"{h['load']:.4g}" for h in out.history if h["limit_point"]]
    raise SolverError(
        f"CPD arc-length continuation did not reach load factor 1 in max_arcs = {opts.max_arcs} arcs "
        f"(load factors reached: {', '.join(f'{x:.4g}' for x in loads)}"
        + (f"; limit points passed near load factors {', '.join(limits)}: the equilibrium path from the "
           "reference state turns back there" if limits else "")
        + "); increase max_arcs or the first load step" + ("" if not limits else
        ", or reduce the load below the first limit point (for C3 < 0 materials: use nu >= 1/4)"))
