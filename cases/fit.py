"""``imperfect fit``: interface parameters from measured specimen stiffnesses (002 Sec 3.4).

The DLS stiffness depends strongly on Dt when the bond is short enough for end effects
to matter (002 Eq 50-51); the DCB stiffness on Dn only when Dn is low. Given stiffnesses
measured on specimens that differ in one case parameter (e.g. the DLS at several bond
lengths l), the interface parameters are found with a model in the loop, the analytic
one (shear lag, beam on elastic foundation) or FEM:

* one parameter and one measurement: the root of k_model(D) = k_measured, bracketed on
  log10 D (``scipy.optimize.brentq``);
* otherwise least squares on the relative residuals ln(k_model/k_measured) over
  log10 D (``scipy.optimize.least_squares``, bounded), for Dt alone or Dt and Dn.

Each parameter is reported with its sensitivity s_i = d ln k_i / d ln D at the fit (how
much the data can tell), and a range: the fit's standard error from the linearised
least-squares covariance sigma^2 (J^T J)^-1 (J in ln D, sigma the relative measurement
noise: given, or the residuals' RMS when there are more measurements than parameters),
widened to +-2 standard errors (~95 %). A parameter the data do not determine
(sensitivity too small against the noise) is reported as such and held at its case
value. A plot shows the measured stiffnesses against the fitted model.

Units: stiffness N/mm, Dn, Dt MPa/mm.
"""
from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
from scipy.optimize import brentq, least_squares

from interfaces.errors import CaseError, SolverError

from . import registry
from .methods import run

LOG10_BOUNDS = (-4.0, 9.0)        # 1e-4 .. 1e9 MPa/mm; the upper end is indistinguishable from perfect here
FIT_METHODS = ("analytic", "fem")
COVERAGE = 2.0                    # +- standard errors in the reported range (~95 %)


@dataclass
class FitResult:
    """Fitted parameters (MPa/mm) with their ranges and sensitivities, and the data."""

    case: str
    method: str
    parameters: dict[str, float]
    ranges: dict[str, tuple[float, float]]
    sensitivities: dict[str, list[float]]
    undetermined: list[str]
    at: str
    x: list[float]
    measured: list[float]
    fitted: list[float]
    noise: float
    noise_source: str
    evaluations: int
    notes: list[str] = field(default_factory=list)

    def summary(self) -> str:
        lines = [f"fit of {', '.join(self.parameters)} for case {self.case} with {self.method} in the loop "
                 f"({self.evaluations} model evaluations)"]
        for p, v in self.parameters.items():
            lo, hi = self.ranges[p]
            s = ", ".join(f"{x:.3g}" for x in self.sensitivities[p])
            lines.append(f"  {p} = {v:.5g} MPa/mm, range [{lo:.5g}, {hi:.5g}] (+-{COVERAGE:g} standard errors at "
                         f"{100 * self.noise:.2g} % relative noise, {self.noise_source}); sensitivity d ln k / d ln {p} "
                         f"= {s}")
        for p in self.undetermined:
            lines.append(f"  {p}: not determined by these data (sensitivity below the noise); held at its case value")
        lines.append(f"  {'':>10} {self.at:>10} {'measured':>12} {'fitted':>12} {'diff':>8}")
        for x, m, f in zip(self.x, self.measured, self.fitted):
            lines.append(f"  {'':>10} {x:>10.4g} {m:>12.5g} {f:>12.5g} {100 * (f / m - 1):>+7.2f}%")
        lines.extend(f"  note: {n}" for n in self.notes)
        return "\n".join(lines)


