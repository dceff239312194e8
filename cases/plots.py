"""Agreement plots: quantities by method against the reference, profiles on shared axes,
and sweep curves (one per method) against a case parameter."""
from __future__ import annotations

import math
import textwrap
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
         "kinetic_energy": "N mm", "bulk_modulus": "MPa", "bulk_modulus_pressure": "MPa", "transmitted_energy": "-", "beta_l": "-",
         "pulse_transmitted_energy": "-", "incident_pulse_energy": "N mm", "energy_balance_error": "-",
         "incident_peak_stress": "MPa", "transmitted_peak_stress": "MPa",
         "compliance": "mm/N", "interface_energy_density": "MPa", "contact_time": "s",
         "shock_speed": "mm/s", "particle_speed": "mm/s", "pressure": "MPa", "longitudinal_stress": "MPa"}
LABELS = {"ux": "u_x (mm)", "uy": "u_y (mm)", "uz": "u_z (mm)", "jump_n": "[u_n] (mm)", "jump_t": "[u_t] (mm)",
          "traction_n": "T_n (MPa)", "traction_t": "T_t (MPa)"}


def _finish(fig, unused_axes, title: str, path) -> Path:
    """Hide unused panels, title, save as PNG and close."""
    for ax in unused_axes:
        ax.axis("off")
    # wrapped to the figure width (~11 characters per inch at 10 pt): one-panel figures are narrow
    fig.suptitle(textwrap.fill(title, max(30, int(11 * fig.get_figwidth()))), fontsize=10)
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
NOT_COMPARED = ("load", "load_displacement", "support_displacement", "external_work")
"""Kept in results.json and comparison.csv but not in the table or the figure: the applied
load is an input, the mean displacements of the load and support sides are compared
through the stiffness they give (002 Eq 43), and the work of a dynamic method includes
what its damping removed, so it differs from the static work."""


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
    """One figure: an agreement panel (each method's relative difference to the reference,
    per shared quantity, on its own axis, with the values printed) and a panel per profile
    component along the case's lines and the interface (all methods on the same axes)."""
    shared = shared_quantities(comparison)
    quantities = [q for q in shared if q in HEADLINE] or shared    # the rest is in the table
    profile_panels_ = profile_panels(comparison)
    n = (1 if quantities else 0) + len(profile_panels_)
    ncol = min(3, max(n, 1))
    nrow = max(1, math.ceil(n / ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.8 * ncol, 3.8 * nrow), squeeze=False)
    axes = axes.ravel()
    if quantities:
        _agreement_panel(axes[0], comparison, quantities)
    scale_t = _tangential_jump_scale(comparison)
    for ax, (pname, key) in zip(axes[1 if quantities else 0:], profile_panels_):
        _profile_panel(ax, comparison, pname, key)
        if key == "jump_n" and pname.startswith("interface_jump") and _normal_is_perfect(comparison.case):
            # expected zero: show it on the scale of the tangential jump and say what it is
            if scale_t > 0:
                ax.set_ylim(-scale_t, scale_t)
            ax.text(0.5, 0.92, "Dn = inf: [u_n] = 0 expected;\nnon-zero values are extrapolation noise",
                    transform=ax.transAxes, ha="center", va="top", fontsize=7, color="0.3")
    return _finish(fig, axes[n:], f"{comparison.case.name}: {comparison.case.description}", path)


def _legend(ax, **kwargs) -> None:
    """The panel's legend, if any curve or marker is labelled (a method that gave no finite
    value draws nothing, and an empty legend would only warn)."""
    if ax.get_legend_handles_labels()[1]:
        ax.legend(**kwargs)


def _agreement_panel(ax, comparison, quantities: list[str]) -> None:
    """Rows = quantities, x = (value - reference) / |reference| in %, one marker per
    method that gives the quantity; the reference's value is in the row label."""
    methods = list(comparison.results)
    spread = 0.0
    for row, q in enumerate(quantities):
        ref = comparison.reference_for(q)
        for k, m in enumerate(methods):
            v = comparison.value(m, q)
            if not math.isfinite(v):
                continue
            d = 0.0 if m == ref else 100.0 * comparison.relative_difference(m, q)
            if not math.isfinite(d):
                continue
            y = row + 0.18 * (k - (len(methods) - 1) / 2)
            st = _style(m)
            ax.plot([d], [y], marker=st["marker"] or "D", color=st["color"], ls="none", ms=6,
                    label=m if row == 0 or m not in ax.get_legend_handles_labels()[1] else None)
            ax.annotate(f"{v:.5g}" + ("" if m == ref else f" ({d:+.2f}%)"), (d, y), xytext=(5, 0),
                        textcoords="offset points", va="center", fontsize=7, color=st["color"])
            spread = max(spread, abs(d))
    ax.axvline(0.0, color="k", lw=0.8)
    ax.set_yticks(range(len(quantities)),
                  [f"{q} ({UNITS.get(q, '-')})\nref: {comparison.reference_for(q)}" for q in quantities],
                  fontsize=7)
    ax.set_ylim(len(quantities) - 0.5, -0.5)
    half = max(1.5 * spread, 0.05)
    ax.set_xlim(-half, 2.2 * half)     # room on the right for the printed values
    ax.set_xlabel("difference to the reference (%)")
    ax.set_title("agreement with the reference", fontsize=10)
    ax.grid(axis="x", alpha=0.3)
    _legend(ax, fontsize=7, loc="lower right")


