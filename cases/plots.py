"""Agreement plots: quantities by method against the reference, profiles on shared axes,
and sweep curves (one per method) against a case parameter."""
from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

STYLE = {"analytic": dict(color="k", ls="-", marker=None, lw=1.6),
         "fem": dict(color="tab:blue", ls="--", marker="s", lw=1.2),
         "mpm": dict(color="tab:red", ls=":", marker="o", lw=1.2),
         "cpd": dict(color="tab:green", ls="-.", marker="^", lw=1.2)}
UNITS = {"stiffness": "N/mm", "stiffness_energy": "N/mm", "strain_energy": "N mm", "interface_energy": "N mm",
         "kinetic_energy": "N mm", "bulk_modulus": "MPa", "transmitted_energy": "-", "beta_l": "-",
         "pulse_transmitted_energy": "-", "incident_pulse_energy": "N mm", "energy_balance_error": "-",
         "incident_peak_stress": "MPa", "transmitted_peak_stress": "MPa",
         "compliance": "mm/N", "interface_energy_density": "MPa"}
LABELS = {"ux": "u_x (mm)", "uy": "u_y (mm)", "uz": "u_z (mm)", "jump_n": "[u_n] (mm)", "jump_t": "[u_t] (mm)",
          "traction_n": "T_n (MPa)", "traction_t": "T_t (MPa)"}


def _finish(fig, unused_axes, title: str, path) -> Path:
    """Hide unused panels, title, save as PNG and close."""
    for ax in unused_axes:
        ax.axis("off")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def _style(method: str) -> dict:
    return STYLE.get(method, dict(color="tab:purple", ls="-", marker="x", lw=1.0))


HEADLINE = ("stiffness", "stiffness_energy", "strain_energy", "interface_energy", "bulk_modulus",
            "transmitted_energy")
PROFILE_KEYS = ("ux", "uy", "uz", "jump_n", "jump_t")
NOT_COMPARED = ("load", "external_work")
"""Kept in results.json but not compared: the applied load is an input, and the work of
a dynamic method includes what its damping removed, so it differs from the static work."""


def shared_quantities(comparison) -> list[str]:
    """Quantities worth a panel: those two or more methods give and that have a
    reference (the case's, else FEM); with one method, its headline quantities."""
    names = comparison.quantity_names()
    methods = list(comparison.results)

    def count(q):
        return sum(math.isfinite(comparison.value(m, q)) for m in methods)

    names = [q for q in names if q not in NOT_COMPARED]
    out = [q for q in names if count(q) > 1 and comparison.reference_for(q) is not None] if len(methods) > 1 else []
    return out or [q for q in names if q in HEADLINE]


def profile_panels(comparison) -> list[tuple[str, str]]:
    """(profile, component) pairs to plot: the case's lines and the interface jump, for
    displacement and jump components that vary along the line (not a rigid shift)."""
    wanted = list(comparison.case.lines) + ["interface_jump"]
    panels = []
    for pname in wanted:
        for key in PROFILE_KEYS:
            peak, present = 0.0, False
            scale = 0.0
            for r in comparison.results.values():
                prof = r.profiles.get(pname)
                if prof is None or key not in prof or "s" not in prof:
                    continue
                v = np.asarray(prof[key], dtype=float)
                if v.shape != np.shape(prof["s"]):
                    continue
                present = True
                peak = max(peak, float(np.nanmax(v) - np.nanmin(v)) if np.isfinite(v).any() else 0.0)
                for k2 in PROFILE_KEYS:
                    a = np.abs(np.asarray(prof.get(k2, []), dtype=float))
                    if a.shape == np.shape(prof["s"]) and np.isfinite(a).any():
                        scale = max(scale, float(np.nanmax(a)))
            if present and peak > 1e-3 * scale and peak > 0:  # skip flat (rigid shift or noise) curves
                panels.append((pname, key))
    return panels


def _abscissa(comparison, pname: str) -> str:
    """Arc length ``s`` along a case line; for the interface jump the coordinate (x or y)
    that varies most, since methods may start their arc length at different points
    (e.g. the DCB crack mouth for FEM, the crack tip for the beam model)."""
    profs = [r.profiles[pname] for r in comparison.results.values() if pname in r.profiles]
    if pname != "interface_jump" or not all("x" in p and "y" in p for p in profs):
        return "s"
    span = {k: max(float(np.ptp(np.asarray(p[k], dtype=float))) if len(p[k]) else 0.0 for p in profs)
            for k in ("x", "y")}
    return max(span, key=span.get)


