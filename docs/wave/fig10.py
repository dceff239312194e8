"""002 Fig 10: energy transmitted through an imperfect interface against Dn, by the exact
pulse solution, transient FEM and MPM, for a linear interface ("L") and the bilinear
interface perfect in compression ("NL"), tensile and compressive pulses.

    python docs/wave/fig10.py [--mpm-cell 0.5] [--fem-h 0.5] [--out docs/wave]

Each series is one ``imperfect sweep`` (the same code, cases.sweep.sweep), e.g. the
linear interface with a tensile pulse:

    imperfect sweep wave --param Dn --values 3800,7000,12000,20000,30000,50000,121000 \
        --methods analytic,fem,mpm --set mpm_cell=0.5 --set fem_h=0.5 --set height=2 \
        --quantities transmitted_energy,pulse_transmitted_energy --x log --out out/wave_L

and ``--set nonlinear=true --set amplitude=1e-4`` for the NL compressive pulse (the
case then runs FEM with central differences, which close interpenetrating node pairs;
MPM applies the bilinear law at its multimaterial nodes). Writes
``wave_fig10.png`` and ``wave_fig10.csv`` (every point, every method) to --out.
"""
from __future__ import annotations

import csv
import math

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from cases.registry import build  # noqa: E402
from wave_args import parse  # noqa: E402 (docs/wave)
from cases.sweep import sweep  # noqa: E402
from interfaces.analytic.waves import pulse_transmission, wave_transmission  # noqa: E402

DN = (3800.0, 7000.0, 12000.0, 20000.0, 30000.0, 50000.0, 121000.0)
SERIES = {  # label: (nonlinear, amplitude x0 in mm, methods)
    "L tensile": (False, -1e-4, "analytic,fem,mpm"),
    "L compressive": (False, 1e-4, "analytic,fem,mpm"),
    "NL tensile": (True, -1e-4, "analytic,fem,mpm"),
    "NL compressive": (True, 1e-4, "analytic,fem,mpm"),
}
MARKERS = {"L tensile": "o", "L compressive": "^", "NL tensile": "v", "NL compressive": "D"}
COLORS = {"L tensile": "tab:blue", "L compressive": "tab:green", "NL tensile": "tab:orange",
          "NL compressive": "tab:red"}


def main() -> None:
    a, out = parse(__doc__, workers=(int, 1))
    rows = []
    fig, ax = plt.subplots(figsize=(7.0, 4.6))
    base = build("wave", height=a.height)
    Z = base.analytic["rho"] * base.analytic["v"]
    f = base.analytic["f"]
    dense = np.logspace(math.log10(2500.0), math.log10(3e5), 200)
    ax.plot(dense, [pulse_transmission(f, d, Z)["peak_ratio_squared"] for d in dense], "k-", lw=1.2,
            label="exact pulse, peak measure (L; NL tensile)")
    ax.plot(dense, [wave_transmission(f, d, Z) for d in dense], color="0.6", ls="--", lw=1.0,
            label="Eq 48, harmonic wave")
    ax.axhline(1.0, color="k", lw=0.8, ls=":", label="exact NL compressive (closed: perfect)")
    for label, (nonlinear, amp, methods) in SERIES.items():
        sw = sweep("wave", "Dn", DN, methods,
                   fixed={"nonlinear": nonlinear, "amplitude": amp, "mpm_cell": a.mpm_cell,
                          "fem_h": a.fem_h, "height": a.height}, workers=a.workers)
        for err in sw.errors():
            print(f"{label}: {err}")
        for m in sw.methods:
            T = [sw.value(i, m, "transmitted_energy") for i in range(len(DN))]
            E = [sw.value(i, m, "pulse_transmitted_energy") for i in range(len(DN))]
            rows += [[label, m, d, t, e] for d, t, e in zip(DN, T, E)]
            if m != "analytic":
                fem_style = m == "fem"
                ax.plot(DN, T, ls="none", marker=MARKERS[label], mfc="none" if fem_style else COLORS[label],
                        mec=COLORS[label], ms=9 if fem_style else 4.5, mew=1.2,
                        label=f"{m.upper()} {label}")
    ax.set_xscale("log")
    ax.set_xlabel("Dn (MPa/mm)")
    ax.set_ylabel("transmitted energy (peak ratio squared)")
    ax.set_title(f"002 Fig 10: half-sine pulse, f = {f / 1e3:g} kHz, uniaxial strain "
                 f"(MPM {a.mpm_cell:g} mm cells, FEM {a.fem_h:g} mm Q1)", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="lower right", ncol=2)
    fig.tight_layout()
    fig.savefig(out / "wave_fig10.png", dpi=130)
    with open(out / "wave_fig10.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["series", "method", "Dn", "transmitted_energy", "pulse_transmitted_energy"])
        w.writerows(rows)
    print(f"wrote {out / 'wave_fig10.png'}, {out / 'wave_fig10.csv'}")


if __name__ == "__main__":
    main()