def _profile_panel(ax, comparison, pname: str, key: str) -> None:
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
    _legend(ax, fontsize=7)


def _normal_is_perfect(case) -> bool:
    laws = [p.law for p in case.interfaces] + [z[1] for p in case.interfaces for z in p.zones]
    return bool(laws) and all(getattr(law, "perfect_normal", False) for law in laws)


def _tangential_jump_scale(comparison) -> float:
    peak = 0.0
    for r in comparison.results.values():
        v = np.asarray(r.profiles.get("interface_jump", {}).get("jump_t", []), dtype=float)
        if v.size and np.isfinite(v).any():
            peak = max(peak, float(np.nanmax(np.abs(v))))
    return 1.1 * peak


def sweep_quantities(sweep) -> list[str]:
    """Quantities worth a panel: given by two or more methods (or all of a single
    method's headline quantities) and not constant over the sweep."""
    def values(q, m):
        v = np.array(sweep.series(m, q), dtype=float)
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


CURVE_MARKERS = ("o", "s", "^", "D", "v", "P")
CURVE_LINES = ("-", "--", ":", "-.")


def plot_sweep(sweep, path, x_transform: str | None = None, quantities=None) -> Path:
    """Each quantity against the swept parameter, one line per method and curve
    (colour: method; line style and marker: curve, when the sweep has several).

    ``x_transform="inverse"`` plots against 1/value (e.g. stiffness vs 1/Dt as 000 Fig 7
    and 002 Fig 5); infinite values then sit at 0. ``"log"`` uses a log axis on which
    the limits 0 and inf (debonded, perfect) sit one decade beyond the finite values,
    at ticks labelled 0 and inf (000 Fig 13).
    """
    quantities = list(quantities) if quantities else sweep_quantities(sweep)
    n = max(1, len(quantities))
    ncol = min(2, n)
    nrow = math.ceil(n / ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(5.2 * ncol, 3.8 * nrow), squeeze=False)
    axes = axes.ravel()
    xplot, limits = _sweep_x(np.asarray(sweep.values, dtype=float), x_transform)
    for ax, q in zip(axes, quantities):
        for c, label in enumerate(sweep.labels):
            for m in sweep.methods:
                _sweep_line(ax, xplot, np.array(sweep.series(m, q, c), dtype=float), m, label, c)
        ax.set_xlabel(f"1/{sweep.param}" if x_transform == "inverse" else sweep.param)
        ax.set_ylabel(f"{q} ({UNITS.get(q, '')})")
        if x_transform == "log":
            ax.set_xscale("log")
            _limit_ticks(ax, limits)
        ax.grid(alpha=0.3)
        _legend(ax, fontsize=8)
    return _finish(fig, axes[n:], f"{sweep.case_name}: sweep of {sweep.param}", path)


def _sweep_line(ax, xplot, y, method: str, label: str, curve: int) -> None:
    ok = np.isfinite(y) & np.isfinite(xplot)
    if not ok.any():
        return
    st = _style(method)
    ls, marker = (CURVE_LINES[curve % len(CURVE_LINES)], CURVE_MARKERS[curve % len(CURVE_MARKERS)]) \
        if label else (st["ls"], st["marker"] or ".")
    order = np.argsort(xplot[ok])
    ax.plot(xplot[ok][order], y[ok][order], color=st["color"], ls=ls, marker=marker, lw=st["lw"],
            mfc="none" if label and method != "analytic" else None, label=f"{method} {label}".strip())


def _sweep_x(xs: np.ndarray, x_transform: str | None):
    """Plot positions of the swept values, and {position: tick label} of the limits
    placed on a log axis."""
    with np.errstate(divide="ignore"):
        if x_transform == "inverse":
            return 1.0 / xs, {}
    if x_transform != "log":
        return xs, {}
    finite = xs[np.isfinite(xs) & (xs > 0)]
    if not finite.size:
        return xs, {}
    lo, hi = float(finite.min()), float(finite.max())
    x = xs.copy()
    limits = {}
    if (xs == 0).any():
        x[xs == 0] = lo / 10.0
        limits[lo / 10.0] = "0"
    if np.isposinf(xs).any():
        x[np.isposinf(xs)] = hi * 10.0
        limits[hi * 10.0] = "inf"
    return x, limits


def _limit_ticks(ax, limits: dict) -> None:
    """Decade ticks between the limits, and the limits' own labels."""
    if not limits:
        return
    lo, hi = ax.get_xlim()
    decades = [10.0 ** k for k in range(math.ceil(math.log10(lo)), math.floor(math.log10(hi)) + 1)]
    ticks = sorted({t for t in decades if all(abs(math.log10(t / p)) > 0.5 for p in limits)} | set(limits))
    ax.set_xticks(ticks)
    ax.set_xticklabels([limits.get(t, f"$10^{{{round(math.log10(t))}}}$") for t in ticks])
    ax.minorticks_off()
