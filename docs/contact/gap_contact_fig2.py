"""004 Fig 2B: mean axial stress of the struck block against time, per contact method.

Two neo-Hookean blocks close a 7.5 mm gap (case ``gap_contact``); solid curves with the
contact plane on a grid line, dashed with it mid-cell; time in units of the theoretical
contact time (gap / push speed + one transit). Writes gap_contact_fig2.png and .csv here.

    PYTHONPATH=. python docs/contact/gap_contact_fig2.py
"""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import cases  # noqa: E402
from cases.contact import CONTACT_METHODS  # noqa: E402
from cases.methods import run  # noqa: E402

HERE = Path(__file__).resolve().parent
COLORS = dict(zip(CONTACT_METHODS, ("tab:gray", "tab:orange", "tab:green", "tab:blue", "tab:red")))
LABELS = {"velocity": "velocity only (Eq 14)", "CP0.92": "CP = 0.92", "CP0.80": "CP = 0.80",
          "DF": "DF (Eq 15)", "LR": "LR"}


def main() -> None:
    fig, (ax, zoom) = plt.subplots(1, 2, figsize=(12, 4.8))
    rows = ["plane,contact,contact_time_s,theory_s,ratio"]
    for plane, ls in (("grid", "-"), ("mid", "--")):
        for contact in CONTACT_METHODS:
            case = cases.build("gap_contact", contact=contact, plane=plane)
            t_ref = run(case, "analytic").quantities["contact_time"]
            res = run(case, "mpm", progress=False)
            g = res.diagnostics["gauges"]
            t, s = np.asarray(g["time"]) / t_ref, -np.asarray(g["axial_stress"])
            for a in (ax, zoom):
                a.plot(t, s, ls=ls, color=COLORS[contact],
                       label=f"{LABELS[contact]}, {'grid line' if plane == 'grid' else 'mid-cell'}")
            tc = res.quantities["contact_time"]
            rows.append(f"{plane},{contact},{tc:.6g},{t_ref:.6g},{tc / t_ref:.4f}")
            print(rows[-1], flush=True)
    for a in (ax, zoom):
        a.axvline(1.0, color="k", lw=0.8)
        a.text(1.003, 0.9, "theoretical\ncontact", transform=a.get_xaxis_transform(), fontsize=8)
        a.set_xlabel("time / theoretical contact time")
    ax.set_xlim(0.0, 1.1)
    zoom.set_xlim(0.6, 1.1)
    zoom.set_ylim(-1.0, 25.0)
    zoom.set_title("near contact (zoom)", fontsize=10)
    ax.set_ylabel("mean axial stress of the lower block, compression (MPa)")
    ax.set_title("004 Fig 2: two blocks closing a 7.5 mm gap (5 mm cells, AG normals)", fontsize=10)
    ax.legend(fontsize=7, ncol=2, loc="upper left")
    fig.tight_layout()
    fig.savefig(HERE / "gap_contact_fig2.png", dpi=130)
    (HERE / "gap_contact_fig2.csv").write_text("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
