"""Transient FEM throughput on the 002 Sec 3.3 wave strip (fem/transient.py).

Runs the ``wave`` case (Dn = 3e4 MPa/mm, uniaxial strain) with Newmark average
acceleration (consistent mass, one factorisation) and with central differences
(lumped mass, stable limit by ARPACK), and prints DOFs, steps, setup and time-loop
seconds, DOF-steps per second and the transmitted energy against the exact pulse
solution. The machine's speed drifts: compare runs made one after the other.

    PYTHONPATH=. python benchmarks/bench_fem_transient.py [--h 0.25] [--height 4] [--repeat 1] [--out benchmarks/bench_fem_transient.json]
"""
from __future__ import annotations

import argparse
import json
import platform
import time
from pathlib import Path

import fem
from cases.registry import build
from interfaces.analytic import solve as analytic_solve


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--h", type=float, default=0.25, help="element size along the strip (mm)")
    ap.add_argument("--height", type=float, default=4.0, help="strip height (mm), elements of size h across")
    ap.add_argument("--repeat", type=int, default=1, help="runs per scheme; the fastest is reported")
    ap.add_argument("--out", default=str(Path(__file__).with_suffix(".json")))
    a = ap.parse_args(argv)
    case = build("wave", Dn=3.0e4, height=a.height)
    exact = analytic_solve(case).quantities["transmitted_energy"]
    report = {"platform": platform.platform(), "h": a.h, "height": a.height, "runs": {}}
    for scheme in ("newmark", "central"):
        best = None
        for _ in range(a.repeat):
            t0 = time.perf_counter()
            r = fem.solve(case, dynamics=scheme, element_size=[a.h, a.h])
            wall = time.perf_counter() - t0
            if best is None or wall < best[0]:
                best = (wall, r)
        wall, r = best
        d, tm = r.diagnostics, r.timings
        loop = tm.get("solve", float("nan"))
        row = {"dofs": d["dofs"], "steps": d["time_steps"], "dt": d["dt"], "wall_s": wall,
               "loop_s": loop, "setup_s": wall - loop,
               "dof_steps_per_s": d["dofs"] * d["time_steps"] / loop,
               "transmitted_energy": r.quantities["transmitted_energy"], "exact": exact}
        report["runs"][scheme] = row
        print(f"{scheme:8s} dofs={row['dofs']:6d} steps={row['steps']:5d} setup {row['setup_s']:.2f} s "
              f"loop {loop:.2f} s  {row['dof_steps_per_s']:.3g} DOF-steps/s  "
              f"T = {row['transmitted_energy']:.4f} (exact {exact:.4f})")
    Path(a.out).write_text(json.dumps(report, indent=1))
    print(f"wrote {a.out}")
    return report


if __name__ == "__main__":
    main()
