"""FEM assembly + solve time of this tree against another checkout, side by side.

Runs ``benchmarks/bench_fem.py`` (the 002 Sec 3.1 DLS with 6-node interface elements)
of both trees in fresh processes, alternating old/new ``--repeat`` times at each element
size, and prints the fastest time of each and the ratio new/old (the machine's speed
drifts by up to 2x within minutes: only same-run ratios mean anything).

    PYTHONPATH=. python benchmarks/bench_fem_compare.py --old /tmp/main_checkout [--h 0.06,0.042,0.0305]
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
STAGES = ("time_mesh_s", "time_assembly_s", "time_constraints_s", "time_solve_s")


def _run(tree: Path, h: float) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "b.json"
        subprocess.run([sys.executable, str(tree / "benchmarks" / "bench_fem.py"), "--h", str(h), "--out", str(out)],
                       cwd=tree, env={**__import__("os").environ, "PYTHONPATH": str(tree)}, check=True,
                       capture_output=True, text=True)
        return json.loads(out.read_text())


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old", required=True, help="the other checkout (e.g. main in a temporary worktree)")
    ap.add_argument("--h", default="0.06,0.042,0.0305", help="element sizes (mm): ~130k, 266k, 500k DOFs")
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--out", default=str(Path(__file__).with_name("bench_fem_compare.json")))
    args = ap.parse_args(argv)
    rows = []
    for h in (float(v) for v in args.h.split(",")):
        best = {}
        for _ in range(args.repeat):
            for label, tree in (("old", Path(args.old).resolve()), ("new", HERE)):
                r = _run(tree, h)
                if label not in best or r["time_assembly_plus_solve_s"] < best[label]["time_assembly_plus_solve_s"]:
                    best[label] = r
        o, n = best["old"], best["new"]
        row = {"h": h, "dofs": n["dofs"], "old_s": o["time_assembly_plus_solve_s"],
               "new_s": n["time_assembly_plus_solve_s"],
               "ratio": n["time_assembly_plus_solve_s"] / o["time_assembly_plus_solve_s"],
               "old_stages_s": {k: o[k] for k in STAGES}, "new_stages_s": {k: n[k] for k in STAGES},
               "stiffness_old": o["stiffness"], "stiffness_new": n["stiffness"]}
        rows.append(row)
        print(f"h = {h:g} mm, {n['dofs']:,} DOFs: old {row['old_s']:.2f} s, new {row['new_s']:.2f} s, "
              f"ratio new/old {row['ratio']:.2f}  (stages new/old: "
              + ", ".join(f"{k[5:-2]} {n[k]:.2f}/{o[k]:.2f}" for k in STAGES) + ")")
        assert abs(n["stiffness"] / o["stiffness"] - 1.0) < 1e-9, "the two trees disagree on the stiffness"
    Path(args.out).write_text(json.dumps(rows, indent=1))
    return {"rows": rows}


if __name__ == "__main__":
    main()
