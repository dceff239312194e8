"""002 Fig 11: shapes of the incident, transmitted and reflected stress pulses at an
imperfect interface transmitting about half the energy, exact, transient FEM and MPM.

    python docs/wave/fig11.py [--Dn 24000] [--mpm-cell 0.5] [--fem-h 0.5] [--out docs/wave]

The histories are the two stress gauges of the ``wave`` case
(``Result.diagnostics["gauges"]``): the incident gauge 25 mm before the interface
records the incident pulse and, later, the reflected one; the transmitted gauge 25 mm
after it the transmitted pulse. Each is plotted against the time since its front
passed the gauge (the record shifted by the travel time from the left edge, via the
interface for the transmitted and the reflected pulse), with the exact histories of ``interfaces.analytic.waves.pulse_histories``
(s0 = Z pi f |x0|). Writes ``wave_fig11.png`` and ``wave_fig11.csv``.
"""
from __future__ import annotations

import csv

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import fem  # noqa: E402
import mpm  # noqa: E402
from cases.registry import build  # noqa: E402
from wave_args import parse  # noqa: E402 (docs/wave)
from interfaces.analytic import solve as analytic_solve  # noqa: E402
from interfaces.analytic.waves import pulse_histories  # noqa: E402

PULSES = {"incident": "k", "transmitted": "tab:blue", "reflected": "tab:red"}


def shifted(gauges: dict, spec: dict, c: float) -> dict:
    """Gauge records as pulse shapes: time since each pulse's front passed the gauge."""
    t = np.asarray(gauges["time"])
    x_int, x_i, x_t = spec["x_interface"], spec["x_incident"], spec["x_transmitted"]
    s_i = np.asarray(gauges["sigma_xx_x_incident"])
    s_t = np.asarray(gauges["sigma_xx_x_transmitted"])
    split = (2.0 * x_int - x_i) / c          # the reflection reaches the incident gauge
    return {"incident": (t[t < split] - x_i / c, s_i[t < split]),
            "reflected": (t[t >= split] - split, s_i[t >= split]),
            "transmitted": (t - x_t / c, s_t)}


def main() -> None:
    a, out = parse(__doc__, Dn=(float, 24000.0))
    case = build("wave", Dn=a.Dn, mpm_cell=a.mpm_cell, fem_h=a.fem_h, height=a.height)
    spec = case.measurements["transmitted_energy"]
    c, Z, f = case.analytic["v"], case.analytic["rho"] * case.analytic["v"], case.analytic["f"]
    x0 = case.boundary_conditions[0].value[0]
    s0 = Z * np.pi * f * abs(x0)
    results = {"MPM": mpm.solve(case, progress=False), "FEM": fem.solve(case)}
    t = np.linspace(-0.1 / f, 1.5 / f, 600)
    exact = pulse_histories(f, a.Dn, Z, t=t, s0=s0)
    fig, ax = plt.subplots(figsize=(7.0, 4.4))
    rows = []
    for name, color in PULSES.items():
        ax.plot(t * 1e6, exact[name], color=color, lw=1.4, ls="--" if name == "incident" else "-",
                label=f"exact {name}")
        rows += [["exact", name, ti, si] for ti, si in zip(t, exact[name])]
    styles = {"MPM": dict(ls="none", marker="o", ms=2.5), "FEM": dict(ls=":", lw=1.6)}
    for method, r in results.items():
        for name, (tm, sm) in shifted(r.diagnostics["gauges"], spec, c).items():
            keep = (tm >= t[0]) & (tm <= t[-1])
            step = max(1, keep.sum() // 150) if method == "MPM" else 1
            ax.plot(tm[keep][::step] * 1e6, sm[keep][::step], color=PULSES[name], **styles[method],
                    label=f"{method} {name}")
            rows += [[method, name, ti, si] for ti, si in zip(tm[keep], sm[keep])]
    q = results["MPM"].quantities, results["FEM"].quantities
    T_exact = analytic_solve(case).quantities["transmitted_energy"]
    ax.axhline(0.0, color="0.5", lw=0.6)
    ax.set_xlabel("time since the front of each pulse passed its gauge (us)")
    ax.set_ylabel("sigma_xx (MPa)")
    ax.set_title(f"002 Fig 11: tensile pulse, Dn = {a.Dn:g} MPa/mm; T "
                 f"exact {T_exact:.3f}, MPM {q[0]['transmitted_energy']:.3f}, FEM {q[1]['transmitted_energy']:.3f}",
                 fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=3, loc="upper right")
    fig.tight_layout()
    fig.savefig(out / "wave_fig11.png", dpi=130)
    with open(out / "wave_fig11.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["source", "pulse", "time_s", "sigma_xx_MPa"])
        w.writerows(rows)
    print(f"wrote {out / 'wave_fig11.png'}, {out / 'wave_fig11.csv'}")


if __name__ == "__main__":
    main()
