"""004 Fig 6: when and where particles of one ellipse get inside another (docs/mpm.md).

Runs ``ellipse_compaction`` once per contact method with ``--frames`` VTK frames (each
particle's position, velocity and deformation gradient) and counts, frame by frame, the
particles whose centre lies in another ellipse's particle domain (``interpenetration``,
mpm/interpenetration.py). Prints per method:

* the count at 50, 60, .., 100 % of the run and the particles that were inside at some
  frame;
* over the inside events of the last 10 % of the frames: the pair's centre line against
  the local normal (between the centroids of the two ellipses' particles within 2
  cells; |cos| below 0.5: side by side along the boundary) and the share with a third
  ellipse's particle within 1.5 cells (against that share among all particles with
  another ellipse within 1.5 cells);
* at the last frame, the median velocity difference between particles of one ellipse
  within a cell of each other and between particles of two ellipses within 0.75 cell.

Writes ellipse_compaction_crossings.csv here (count against compression per method).

    PYTHONPATH=. python docs/contact/ellipse_compaction_crossings.py --cell 0.025 --contacts LR
"""
from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import meshio
import numpy as np
from scipy.spatial import cKDTree

import cases
from cases.methods import run
from ellipse_compaction_fig6 import split_run  # the Fig 6 script beside this one
from mpm.interpenetration import inside_pairs

HERE = Path(__file__).resolve().parent


def frames(label: str, cell: float, n_frames: int) -> tuple[list, np.ndarray]:
    """One run's frames [(x, v, F (P, 2, 2), material)] and the mask of its ellipse
    particles."""
    contact, three = split_run(label, "lump")
    case = cases.build("ellipse_compaction", contact=contact, mpm_cell=cell, three_material=three)
    with tempfile.TemporaryDirectory() as tmp:
        run(case, "mpm", progress=True, shape="cpdi", xpic=5, vtk_dir=tmp, vtk_frames=n_frames)
        out = []
        for path in sorted(Path(tmp).glob("*.vtu")):
            m = meshio.read(path)
            d = m.point_data
            out.append((m.points[:, :2], d["velocity"][:, :2],
                        d["deformation_gradient"].reshape(-1, 3, 3)[:, :2, :2], d["material"]))
    names = np.array([b.name for b in case.bodies])
    return out, np.char.startswith(names[out[0][3]], "ellipse")


def geometry(x, mat, pairs, cell):
    """|cos| of each pair's centre line with the local normal, and whether a third
    ellipse has a particle within 1.5 cells of the pair's midpoint."""
    tree = cKDTree(x)
    cos, third = [], []
    for p, q in pairs:
        mid = 0.5 * (x[p] + x[q])
        near = np.asarray(tree.query_ball_point(mid, 2.0 * cell))
        n = x[near[mat[near] == mat[q]]].mean(0) - x[near[mat[near] == mat[p]]].mean(0)
        e = x[q] - x[p]
        cos.append(abs(n @ e) / (np.linalg.norm(n) * np.linalg.norm(e)))
        close = np.asarray(tree.query_ball_point(mid, 1.5 * cell))
        third.append(len(set(mat[close])) >= 3)
    return np.array(cos), np.array(third)


def contact_share_near_three(x, mat, cell):
    """Among particles with another ellipse within 1.5 cells, the share with two others."""
    tree = cKDTree(x)
    kinds = np.array([len(set(mat[j])) for j in tree.query_ball_point(x, 1.5 * cell)])
    return np.sum(kinds >= 3) / max(np.sum(kinds >= 2), 1)


def ringing(x, v, mat, cell):
    """Median |v_p - v_q| over particles of one ellipse within a cell and of two
    ellipses within 0.75 cell (mm/s)."""
    tree = cKDTree(x)
    out = []
    for radius, same in ((cell, True), (0.75 * cell, False)):
        pairs = tree.query_pairs(radius, output_type="ndarray")
        pairs = pairs[(mat[pairs[:, 0]] == mat[pairs[:, 1]]) == same]
        out.append(float(np.median(np.linalg.norm(v[pairs[:, 0]] - v[pairs[:, 1]], axis=1))))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cell", type=float, default=0.025, help="MPM cell (mm)")
    ap.add_argument("--contacts", default="LR", help="comma list, e.g. LR,LR/explicit,DF")
    ap.add_argument("--frames", type=int, default=170, help="VTK frames over the run")
    args = ap.parse_args()
    half = np.full(2, 0.25 * args.cell)                       # 2 x 2 particles per cell
    rows = ["contact,frame_fraction,inside"]
    for label in args.contacts.split(","):
        series, ell = frames(label, args.cell, args.frames)
        counts, ever, late = [], set(), []
        for k, (x, v, F, mat) in enumerate(series):
            pairs = inside_pairs(x[ell], mat[ell], F[ell], half)
            counts.append(len(np.unique(pairs[:, 0])))
            ever.update(np.unique(pairs[:, 0]).tolist())
            if k >= 0.9 * len(series):
                late.append(geometry(x[ell], mat[ell], pairs, args.cell))
            rows.append(f"{label},{k / (len(series) - 1):.4f},{counts[-1]}")
        x, v, F, mat = series[-1]
        cos = np.concatenate([c for c, _ in late])
        third = np.concatenate([t for _, t in late])
        same, other = ringing(x[ell], v[ell], mat[ell], args.cell)
        tenths = [counts[round(f * (len(counts) - 1))] for f in np.linspace(0.5, 1.0, 6)]
        print(f"{label} at {args.cell:g} mm: inside at 50/60/70/80/90/100 % of the run "
              f"{'/'.join(map(str, tenths))}; inside at some frame {len(ever)}; "
              f"last 10 %: {cos.size} events, |cos| median {np.median(cos):.2f}, "
              f"{np.mean(cos < 0.5):.0%} side by side, {np.mean(third):.0%} near a third ellipse "
              f"(contact particles: {contact_share_near_three(x[ell], mat[ell], args.cell):.0%}); "
              f"velocity differences {same / 1e3:.0f} m/s within an ellipse, {other / 1e3:.0f} m/s "
              f"across contacts", flush=True)
    (HERE / "ellipse_compaction_crossings.csv").write_text("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
