"""004 Fig 6 over several packings: how much of LR's margin over DF is the packing's.

004 drew its 20 ellipses by hand; the case generates them from a seed
(:func:`cases.packing.ellipse_packing`). This script runs LR and DF (lumped 3+ nodes) on
the packings of several seeds at one cell size, with the runs of
ellipse_compaction_fig6.py (stored per run in ``--store``, reused when present), and
writes ellipse_compaction_packings.png and .csv here: per packing the final mean axial
stress of LR and DF, LR / DF, and the particles inside another ellipse.

    PYTHONPATH=. python docs/contact/ellipse_compaction_packings.py --cell 0.025 --seeds 2004,2005,2006,2007 --option shape=cpdi --option xpic=5
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from ellipse_compaction_fig6 import solve  # noqa: E402

from interfaces.errors import SolverError  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cell", type=float, default=0.025, help="MPM cell (mm); 004: 0.0143")
    ap.add_argument("--strain", type=float, default=0.75)
    ap.add_argument("--seeds", default="2004,2005,2006,2007", help="packing seeds, comma separated")
    ap.add_argument("--option", action="append", default=[], help="mpm option key=value")
    ap.add_argument("--store", default="out/ellipse_fig6", help="folder of the per-run .npz files")
    args = ap.parse_args()
    args.three_material = "lump"
    store = Path(args.store)
    rows = ["seed,LR_GPa,DF_GPa,LR_over_DF,LR_inside,DF_inside,particles"]
    seeds, ratios = [], []
    for seed in (int(s) for s in args.seeds.split(",")):
        args.seed = seed
        try:
            lr, df = solve("LR", args, store), solve("DF", args, store)
        except SolverError as e:         # one failed packing does not lose the others
            rows.append(f"{seed},failed: {str(e).replace(',', ';')},,,,,")
            print(rows[-1], flush=True)
            continue
        s_lr, s_df = lr["stress"][-1] / 1e3, df["stress"][-1] / 1e3
        rows.append(f"{seed},{s_lr:.2f},{s_df:.2f},{s_lr / s_df:.3f},{int(lr['interpenetration'])},"
                    f"{int(df['interpenetration'])},{int(lr['particles'])}")
        print(rows[-1], flush=True)
        seeds.append(seed)
        ratios.append((s_lr, s_df))
    (HERE / "ellipse_compaction_packings.csv").write_text("\n".join(rows) + "\n")
    if not ratios:
        raise SystemExit("no packing finished")
    s = np.array(ratios)
    x = np.arange(len(seeds))
    fig, ax = plt.subplots(figsize=(1.6 + 1.3 * len(seeds), 4.5))
    ax.bar(x - 0.2, s[:, 0], 0.4, label="LR")
    ax.bar(x + 0.2, s[:, 1], 0.4, label="DF")
    for k in x:
        ax.annotate(f"{s[k, 0] / s[k, 1]:.2f}x", (k, s[k].max()), ha="center", va="bottom")
    ax.set_xticks(x, [str(v) for v in seeds])
    ax.set_xlabel("packing seed")
    ax.set_ylabel(f"mean axial stress at {100 * args.strain:g} % (GPa)")
    ax.set_ylim(0, 1.3 * s.max())
    ax.legend(loc="upper left", ncol=2)
    ax.set_title(f"004 Fig 6: LR / DF per packing\n({args.cell:g} mm cells, {', '.join(args.option)}, "
                 "lumped 3+ nodes)", fontsize=9)
    fig.tight_layout()
    fig.savefig(HERE / "ellipse_compaction_packings.png", dpi=110)


if __name__ == "__main__":
    main()
