"""004 Fig 6: compaction of 20 ellipses in a box, LR against grid-based contact.

Case ``ellipse_compaction`` (each ellipse its own neo-Hookean aluminium material, rigid
walls, a rigid piston at 100 m/s, 75 % compression), one run per contact method. Each
run's history and final particles are kept in ``--store`` (one .npz per run, reused when
present, so an interrupted figure loses at most the run in progress). Writes
ellipse_compaction_fig6.png and .csv here: the mean axial stress of the ellipses against
compression, the final particle domains (x + F [-l, l]^2, the particle shapes 004
draws) coloured by ellipse with the particles found inside another ellipse
(``interpenetration``) in black, and per method the final stress, the
interpenetration count, the particles cut off from their own ellipse (their four
nearest particles all of other ellipses: carried about a particle or more into another
ellipse, whatever the shapes of the domains), the ellipses' current area over the box's area
(``material_area_over_container``: above 1, material overlaps material, whatever the
particle count says) and the run time (wall and CPU).

    PYTHONPATH=. python docs/contact/ellipse_compaction_fig6.py --cell 0.05 --contacts DF,LR,CP0.80 --option shape=cpdi --option xpic=5
    PYTHONPATH=. python docs/contact/ellipse_compaction_fig6.py --cell 0.0143 --contacts LR,LR/explicit,DF --option shape=cpdi --option xpic=5
"""
from __future__ import annotations

import argparse
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
import numpy as np  # noqa: E402

import cases  # noqa: E402
from cases.cli import parse_value  # noqa: E402
from cases.contact import compression_strain  # noqa: E402
from cases.methods import run  # noqa: E402
from interfaces.errors import SolverError  # noqa: E402
from mpm.interpenetration import cut_off_from_own_material, inside_other_material  # noqa: E402

HERE = Path(__file__).resolve().parent


def split_run(label: str, default_three_material: str) -> tuple[str, str]:
    """``LR`` or ``LR/explicit``: the contact method and the 3+ material node treatment."""
    contact, _, three_material = label.partition("/")
    return contact, three_material or default_three_material


def solve(label: str, args, store: Path) -> dict:
    """One run (or its stored copy): strain and stress histories, final particles, timing."""
    contact, three_material = split_run(label, args.three_material)
    seed = [] if args.seed is None else [f"seed{args.seed}"]
    tag = "_".join([contact, three_material, f"cell{args.cell:g}", f"strain{args.strain:g}"] + seed
                   + [o.replace("=", "") for o in args.option])
    path = store / f"{tag}.npz"
    if path.exists():
        return dict(np.load(path, allow_pickle=False))
    packing = {} if args.seed is None else {"seed": args.seed}
    case = cases.build("ellipse_compaction", contact=contact, mpm_cell=args.cell, strain=args.strain,
                       three_material=three_material, **packing)
    options = dict(o.split("=", 1) for o in args.option)
    wall, cpu = time.perf_counter(), time.process_time()
    res = run(case, "mpm", progress=True, **{k: parse_value(v) for k, v in options.items()})
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    g = res.diagnostics["gauges"]
    out = {"strain": compression_strain(case, g["time"]), "stress": -np.asarray(g["axial_stress"]),
           "position": res.fields["position"] + res.fields["displacement"],
           "material": res.fields["material"], "rigid": np.array(case.discretization["mpm"]["rigid_bodies"]),
           "names": np.array([b.name for b in case.bodies]),
           "F": res.fields["deformation_gradient"].reshape(-1, 3, 3)[:, :2, :2],
           "spacing": args.cell / case.discretization["mpm"]["ppc"],
           "interpenetration": res.quantities["interpenetration"],
           "area_over_box": res.quantities["material_area_over_container"],
           "wall_s": wall, "cpu_s": cpu, "particles": res.fields["material"].size}
    store.mkdir(parents=True, exist_ok=True)
    np.savez(path, **out)
    return out


