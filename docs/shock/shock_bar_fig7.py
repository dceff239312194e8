"""004 Fig 7: a shock in a confined nickel bar, single material and split by a perfect
interface, and the shock speed and pressure against the Hugoniot.

Case ``shock_bar`` (Mie-Grueneisen nickel of 004 Eq 51 with the neo-Hookean shear of
Eq 18 and the artificial viscosity of Eq 52, 0.25 mm cells, 2 x 2 particles per cell,
B2 shape). Left: the particles' longitudinal stress along the bar at the end of the
run, one body (SMM) and two bodies joined at mid-length by a perfect interface (MM),
with a zoom on the front as 004 Fig 7 shows it. Right: shock speed and shocked pressure
and longitudinal stress (shock_front gauge, mpm/shock_front.py) over impact speeds
against the Hugoniot of the same material (interfaces.analytic.hugoniot). Bottom: the particle
updates 004 compares at 1840 m/s (B2 and B2-CPDI with FLIP, B2-CPDI with XPIC(5), and
XPIC(5) without the Delta v term of Eq 33, "uncorrected"): the front of the single body,
and the split bar's difference from it. Writes
shock_bar_fig7.png and .csv here.

    PYTHONPATH=. python docs/shock/shock_bar_fig7.py
"""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import cases  # noqa: E402
import mpm  # noqa: E402
from interfaces.analytic.hugoniot import ShockHugoniot  # noqa: E402

HERE = Path(__file__).resolve().parent
#: impact speeds (mm/s): 004 Fig 7 is 1840 m/s
SPEEDS = (5e5, 1e6, 1.84e6, 2.5e6)
QUANTITIES = ("shock_speed", "pressure", "longitudinal_stress")
#: particle updates of 004 Fig 7 at 1840 m/s (label, mpm options): 004 ran B2-CPDI with
#: XPIC(5), and showed that XPIC without the Delta v term of Eq 33 oscillates at the
#: perfect interface of the split bar
VARIANTS = (("B2, FLIP", {}),
            ("B2-CPDI, FLIP", {"shape": "b2cpdi"}),
            ("B2-CPDI, XPIC(5)", {"shape": "b2cpdi", "xpic": 5}),
            ("B2-CPDI, XPIC(5) uncorrected", {"shape": "b2cpdi", "xpic": 5, "xpic_correction": False}))


def shock_runs() -> list[tuple[float, dict, dict]]:
    """(impact speed, MPM quantities, Hugoniot state) per impact speed, one body."""
    out = []
    for v in SPEEDS:
        case = cases.build("shock_bar", impact_speed=v)
        q = mpm.solve(case, progress=False).quantities
        h = ShockHugoniot(**{k: case.analytic[k] for k in ("K", "rho", "S1", "gamma0", "G")})
        st = h.state(v)
        ref = {"shock_speed": st.shock_speed, "pressure": st.pressure,
               "longitudinal_stress": st.longitudinal_stress}
        out.append((v, q, ref))
        print(f"{v / 1e3:g} m/s: " + ", ".join(
            f"{k} {q[k]:.5g} / {ref[k]:.5g} ({100 * (q[k] / ref[k] - 1):+.2f} %)" for k in QUANTITIES),
            flush=True)
    return out


