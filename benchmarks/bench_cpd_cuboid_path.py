"""CPD 3D: whole solves of the 003 Sec 4.5 cuboid at the paper's spacing, load control or arc length.

One solve per invocation (the machine is shared; each run is its own process so that its peak
RSS is its own): size, interface, load case, ``path`` and ``load_steps`` as given; prints the
Newton progress on stderr and appends one JSON line to ``--out`` with the per-step (per-arc)
load factors and normalised residuals, the wall and CPU time, the peak RSS, the strain energy,
the linear-solver counts and the negative pivots of the last factorisation of each step.

    NUMBA_NUM_THREADS=1 MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/bench_cpd_cuboid_path.py \\
        --size 0.8x0.6x0.6 --path arc_length --load-steps 4 --out benchmarks/bench_cpd_cuboid_path.json
"""
from __future__ import annotations

import argparse
import json
import resource
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def run(size: tuple, interface: str, load_case: int, path: str, load_steps: int,
        nu_A: float = 0.1) -> dict:
    import peridynamics
    from cases import library
    from interfaces.errors import SolverError

    case = library.cuboid(interface=interface, load_case=load_case, size=size, nu_A=nu_A)
    t0, c0 = time.perf_counter(), time.process_time()
    row = {"size": list(size), "interface": interface, "load_case": load_case, "path": path,
           "load_steps": load_steps, "nu_A": nu_A}
    try:
        res = peridynamics.solve(case, h=0.035, path=path, load_steps=load_steps, progress=True)
    except SolverError as e:
        row.update(converged=False, error=str(e))
    else:
        d = res.diagnostics
        row.update(converged=True, points=d["n_points"], free_dofs=d["n_free_dofs"],
                   strain_energy=res.quantities["strain_energy"], iterations=d["iterations"],
                   steps=[{k: h.get(k) for k in ("load", "residuals", "arc_length", "t_lam", "negative_pivots",
                                                 "path")} for h in d["newton_history"]],
                   linear_solver={k: v for k, v in d["linear_solver"].items() if k != "failed_attempts"},
                   failed_attempts=d["linear_solver"]["failed_attempts"], timings=res.timings)
    row.update(wall_s=time.perf_counter() - t0, cpu_s=time.process_time() - c0,
               peak_rss_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
    return row


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--size", default="0.5x0.4x0.4")
    ap.add_argument("--interface", default="horizontal", choices=("horizontal", "vertical"))
    ap.add_argument("--load-case", type=int, default=2)
    ap.add_argument("--path", default="arc_length")
    ap.add_argument("--load-steps", type=int, default=4)
    ap.add_argument("--nu-a", dest="nu_A", type=float, default=0.1,
                    help="material A's Poisson ratio (003: 0.1, C3^A < 0; 0.25: C3^A = 0)")
    ap.add_argument("--out")
    a = ap.parse_args()
    size = tuple(float(v) for v in a.size.split("x"))
    row = run(size, a.interface, a.load_case, a.path, a.load_steps, a.nu_A)
    line = json.dumps(row, default=str)
    print(line, flush=True)
    if a.out:
        with open(a.out, "a") as fh:
            fh.write(line + "\n")


if __name__ == "__main__":
    main()
