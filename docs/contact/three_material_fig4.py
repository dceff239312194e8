"""004 Fig 4: three blocks meeting at a node, compressed 5 %, lumping against explicit pairs.

Case ``three_material_node``: a lower block and two upper blocks side by side, LR contact,
compressed by a bonded rigid piston; the 3+ nodes lumped (004 Eq 50) or treated pair by
pair (004 Sec 3.4, Eq 49), each against single-material MPM of the same region (the
blocks are identical, so any difference is an error of the contact treatment). Writes
three_material_fig4.png and .csv here:

* left: particles near the meeting point at their start positions moved by 10 x their
  displacement error u - u_SMM at the end, coloured by |u - u_SMM| / cell;
* right: (MM - SMM) / SMM of the mean axial stress against compression strain.

    PYTHONPATH=. python docs/contact/three_material_fig4.py
"""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import cases  # noqa: E402
from cases.contact import compression_strain  # noqa: E402
from cases.methods import run  # noqa: E402

HERE = Path(__file__).resolve().parent
CELL = 5.0
MAGNIFY = 10.0
RUNS = [("lump", "grid"), ("explicit", "grid"), ("lump", "mid"), ("explicit", "mid")]


def solve(contact: str, three: str, plane: str):
    case = cases.build("three_material_node", contact=contact, three_material=three, plane=plane)
    res = run(case, "mpm", progress=False)
    g = res.diagnostics["gauges"]
    return case, res, compression_strain(case, g["time"]), -np.asarray(g["axial_stress"])


def deviation(res, ref) -> tuple[np.ndarray, np.ndarray]:
    """Start positions and displacement errors u - u_SMM of the blocks' particles (matched
    to the single-material run by their start positions)."""
    blocks = res.fields["material"] < 3
    x0 = res.fields["position"][blocks]
    u = res.fields["displacement"][blocks]
    ref_blocks = ref.fields["material"] < 1
    index = {tuple(k): i for i, k in enumerate(np.round(ref.fields["position"][ref_blocks] * 1e3).astype(int))}
    j = np.array([index[tuple(k)] for k in np.round(x0 * 1e3).astype(int)])
    return x0, u - ref.fields["displacement"][ref_blocks][j]


def main() -> None:
    _, ref, e_ref, s_ref = solve("single", "lump", "grid")
    fig, axes = plt.subplot_mosaic([["lump grid", "explicit grid", "stress"],
                                    ["lump mid", "explicit mid", "stress"]], figsize=(15, 9),
                                   width_ratios=[1, 1.25, 1.6])
    rows = ["three_material,plane,max_u_deviation_cells,rms_u_deviation_cells,"
            "axial_stress_error_percent_at_end,max_abs_axial_stress_error_percent"]
    for three, plane in RUNS:
        case, res, e, s = solve("LR", three, plane)
        x0, du = deviation(res, ref)
        dev = np.linalg.norm(du, axis=1) / CELL
        err = np.interp(e_ref[1:], e, s) / s_ref[1:] - 1.0
        rows.append(f"{three},{plane},{dev.max():.4f},{np.sqrt(np.mean(dev ** 2)):.4f},"
                    f"{100 * err[-1]:.3f},{100 * np.abs(err[e_ref[1:] > 0.005]).max():.3f}")
        print(rows[-1], flush=True)
        ax = axes[f"{three} {plane}"]
        xy = x0 + MAGNIFY * du
        sc = ax.scatter(*xy.T, c=dev, s=40, cmap="viridis", vmin=0.0, vmax=0.1, linewidths=1.5,
                        edgecolors=[f"C{m}" for m in res.fields["material"][res.fields["material"] < 3]])
        meet = np.array([20.0, 25.0]) + (0.5 * CELL if plane == "mid" else 0.0)
        ax.set_xticks(np.arange(0, 41, CELL))
        ax.set_yticks(np.arange(0, 51, CELL))
        ax.set_xlim(meet[0] - 2.2 * CELL, meet[0] + 2.2 * CELL)
        ax.set_ylim(meet[1] - 2.2 * CELL, meet[1] + 2.2 * CELL)
        ax.grid(True, lw=0.5, color="0.8")
        ax.set_aspect("equal")
        ax.set_title(f"{three}, meeting point {'on a node' if plane == 'grid' else 'mid-cell'}:\n"
                     f"max |u - u_SMM| = {dev.max():.3f} cell", fontsize=10)
        axes["stress"].plot(100 * e_ref[1:], 100 * err, ls="-" if plane == "grid" else "--",
                            color="tab:red" if three == "lump" else "tab:blue",
                            label=f"LR, {three}, {plane}")
    for key in ("explicit grid", "explicit mid"):
        fig.colorbar(sc, ax=axes[key], label="|u - u_SMM| / cell")
    ax = axes["stress"]
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_xlabel("compression strain (%)")
    ax.set_ylabel("(MM - SMM) / SMM, mean axial stress (%)")
    ax.legend()
    fig.suptitle(f"004 Fig 4: three blocks meeting at a node, compressed 5 %, LR contact (particles: "
                 f"start positions + {MAGNIFY:g} x (u - u_SMM); edge colour = block)")
    fig.tight_layout()
    fig.savefig(HERE / "three_material_fig4.png", dpi=110)
    (HERE / "three_material_fig4.csv").write_text("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