class _Model:
    """k(D) at every measurement setting, counting evaluations."""

    def __init__(self, case: str, at: str, xs, method: str, fixed: dict, options: dict):
        if method not in FIT_METHODS:
            raise CaseError(f"fit method must be one of {', '.join(FIT_METHODS)}, got {method!r}")
        self.case, self.at, self.xs, self.method = case, at, list(xs), method
        self.fixed, self.options, self.evaluations = dict(fixed), dict(options), 0
        allowed = registry.parameters(case)
        if at not in allowed:
            raise CaseError(f"--at: case {case} has no parameter {at!r} (parameters: {', '.join(allowed)})")

    def stiffness(self, params: dict[str, float], x: float) -> float:
        case = registry.build(self.case, **{**self.fixed, **params, self.at: x})
        if self.method not in case.methods():
            raise CaseError(f"method {self.method!r} does not support case {self.case!r}")
        self.evaluations += 1
        q = run(case, self.method, **self.options).quantities
        if "stiffness" not in q:
            raise CaseError(f"case {self.case} with {self.method} gives no stiffness to fit")
        return float(q["stiffness"])

    def all(self, params: dict[str, float]) -> np.ndarray:
        return np.array([self.stiffness(params, x) for x in self.xs])


def _log_residuals(model: _Model, names, measured: np.ndarray):
    def residuals(z: np.ndarray) -> np.ndarray:
        return np.log(model.all({n: 10.0 ** v for n, v in zip(names, z)}) / measured)
    return residuals


def _jacobian_ln(model: _Model, names, z: np.ndarray, step: float = 0.01) -> np.ndarray:
    """d ln k_i / d ln D_j by central differences in log10 D (step in decades)."""
    f = _log_residuals(model, names, np.ones(len(model.xs)))
    cols = []
    for j in range(len(names)):
        e = np.zeros(len(names))
        e[j] = step
        cols.append((f(z + e) - f(z - e)) / (2.0 * step * math.log(10.0)))
    return np.stack(cols, axis=1)


def fit(case: str, at: str, xs, stiffness, parameters=("Dt",), method: str = "analytic", fixed=None,
        options=None, noise: float | None = None, start: float = 10.0) -> FitResult:
    """Fit ``parameters`` (subset of Dt, Dn) of the named ``case`` to stiffnesses measured at
    case parameter ``at`` = ``xs`` (module docstring). ``noise`` is the relative measurement
    scatter (e.g. 0.02); without it the residuals' RMS is used (needs more measurements than
    parameters)."""
    xs, measured, names = _checked_inputs(case, xs, stiffness, parameters, noise)
    model = _Model(case, at, xs, method, fixed or {}, options or {})
    z, notes = _solve(model, names, measured, math.log10(start))
    J = _jacobian_ln(model, names, z)
    sigma, source = _scatter(model, names, z, measured, noise)
    # parameters whose effect on every stiffness over half a decade is below the scatter are not determined
    determined = [j for j in range(len(names)) if np.linalg.norm(J[:, j]) * 0.5 * math.log(10.0) > sigma]
    undetermined = [n for j, n in enumerate(names) if j not in determined]
    if not determined:
        raise SolverError(f"none of {', '.join(names)} changes the stiffness by more than the noise "
                          f"({100 * sigma:.2g} %) over a decade: these measurements cannot determine them "
                          "(002 Sec 3.4: the DLS tells Dt when its bond is short, small beta l; the DCB tells Dn "
                          "only when Dn is low)")
    if undetermined:        # refit the others with the undetermined ones at their case values
        names = [names[j] for j in determined]
        z, notes = _solve(model, names, measured, z[determined[0]])
        J = _jacobian_ln(model, names, z)
        sigma, source = _scatter(model, names, z, measured, noise)
    params, ranges, sens = _ranges(names, z, J, sigma, notes)
    fitted = model.all(params)
    return FitResult(case=case, method=method, parameters=params, ranges=ranges, sensitivities=sens,
                     undetermined=undetermined, at=at, x=xs, measured=[float(v) for v in measured],
                     fitted=[float(v) for v in fitted], noise=sigma, noise_source=source,
                     evaluations=model.evaluations, notes=notes)


def _checked_inputs(case: str, xs, stiffness, parameters, noise):
    xs = [float(v) for v in xs]
    measured = np.asarray(stiffness, dtype=float)
    if len(xs) != len(measured) or len(xs) == 0:
        raise CaseError(f"--stiffness needs one value per --values entry, got {len(measured)} for {len(xs)}")
    if not np.all(np.isfinite(measured) & (measured > 0)):
        raise CaseError(f"--stiffness values must be positive numbers (N/mm), got {list(measured)}")
    names = list(dict.fromkeys(parameters))
    if not names or any(n not in ("Dt", "Dn") for n in names):
        raise CaseError(f"--fit must list Dt and/or Dn, got {','.join(parameters)}")
    if noise is not None and not 0 < noise < 1:
        raise CaseError(f"--noise is a relative scatter in (0, 1), got {noise}")
    for n in names:
        if n not in registry.parameters(case):
            raise CaseError(f"--fit: case {case} has no parameter {n!r}")
    return xs, measured, names