def particle_stress(split: bool, **options) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(reference position x0, current x, longitudinal compressive stress) of every
    particle at the end of the 1840 m/s run, sorted by reference position."""
    res = mpm.solve(cases.build("shock_bar", split=split), progress=False, **options)
    x0 = res.fields["position"]
    x = x0 + res.fields["displacement"]
    order = np.lexsort((x0[:, 1], x0[:, 0]))
    return x0[order], x[order], -res.fields["stress"][order, 0]


def variant_rows(sigma: float, length: float, cell: float):
    """Per particle update of VARIANTS at 1840 m/s: the scatter of the single body's
    particle stress behind the front (/ Hugoniot sigma), the largest split - single
    difference near the interface and anywhere, and the middle-row profiles."""
    rows, profiles = [], {}
    for label, options in VARIANTS:
        x0, x, s1 = particle_stress(False, **options)
        _, x_m, s2 = particle_stress(True, **options)
        behind = (x0[:, 0] > 25.0) & (x0[:, 0] < 45.0)
        dev = s1[behind] / sigma - 1.0
        near = np.abs(x0[:, 0] - 0.5 * length) <= 2.0 * cell
        diff = np.abs(s2 - s1)
        rows.append(f"# {label}: stress behind the front / Hugoniot sigma - 1: mean {dev.mean():.4f}, "
                    f"standard deviation {dev.std():.4f}, largest {np.abs(dev).max():.4f}; "
                    f"|split - single| near the interface {diff[near].max():.4g} MPa, anywhere "
                    f"{diff.max():.4g} MPa ({diff.max() / s1.max():.2e} of the peak)")
        print(rows[-1], flush=True)
        profiles[label] = (x0, x, s1, diff)
    return rows, profiles


def plot_variants(axes, profiles, length: float) -> None:
    """Bottom row: the front of the single body and |split - single| along the bar."""
    for k, (label, (x0, x, s1, diff)) in enumerate(profiles.items()):
        rows_y = np.unique(x0[:, 1])
        mid = np.isclose(x0[:, 1], rows_y[len(rows_y) // 2])
        axes[0].plot(x[mid, 0], s1[mid] / 1e3 + 20.0 * k, lw=0.9, label=f"{label} (+{20 * k} GPa)")
        axes[1].semilogy(x0[mid, 0], np.maximum(diff[mid], 1e-12), lw=0.9, label=label)
    axes[0].set_xlabel("x (mm)")
    axes[0].set_ylabel("-sigma_xx (GPa), curves offset")
    axes[0].set_title("1840 m/s, one body, middle row: particle updates", fontsize=10)
    axes[0].legend(fontsize=7)
    axes[1].axvline(0.5 * length, color="k", lw=0.6)
    axes[1].set_xlabel("x0 (mm)")
    axes[1].set_ylabel("|MM - SMM| of -sigma_xx (MPa)")
    axes[1].set_title("split bar (perfect interface at the line) against one body", fontsize=10)
    axes[1].legend(fontsize=7)


def main() -> None:
    runs = shock_runs()
    x0_s, x_s, s_s = particle_stress(False)
    x0_m, x_m, s_m = particle_stress(True)
    assert np.allclose(x0_s, x0_m)
    case = cases.build("shock_bar")
    length = 50.0
    cell = case.discretization["mpm"]["cell"]
    near = np.abs(x0_s[:, 0] - 0.5 * length) <= 2.0 * cell
    peak = s_s.max()
    d_near = np.abs(s_m - s_s)[near].max()
    d_all = np.abs(s_m - s_s).max()
    rows = ["impact_speed_m_s," + ",".join(f"{k}_mpm,{k}_hugoniot,{k}_error_percent" for k in QUANTITIES)]
    for v, q, ref in runs:
        rows.append(f"{v / 1e3:g}," + ",".join(
            f"{q[k]:.6g},{ref[k]:.6g},{100 * (q[k] / ref[k] - 1):.3f}" for k in QUANTITIES))
    rows.append(f"# split vs single at 1840 m/s: largest particle stress difference within 2 cells "
                f"of the interface {d_near:.4g} MPa ({100 * d_near / peak:.3f} % of the peak "
                f"{peak:.4g} MPa), anywhere {d_all:.4g} MPa ({100 * d_all / peak:.3f} %)")
    print(rows[-1])
    behind = (x0_s[:, 0] > 25.0) & (x0_s[:, 0] < 45.0)      # shocked, clear of front and wall
    sigma = runs[SPEEDS.index(1.84e6)][2]["longitudinal_stress"]
    dev = s_s[behind] / sigma - 1.0
    rows.append(f"# particle stress behind the front at 1840 m/s (x0 in 25..45 mm) / Hugoniot sigma - 1: "
                f"mean {dev.mean():.4f}, standard deviation {dev.std():.4f}, largest {np.abs(dev).max():.4f}")
    print(rows[-1])

    more, profiles = variant_rows(sigma, length, cell)
    rows += more
    fig, axes = plt.subplots(3, 2, figsize=(12, 12))
    plot_variants(axes[2], profiles, length)
    mid = np.isclose(x0_s[:, 1], np.unique(x0_s[:, 1])[len(np.unique(x0_s[:, 1])) // 2])
    ax = axes[0, 0]
    ax.plot(x_s[mid, 0], s_s[mid] / 1e3, "o-", ms=2.5, lw=0.8, color="tab:blue", label="SMM (one body)")
    ax.plot(x_m[mid, 0], s_m[mid] / 1e3, "s--", ms=2.5, lw=0.8, color="tab:red",
            label="MM (two bodies, perfect interface)")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("-sigma_xx (GPa)")
    ax.set_title("1840 m/s, particles of the middle row, end of run (full wave)", fontsize=10)
    ax.legend(fontsize=8)
    ax = axes[0, 1]
    front = x_s[mid, 0][np.argmax(s_s[mid] > 0.5 * np.median(s_s[mid][s_s[mid] > 0.5 * peak]))]
    zoom = np.abs(x_s[mid, 0] - front) < 2.0
    ax.plot(x_s[mid, 0][zoom], s_s[mid][zoom] / 1e3, "o-", ms=3, color="tab:blue", label="SMM")
    zoom_m = np.abs(x_m[mid, 0] - front) < 2.0
    ax.plot(x_m[mid, 0][zoom_m], s_m[mid][zoom_m] / 1e3, "s--", ms=3, color="tab:red", label="MM")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("-sigma_xx (GPa)")
    ax.set_title(f"zoom on the front (as 004 Fig 7); max |MM - SMM| near the interface\n"
                 f"{d_near:.2g} MPa ({d_near / peak:.1e} of the peak)", fontsize=9)
    ax.legend(fontsize=8)
    h = ShockHugoniot(**{k: case.analytic[k] for k in ("K", "rho", "S1", "gamma0", "G")})
    curve = h.curve(np.linspace(0.0, 1.1 * max(SPEEDS), 60))
    v = np.array([r[0] for r in runs])
    ax = axes[1, 0]
    ax.plot(curve["particle_speed"] / 1e6, curve["shock_speed"] / 1e6, "k-", label="Hugoniot")
    ax.plot(v / 1e6, [r[1]["shock_speed"] / 1e6 for r in runs], "o", color="tab:red", label="MPM")
    ax.set_xlabel("impact speed (km/s)")
    ax.set_ylabel("shock speed U_s (km/s)")
    ax.legend(fontsize=8)
    ax = axes[1, 1]
    ax.plot(curve["particle_speed"] / 1e6, curve["pressure"] / 1e3, "k-", label="Hugoniot p")
    ax.plot(curve["particle_speed"] / 1e6, curve["longitudinal_stress"] / 1e3, "k--",
            label="Hugoniot sigma")
    ax.plot(v / 1e6, [r[1]["pressure"] / 1e3 for r in runs], "o", color="tab:red", label="MPM p")
    ax.plot(v / 1e6, [r[1]["longitudinal_stress"] / 1e3 for r in runs], "^", color="tab:orange",
            label="MPM sigma")
    ax.set_xlabel("impact speed (km/s)")
    ax.set_ylabel("shocked pressure / longitudinal stress (GPa)")
    ax.legend(fontsize=8)
    fig.suptitle("004 Fig 7: shock in a confined nickel bar (Mie-Grueneisen Eq 51, viscosity Eq 52, "
                 "0.25 mm cells, B2)", fontsize=10)
    fig.tight_layout()
    fig.savefig(HERE / "shock_bar_fig7.png", dpi=120)
    (HERE / "shock_bar_fig7.csv").write_text("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