def plot_comparison(comparison, path) -> Path:
    """One figure: a panel per shared quantity (value by method, reference as a dashed
    line, relative difference printed) and a panel per profile component along the
    case's lines and the interface (all methods on the same axes)."""
    quantities = shared_quantities(comparison)
    profile_panels_ = profile_panels(comparison)
    n = len(quantities) + len(profile_panels_)
    ncol = min(3, max(n, 1))
    nrow = max(1, math.ceil(n / ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.6 * ncol, 3.6 * nrow), squeeze=False)
    axes = axes.ravel()
    methods = list(comparison.results)
    for ax, q in zip(axes, quantities):
        vals = [comparison.value(m, q) for m in methods]
        for i, (m, v) in enumerate(zip(methods, vals)):
            if math.isfinite(v):
                ax.bar(i, v, color=_style(m)["color"], alpha=0.75)
                d = comparison.relative_difference(m, q)
                lab = f"{v:.4g}" + (f"\n{100 * d:+.1f}%" if m != comparison.reference_for(q) and math.isfinite(d) else "")
                ax.annotate(lab, (i, v), ha="center", va="bottom", fontsize=8)
        ref_method = comparison.reference_for(q)
        if ref_method is not None:
            ax.axhline(comparison.value(ref_method, q), color="k", lw=1, ls="--", label=f"reference ({ref_method})")
            ax.legend(fontsize=7, loc="lower right")
        ax.set_xticks(range(len(methods)), methods)
        ax.set_title(f"{q} ({UNITS.get(q, '')})", fontsize=10)
        finite = [v for v in vals if math.isfinite(v)]
        if finite:
            ax.set_ylim(0, 1.25 * max(finite) if max(finite) > 0 else None)
    for ax, (pname, key) in zip(axes[len(quantities):], profile_panels_):
        absc = _abscissa(comparison, pname)
        for m, r in comparison.results.items():
            prof = r.profiles.get(pname)
            if prof is None or key not in prof:
                continue
            st = _style(m)
            s, v = np.asarray(prof[absc], dtype=float), np.asarray(prof[key], dtype=float)
            order = np.argsort(s)
            ax.plot(s[order], v[order], color=st["color"], ls=st["ls"], lw=st["lw"], label=m,
                    marker=st["marker"] if len(s) < 40 else None, ms=3)
        ax.set_xlabel(f"distance along {pname} (mm)" if absc == "s" else f"{absc} (mm)")
        ax.set_ylabel(LABELS.get(key, key))
        ax.set_title(f"{pname}: {key}", fontsize=10)
        ax.legend(fontsize=7)
    return _finish(fig, axes[n:], f"{comparison.case.name}: {comparison.case.description}", path)


def sweep_quantities(sweep) -> list[str]:
    """Quantities worth a panel: given by two or more methods (or all of a single
    method's headline quantities) and not constant over the sweep."""
    def values(q, m):
        v = np.array([sweep.value(i, m, q) for i in range(len(sweep.values))], dtype=float)
        return v[np.isfinite(v)]

    out = []
    for q in sweep.quantity_names():
        having = [m for m in sweep.methods if values(q, m).size]
        if len(sweep.methods) > 1 and len(having) < 2:
            continue
        if len(sweep.methods) == 1 and q not in HEADLINE:
            continue
        allv = np.concatenate([values(q, m) for m in having])
        if np.ptp(allv) <= 1e-9 * max(np.abs(allv).max(), 1e-300):
            continue
        out.append(q)
    return out


def plot_sweep(sweep, path, x_transform: str | None = None, quantities=None) -> Path:
    """Each quantity against the swept parameter, one curve per method.

    ``x_transform="inverse"`` plots against 1/value (e.g. stiffness vs 1/Dt as 000 Fig 7
    and 002 Fig 5); infinite values then sit at 0.
    """
    quantities = list(quantities) if quantities else sweep_quantities(sweep)
    n = max(1, len(quantities))
    ncol = min(2, n)
    nrow = math.ceil(n / ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(5.2 * ncol, 3.8 * nrow), squeeze=False)
    axes = axes.ravel()
    xs = np.asarray(sweep.values, dtype=float)
    with np.errstate(divide="ignore"):
        xplot = 1.0 / xs if x_transform == "inverse" else xs
    for ax, q in zip(axes, quantities):
        for m in sweep.methods:
            y = np.array([sweep.value(i, m, q) for i in range(len(xs))], dtype=float)
            ok = np.isfinite(y) & np.isfinite(xplot)
            if not ok.any():
                continue
            st = _style(m)
            order = np.argsort(xplot[ok])
            ax.plot(xplot[ok][order], y[ok][order], color=st["color"], ls=st["ls"], marker=st["marker"] or ".",
                    lw=st["lw"], label=m)
        xl = f"1/{sweep.param}" if x_transform == "inverse" else sweep.param
        ax.set_xlabel(xl)
        ax.set_ylabel(f"{q} ({UNITS.get(q, '')})")
        if x_transform == "log":
            ax.set_xscale("log")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    return _finish(fig, axes[n:], f"{sweep.case_name}: sweep of {sweep.param}", path)
