"""Mesh convergence of the FEM on a curved imperfect interface (002 Sec 2, Eq 26-29).

A circular (radius 1 mm) and an elliptical (semi-axes 1 and 0.5 mm) glass inclusion with
Dn = Dt = 100 MPa/mm in a 4 mm polymer plate under 10 MPa tension (case ``inclusion``),
meshed by gmsh at h = 1/2 ... 1/16 mm with curved 6-node triangles (mid-edge nodes on the
curve, curved 6-node interface elements) and with straight-sided ones on the same
vertices (equal DOFs). Error: total energy (bulk + interface, = half the external work)
against a curved mesh at h = 1/40 mm; observed order p in error ~ DOFs^(-p/2) ~ h^p.

    PYTHONPATH=. python docs/fem_curved/inclusion_convergence.py [--out docs/fem_curved]
"""
from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import cases  # noqa: E402
import fem  # noqa: E402

SIZES = (2, 4, 8, 16)           # h = 1/k mm
REFERENCE = 40


def study(shape: str, sizes=SIZES, reference: int = REFERENCE) -> dict:
    """Errors and observed orders of curved and straight-sided meshes for one inclusion shape."""
    case = cases.build("inclusion", shape=shape, width=4.0, D=100.0)
    U_ref = fem.solve(case, h=1.0 / reference, fields=False).quantities["total_energy"]
    out = {"shape": shape, "reference_h": 1.0 / reference, "reference_total_energy": U_ref}
    for curved in (True, False):
        rows = []
        for k in sizes:
            r = fem.solve(case, h=1.0 / k, fields=False, curved=curved)
            rows.append({"h": 1.0 / k, "dofs": r.diagnostics["dofs"],
                         "error": abs(r.quantities["total_energy"] / U_ref - 1.0)})
        for prev, row in zip(rows, rows[1:]):
            row["order"] = math.log(prev["error"] / row["error"]) / math.log(math.sqrt(row["dofs"] / prev["dofs"]))
        out["curved" if curved else "straight"] = rows
    return out


def plot(results: list[dict], path: Path) -> None:
    fig, ax = plt.subplots(figsize=(6.0, 4.5))
    for res, color in zip(results, ("tab:blue", "tab:red")):
        for kind, style in (("curved", "o-"), ("straight", "s--")):
            rows = res[kind]
            p = rows[-1]["order"]
            ax.loglog([r["dofs"] for r in rows], [r["error"] for r in rows], style, color=color,
                      label=f"{res['shape']}, {kind} (order {p:.1f})")
    ax.set_xlabel("DOFs")
    ax.set_ylabel("relative error of the total energy")
    ax.set_title("Inclusion, Dn = Dt = 100 MPa/mm: curved vs straight 6-node elements", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None) -> list[dict]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(Path(__file__).parent))
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    results = [study(s) for s in ("circle", "ellipse")]
    for res in results:
        for kind in ("curved", "straight"):
            print(res["shape"], kind, ", ".join(f"{r['dofs']} DOFs: {r['error']:.2e}"
                                                + (f" (order {r['order']:.2f})" if "order" in r else "")
                                                for r in res[kind]))
    (out / "inclusion_convergence.json").write_text(json.dumps(results, indent=1))
    plot(results, out / "inclusion_convergence.png")
    return results


if __name__ == "__main__":
    main()