def _scatter(model: _Model, names, z: np.ndarray, measured: np.ndarray, noise) -> tuple[float, str]:
    """The relative measurement scatter: given, or the RMS of the fit's log residuals."""
    if noise is not None:
        return float(noise), "given"
    dof = len(measured) - len(names)
    if dof < 1:
        raise CaseError("--noise is needed for a range when there are no more measurements than fitted "
                        "parameters (the residuals cannot estimate the scatter)")
    resid = _log_residuals(model, names, measured)(z)
    return max(float(np.sqrt(resid @ resid / dof)), 1e-12), "RMS of the residuals"


def _ranges(names, z: np.ndarray, J: np.ndarray, sigma: float, notes: list[str]):
    """Fitted values, +-COVERAGE standard-error ranges from sigma^2 (J^T J)^-1 in ln D, and
    the sensitivities d ln k_i / d ln D."""
    cov = sigma ** 2 * np.linalg.inv(J.T @ J)
    params, ranges, sens = {}, {}, {}
    for j, name in enumerate(names):
        D, se = 10.0 ** z[j], math.sqrt(cov[j, j])
        params[name], ranges[name] = D, (D * math.exp(-COVERAGE * se), D * math.exp(COVERAGE * se))
        sens[name] = [float(v) for v in J[:, j]]
        if z[j] >= LOG10_BOUNDS[1] - 1e-6:
            notes.append(f"{name} reached the upper bound 1e9 MPa/mm: the data are consistent with a perfect "
                         "interface")
    return params, ranges, sens


def _solve(model: _Model, names, measured: np.ndarray, z0: float) -> tuple[np.ndarray, list[str]]:
    """Bracketed root (one parameter, one measurement) or bounded least squares in log10 D."""
    res = _log_residuals(model, names, measured)
    lo, hi = LOG10_BOUNDS
    if len(names) == 1 and len(measured) == 1:
        a, b = _bracket(lambda v: res(np.array([v]))[0], float(np.clip(z0, lo, hi)), lo, hi, measured[0])
        return np.array([brentq(lambda v: res(np.array([v]))[0], a, b, xtol=1e-6)]), []
    sol = least_squares(res, np.full(len(names), np.clip(z0, lo, hi)), bounds=(lo, hi), x_scale=1.0,
                        diff_step=1e-3, xtol=1e-10, ftol=1e-12, gtol=1e-12)
    if not sol.success:
        raise SolverError(f"the least-squares fit did not converge ({sol.message})")
    return sol.x, []


def _bracket(f, z0: float, lo: float, hi: float, k: float) -> tuple[float, float]:
    """A sign change of the log residual f(log10 D), searched one decade at a time from z0 (the
    stiffness rises with D): the model is never evaluated far beyond the answer, where a near-
    mechanism (D -> 0) or a stiff tie (D -> inf) is ill-conditioned."""
    f0 = f(z0)
    step = 1.0 if f0 < 0 else -1.0            # model too soft: raise D
    z = z0
    while True:
        z_next = min(max(z + step, lo), hi)
        if z_next == z:
            end = "above the perfect" if step > 0 else "below the debonded"
            raise SolverError(f"the measured stiffness {k:g} N/mm is {end}-interface end of the model's range "
                              f"(D = 10^{z:g} MPa/mm gives {math.exp(f0) * k:.5g} N/mm): check the specimen "
                              "parameters (--set)")
        f1 = f(z_next)
        if f1 == 0.0 or (f1 > 0) != (f0 > 0):
            return (z, z_next) if z < z_next else (z_next, z)
        z, f0 = z_next, f1


