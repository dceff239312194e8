"""Whole-run cost of LR contact (004 Sec 3.1, mpm/multimaterial_lr.py) against DF
separation on the ellipse compaction of 004 Fig 6.

The LR cost grows with the number of multimaterial nodes, which grows as the 20 ellipses
are packed, so the figure is the whole run, not a window of it: case
``ellipse_compaction`` (CPDI + XPIC(5), lumped 3+ material nodes) to ``--strain`` at
``--cell``, LR and DF, each run in its own process on one numba thread, timed by the wall
clock and by CPU time; ``--repeat`` rounds in alternating order, the medians are the
figures. 004 reports LR at about 1.55x the cost of DF. With ``--old PATH`` (a checkout
of the previous commit, e.g. ``git worktree add --detach /tmp/mpm_old main``) the same
runs of that tree interleave with these and the old / new time ratios are reported.
Each run's final mean axial stress and interpenetration count are printed beside its
time: the packing amplifies round-off (docs/mpm.md, "Ties": at 0.05 mm a 1e-12 mm
change departs DF past about 57 % compression and LR from about 16 %), so two trees
whose kernels differ only in round-off still end in different packings; compare times
over a strain both trees share (``--strain 0.15`` for LR, ``0.5`` for DF) when that
matters. Writes ``bench_mpm_lr.json`` next to this script.

Usage: ``python benchmarks/bench_mpm_lr.py [--cell 0.05] [--strain 0.75] [--repeat 2]
[--old PATH]``
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

from mpm_windows import write_json

ROOT = Path(__file__).resolve().parents[1]
CONTACTS = ("LR", "DF")


def measure(contact: str, cell: float, strain: float) -> dict:
    """One ellipse compaction run with ``contact``: wall and CPU seconds, final state."""
    import time

    import cases
    from cases.methods import run
    case = cases.build("ellipse_compaction", contact=contact, mpm_cell=cell, strain=strain)
    wall, cpu = time.perf_counter(), time.process_time()
    res = run(case, "mpm", progress=False, shape="cpdi", xpic=5)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    return {"wall_s": wall, "cpu_s": cpu, "particles": int(res.fields["material"].size),
            "final_stress_GPa": float(-res.diagnostics["gauges"]["axial_stress"][-1] / 1e3),
            "interpenetration": int(res.quantities["interpenetration"])}


def _run_in(tree: Path, contact: str, cell: float, strain: float) -> dict:
    code = (f"import json, sys; sys.path[:0] = [{str(tree)!r}, {str(ROOT / 'benchmarks')!r}]; "
            f"import bench_mpm_lr; print(json.dumps(bench_mpm_lr.measure({contact!r}, {cell!r}, {strain!r})))")
    env = dict(os.environ, PYTHONPATH=str(tree))
    env.setdefault("NUMBA_NUM_THREADS", "1")
    out = subprocess.run([sys.executable, "-c", code], env=env, cwd=str(tree), capture_output=True,
                         text=True)
    if out.returncode:
        raise RuntimeError(f"the run in {tree} stopped:\n{out.stderr[-2000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def _medians(runs: list) -> dict:
    out = {k: statistics.median(r[k] for r in runs) for k in ("wall_s", "cpu_s")}
    out["runs"] = runs
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cell", type=float, default=0.05, help="MPM cell (mm); 004: 0.0143")
    ap.add_argument("--strain", type=float, default=0.75, help="compression of the box, (0, 0.8]")
    ap.add_argument("--repeat", type=int, default=2, help="rounds of runs")
    ap.add_argument("--old", default=None, help="checkout of the previous commit, timed alongside")
    args = ap.parse_args()
    trees = {"new": ROOT} | ({"old": Path(args.old).resolve()} if args.old else {})
    runs: dict = {t: {c: [] for c in CONTACTS} for t in trees}
    for k in range(args.repeat):
        order = list(trees) if k % 2 == 0 else list(trees)[::-1]
        for contact in CONTACTS:
            for tag in order:
                r = _run_in(trees[tag], contact, args.cell, args.strain)
                print(f"{tag} {contact}: wall {r['wall_s']:.1f} s, cpu {r['cpu_s']:.1f} s, "
                      f"stress {r['final_stress_GPa']:.3f} GPa, inside {r['interpenetration']}", flush=True)
                runs[tag][contact].append(r)
    out: dict = {"cell": args.cell, "strain": args.strain}
    for tag in trees:
        med = {c: _medians(runs[tag][c]) for c in CONTACTS}
        out[tag] = med | {"LR_over_DF": {k: med["LR"][k] / med["DF"][k] for k in ("wall_s", "cpu_s")}}
    if args.old:
        out["old_over_new"] = {c: {k: out["old"][c][k] / out["new"][c][k] for k in ("wall_s", "cpu_s")}
                               for c in CONTACTS}
    write_json(__file__, out)


if __name__ == "__main__":
    main()