def draw_domains(ax, r: dict, ell: np.ndarray) -> None:
    """The final particles as 004 Fig 6 draws them: each particle's deformed domain
    x + F [-l, l]^2 (CPDI; l the half spacing), filled with its ellipse's colour, the
    walls and piston grey, and the particles inside another ellipse's particle domain
    (``interpenetration``) black, drawn last."""
    h = 0.5 * float(r["spacing"])
    corners = np.array([[-h, -h], [h, -h], [h, h], [-h, h]])
    polys = r["position"][:, None, :] + np.einsum("pij,cj->pci", r["F"], corners)
    colours = np.where(ell[:, None], plt.get_cmap("tab20")(r["material"] % 20), (0.6, 0.6, 0.6, 1.0))
    inside = np.zeros(ell.size, bool)
    inside[ell] = inside_other_material(r["position"][ell], r["material"][ell], r["F"][ell],
                                        np.full(2, h))
    colours[inside] = (0.0, 0.0, 0.0, 1.0)
    order = np.argsort(inside, kind="stable")
    ax.add_collection(PolyCollection(polys[order], facecolors=colours[order], edgecolors="none"))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cell", type=float, default=0.05, help="MPM cell (mm); 004: 0.0143")
    ap.add_argument("--strain", type=float, default=0.75)
    ap.add_argument("--contacts", default="LR,DF",
                    help="contact methods, comma separated; LR/explicit: LR with 3+ material nodes explicit")
    ap.add_argument("--three-material", dest="three_material", default="lump",
                    help="3+ material node treatment of the runs that name none")
    ap.add_argument("--option", action="append", default=[], help="mpm option key=value")
    ap.add_argument("--seed", type=int, default=None, help="packing seed (default: the case's, 2004)")
    ap.add_argument("--store", default="out/ellipse_fig6", help="folder of the per-run .npz files")
    args = ap.parse_args()
    store = Path(args.store)
    contacts = args.contacts.split(",")
    runs, failed = {}, {}
    for c in contacts:
        try:
            runs[c] = solve(c, args, store)
        except SolverError as e:          # one failed run does not lose the others
            failed[c] = str(e).split(":")[1].strip().replace(",", ";")
            print(f"{c}: {e}", flush=True)
    contacts = list(runs)
    if not runs:
        raise SystemExit("no run finished: " + "; ".join(failed.values()))
    # the compacted boxes (1 x 0.5 mm) one above the other beside the stress histories
    fig, axes = plt.subplot_mosaic([["stress", c] for c in contacts], figsize=(11.5, 1.2 + 3.0 * len(contacts)),
                                   width_ratios=[1.2, 1])
    rows = ["contact,three_material,cell_mm,options,final_strain,final_stress_GPa,interpenetration,"
            "cut_off,particles,area_over_box,wall_s,cpu_s"]
    for c, r in runs.items():
        axes["stress"].plot(100 * r["strain"], r["stress"] / 1e3, label=f"{c}")
        ell = np.char.startswith(r["names"][r["material"]], "ellipse")
        cut_off = int(cut_off_from_own_material(r["position"][ell], r["material"][ell]).sum())
        rows.append(f"{','.join(split_run(c, args.three_material))},{args.cell:g},{' '.join(args.option)},{r['strain'][-1]:.4f},"
                    f"{r['stress'][-1] / 1e3:.2f},{int(r['interpenetration'])},{cut_off},{int(r['particles'])},"
                    f"{float(r['area_over_box']):.3f},"
                    f"{float(r['wall_s']):.0f},{float(r['cpu_s']):.0f}")
        print(rows[-1], flush=True)
        ax = axes[c]
        draw_domains(ax, r, ell)
        ax.set_aspect("equal")
        top = r["position"][ell, 1].max() + 3.0 * args.cell     # the compacted box, not the walls above
        ax.set_xlim(r["position"][:, 0].min() - args.cell, r["position"][:, 0].max() + args.cell)
        ax.set_ylim(r["position"][:, 1].min() - args.cell, top)
        ax.set_title(f"{c}: {int(r['interpenetration'])} particles inside another ellipse (black), "
                     f"{cut_off} cut off; ellipse area / box {float(r['area_over_box']):.2f}", fontsize=8)
        ax.set_xticks([])
        ax.set_yticks([])
    rows += [f"{','.join(split_run(c, args.three_material))},{args.cell:g},{' '.join(args.option)},failed: {why},,,,,,,"
             for c, why in failed.items()]
    ax = axes["stress"]
    ax.set_xlabel("compression strain (%)")
    ax.set_ylabel("mean axial stress of the ellipses (GPa)")
    ax.legend()
    opts = ", ".join(args.option) or "uGIMP, FLIP"
    fig.suptitle(f"004 Fig 6: 20 ellipses compacted {100 * args.strain:g} % at 100 m/s "
                 f"({args.cell:g} mm cells, {opts}; 3+ nodes {args.three_material} unless named)")
    fig.tight_layout(rect=(0, 0, 1, 0.96))
    fig.savefig(HERE / "ellipse_compaction_fig6.png", dpi=110)
    (HERE / "ellipse_compaction_fig6.csv").write_text("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