def plot_fit(result: FitResult, path: Path, model_curve=None) -> Path:
    """Measured stiffnesses (with +-2 sigma bars) against the fitted model; ``model_curve`` =
    (x, k, (k_low, k_high) or None): the model over x and at the ends of the fitted range."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.0, 4.2))
    m = np.array(result.measured)
    ax.errorbar(result.x, m, yerr=COVERAGE * result.noise * m, fmt="o", color="black", capsize=3,
                label=f"measured (+-{COVERAGE:g} x {100 * result.noise:.2g} %)")
    label = ", ".join(f"{p} = {v:.4g}" for p, v in result.parameters.items())
    if model_curve is not None:
        xs, k, band = model_curve
        ax.plot(xs, k, "-", color="tab:blue", label=f"{result.method}, {label} MPa/mm")
        if band is not None:
            ax.fill_between(xs, *band, color="tab:blue", alpha=0.2, label="fitted range")
    ax.plot(result.x, result.fitted, "x", color="tab:blue", ms=8, label=None if model_curve is not None else
            f"{result.method}, {label} MPa/mm")
    ax.set_xlabel(result.at)
    ax.set_ylabel("stiffness (N/mm)")
    ax.set_title(f"imperfect fit: {result.case}", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def _curve(result: FitResult, fixed: dict, options: dict):
    """The fitted model over the measured range (analytic only: FEM is shown at the points)."""
    if result.method != "analytic" or len(result.x) < 2:
        return None
    xs = np.linspace(min(result.x), max(result.x), 60)
    model = _Model(result.case, result.at, xs, "analytic", fixed, options)
    band = None
    if len(result.parameters) == 1:
        (p, (lo, hi)), = result.ranges.items()
        band = (model.all({p: lo}), model.all({p: hi}))
    return xs, model.all(result.parameters), band


def add_parser(sub) -> None:
    """The ``fit`` subcommand of ``imperfect``."""
    f = sub.add_parser("fit", help="fit Dt (and Dn) to measured stiffnesses (002 Sec 3.4)")
    f.add_argument("case", help="named case with a stiffness, e.g. dls or dcb")
    f.add_argument("--stiffness", required=True, help="comma list of measured stiffnesses (N/mm)")
    f.add_argument("--at", default=None, help="case parameter the specimens differ in (default: l for dls, a for dcb)")
    f.add_argument("--values", default=None, help="comma list of that parameter, one per stiffness")
    f.add_argument("--fit", default=None, help="Dt (default for dls), Dn (default for dcb) or Dt,Dn")
    f.add_argument("--method", default="analytic", choices=FIT_METHODS, help="model in the loop")
    f.add_argument("--noise", type=float, default=None, help="relative measurement scatter, e.g. 0.02")
    f.add_argument("--set", action="append", metavar="KEY=VALUE", help="fixed case parameters")
    f.add_argument("--option", action="append", metavar="METHOD.KEY=VALUE", help="solver option, e.g. fem.h=0.2")
    f.add_argument("--out", default="out")


def cmd_fit(args) -> int:
    from .cli import parse_assignments, parse_options, parse_value

    stiff = parse_value(args.stiffness)
    stiff = list(stiff) if isinstance(stiff, (list, tuple)) else [stiff]
    at = args.at or {"dls": "l", "dcb": "a"}.get(args.case)
    if at is None:
        raise CaseError("--at is required for this case (the case parameter the specimens differ in)")
    fixed = parse_assignments(args.set)
    if args.values is None:
        if len(stiff) != 1:
            raise CaseError("--values (one per stiffness) is required with several stiffnesses")
        xs = [fixed.pop(at, registry.parameters(args.case)[at])]
    else:
        v = parse_value(args.values)
        xs = list(v) if isinstance(v, (list, tuple)) else [v]
    names = (args.fit or {"dcb": "Dn"}.get(args.case, "Dt")).split(",")
    options = parse_options(args.option).get(args.method, {})
    result = fit(args.case, at, xs, stiff, names, args.method, fixed, options, args.noise)
    print(result.summary())
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "fit.json").write_text(json.dumps(asdict(result), indent=1))
    png = plot_fit(result, out / f"{args.case}_fit.png", _curve(result, fixed, options))
    print(f"\nwrote {out / 'fit.json'}, {png}")
    return 0


__all__ = ["FitResult", "fit", "plot_fit", "add_parser", "cmd_fit"]
