"""Summarise the MPM validation sweeps of issue #4 into CSV tables and figures.

Reads ``sweep.csv`` files written by ``imperfect sweep`` (commands in README.md,
Validation) and writes, next to this script:

* ``dls_01_normals.csv`` / ``.png``: 002 Sec 3.1 DLS at 0.1 mm cells, MPM stiffness
  relative to quadratic FEM and to shear lag (002 Eq 40-42) against 1/Dt, one curve per
  normal method (SN, MVG, AVG; 000 Sec 2.5, Fig 7) and AVG with edge screening;
* ``dls_rotated.csv`` / ``.png``: the 000 DLS rotated against the grid (000 Fig 9),
  stiffness relative to the unrotated run, regular grid and dy = 2 dx with and without
  h-perp (000 Eq 22, method 1).

Usage: python docs/mpm_validation/summarise.py SWEEP_ROOT  (directories dls_01_SN, dls_01_MVG, dls_01_AVG, dls_01_AVG_screened,
rot_regular, rot_dy2dx_ellipse_tangent, rot_dy2dx_none under SWEEP_ROOT)
"""
from __future__ import annotations

import csv
import math
import sys
from collections import defaultdict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = Path(__file__).resolve().parent
NORMAL_STYLE = {"SN": dict(marker="o", ms=8, ls="-"), "MVG": dict(marker="s", ms=5, ls="--"),
                "AVG": dict(marker="^", ms=6, ls=":"),
                "AVG, edge cutoff 0.85": dict(marker="v", ms=6, ls="-.")}
#: sweep directory suffix -> label (AVG screened: --option mpm.edge_cutoff=0.85, 000 Sec 3)
NORMAL_RUNS = {"SN": "SN", "MVG": "MVG", "AVG": "AVG", "AVG_screened": "AVG, edge cutoff 0.85"}


def _read(path: Path) -> dict:
    """{(parameter value, method, quantity): value} of one sweep.csv."""
    out = {}
    with open(path) as fh:
        rows = csv.DictReader(fh)
        param = rows.fieldnames[0]
        for r in rows:
            out[(float(r[param]), r["method"], r["quantity"])] = float(r["value"])
    return out


def normals(root: Path) -> None:
    rows, curves = [], defaultdict(list)
    for run, normal in NORMAL_RUNS.items():
        path = root / f"dls_01_{run}" / "sweep.csv"
        if not path.exists():
            continue
        d = _read(path)
        for Dt in sorted({k[0] for k in d}):
            k_mpm, k_fem = d[(Dt, "mpm", "stiffness")], d[(Dt, "fem", "stiffness")]
            k_sl = d[(Dt, "analytic", "stiffness")]
            ke = d[(Dt, "mpm", "stiffness_energy")]
            rows.append([normal, Dt, k_mpm, ke, k_fem, k_sl, 100 * (k_mpm / k_fem - 1),
                         100 * (k_mpm / k_sl - 1), 100 * (ke / k_fem - 1)])
            curves[normal].append((0.0 if math.isinf(Dt) else 1.0 / Dt, 100 * (k_mpm / k_fem - 1),
                                   100 * (k_mpm / k_sl - 1)))
    with open(HERE / "dls_01_normals.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["normal", "Dt", "k_mpm", "k_energy_mpm", "k_fem", "k_shear_lag",
                    "mpm_vs_fem_pct", "mpm_vs_shear_lag_pct", "k_energy_vs_fem_pct"])
        w.writerows(rows)
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8), sharey=True)
    for normal, pts in curves.items():
        pts.sort()
        x = [p[0] for p in pts]
        for ax, j in zip(axes, (1, 2)):
            ax.plot(x, [p[j] for p in pts], label=normal, **NORMAL_STYLE[normal])
    for ax, ref in zip(axes, ("quadratic FEM", "shear lag (002 Eq 40-42)")):
        ax.axhline(0.0, color="k", lw=0.8)
        ax.set_xlabel("1/Dt (mm/MPa)")
        ax.set_title(f"MPM stiffness vs {ref}", fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend(title="normal", fontsize=8)
    axes[0].set_ylabel("difference (%)")
    fig.suptitle("002 DLS, MPM 0.1 mm cells, 2x2 particles per cell", fontsize=10)
    fig.tight_layout()
    fig.savefig(HERE / "dls_01_normals.png", dpi=120)
    plt.close(fig)


def rotated(root: Path) -> None:
    runs = {"regular grid 0.25 mm": "rot_regular",
            "dx = 0.25, dy = 0.5 mm, h-perp method 1": "rot_dy2dx_ellipse_tangent",
            "dx = 0.25, dy = 0.5 mm, no h-perp correction": "rot_dy2dx_none"}
    rows = []
    fig, ax = plt.subplots(figsize=(6.5, 4))
    base = None
    for label, name in runs.items():
        path = root / name / "sweep.csv"
        if not path.exists():
            continue
        d = _read(path)
        angles = sorted({k[0] for k in d})
        if base is None:
            base = d[(0.0, "mpm", "stiffness")]
        for a in angles:
            rows.append([label, a, d[(a, "mpm", "stiffness")], d[(a, "mpm", "stiffness_energy")],
                         100 * (d[(a, "mpm", "stiffness")] / base - 1)])
        ax.plot(angles, [100 * (d[(a, "mpm", "stiffness")] / base - 1) for a in angles],
                marker="o", label=label)
    if base is None:
        plt.close(fig)
        return
    with open(HERE / "dls_rotated.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["grid", "angle_deg", "k_mpm", "k_energy_mpm", "vs_regular_0deg_pct"])
        w.writerows(rows)
    ax.axhline(0.0, color="k", lw=0.8)
    for y in (-3, 3):
        ax.axhline(y, color="0.6", lw=0.8, ls="--")
    ax.set_xlabel("rotation angle (deg)")
    ax.set_ylabel("stiffness vs regular grid at 0 deg (%)")
    ax.set_title("000 DLS (Dt = 5, Dn = inf) rotated against the grid (000 Fig 9)", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(HERE / "dls_rotated.png", dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    root = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    normals(root)
    rotated(root)
    print(f"wrote {HERE}/dls_01_normals.csv/.png, dls_rotated.csv/.png")
