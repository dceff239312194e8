"""004 Fig 5: (MM - SMM) / SMM of the mean axial stress against compression strain.

Two identical neo-Hookean blocks in contact (case ``compression_20``) compressed to 20 %
by a rigid piston, one run per contact method, against the single-material run of the
same stack (``contact = single``). Writes compression_20_fig5.png and .csv here.

    PYTHONPATH=. python docs/contact/compression_20_fig5.py
"""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import cases  # noqa: E402
from cases.contact import CONTACT_METHODS, compression_strain  # noqa: E402
from cases.methods import run  # noqa: E402

HERE = Path(__file__).resolve().parent
COLORS = dict(zip(CONTACT_METHODS, ("tab:gray", "tab:orange", "tab:green", "tab:blue", "tab:red")))
#: strains below this carry too little stress for a meaningful ratio
FROM_STRAIN = 0.01


def stress_history(contact: str) -> tuple[np.ndarray, np.ndarray]:
    """(compression strain, mean axial stress, compression positive) of one run."""
    case = cases.build("compression_20", contact=contact)
    res = run(case, "mpm", progress=False)
    g = res.diagnostics["gauges"]
    return compression_strain(case, g["time"]), -np.asarray(g["axial_stress"])


def relative_errors() -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """(strain, (MM - SMM) / SMM) per contact method, from FROM_STRAIN on."""
    e_ref, s_ref = stress_history("single")
    keep = e_ref >= FROM_STRAIN
    out = {}
    for contact in CONTACT_METHODS:
        e, s = stress_history(contact)
        out[contact] = (e_ref[keep], np.interp(e_ref[keep], e, s) / s_ref[keep] - 1.0)
    return out


def main() -> None:
    errors = relative_errors()
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6))
    rows = ["contact,max_abs_error_percent,error_at_20_percent"]
    for contact, (e, r) in errors.items():
        for ax in axes:
            ax.plot(100 * e, 100 * r, color=COLORS[contact], label=contact)
        rows.append(f"{contact},{100 * np.abs(r).max():.3f},{100 * r[-1]:.3f}")
        print(rows[-1], flush=True)
    for ax in axes:
        ax.axhline(0.0, color="k", lw=0.8)
        ax.set_xlabel("compression strain (%)")
        ax.set_ylabel("(MM - SMM) / SMM, mean axial stress (%)")
    axes[1].set_ylim(-1.0, 1.0)
    axes[1].set_title("zoom: +-1 %", fontsize=10)
    axes[0].set_title("004 Fig 5: two blocks in contact against one block (5 mm cells)", fontsize=10)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(HERE / "compression_20_fig5.png", dpi=130)
    (HERE / "compression_20_fig5.csv").write_text("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
