"""MPM throughput in particle-steps per second.

Two runs, each at NUMBA_NUM_THREADS = 1 and 2 (every setting in its own subprocess,
since numba fixes the thread count at import):

* ``single_ugimp``: one-material block of ~100k particles (uGIMP, 2x2 per cell),
  bottom fixed, sheared top traction: the whole step loop runs compiled
  (:func:`mpm.kernels.run_chunk_2d`).
* ``dls_interface``: the 002 double-lap-shear specimen (Dt = 5 MPa/mm, 0.1 mm cells)
  with the imperfect interface active (multimaterial P2G, two contact corrections and
  interface forces per step).

Compilation is excluded (a warm-up chunk runs first). Targets (one core): >= 1e7
particle-steps/s single material, >= 5e6 with the interface.

Usage: ``python benchmarks/bench_mpm.py [--steps 200] [--out benchmarks/bench_mpm.json]``
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

TARGETS = {"single_ugimp": 1e7, "dls_interface": 5e6}


def _block_case():
    from interfaces import Body, BoundaryCondition, Case, IsotropicElastic, Rectangle
    mat = IsotropicElastic(E=1000.0, nu=0.3, rho=1e-9)
    return Case(name="block", analysis="plane_strain", thickness=1.0, materials={"m": mat},
                bodies=[Body("b", Rectangle(0, 0, 160, 160), "m")],
                boundary_conditions=[
                    BoundaryCondition("fixed", "b", "ymin", ("x", "y"), (0.0, 0.0)),
                    BoundaryCondition("traction", "b", "ymax", ("x", "y"), (1.0, -5.0))])


def measure(name: str, steps: int) -> dict:
    """Time ``steps`` steps of run ``name`` in this process (after a warm-up)."""
    from mpm.options import merge
    from mpm.solver import Model, _Runner
    if name == "single_ugimp":
        case = _block_case()
        opts = merge(case, {"cell": 1.0, "shape": "ugimp", "progress": False})
    else:
        from cases.library import dls
        case = dls(Dt=5.0, mpm_cell=0.1)
        opts = merge(case, {"progress": False})
    model = Model(case, opts)
    run = _Runner(model)
    run._advance(3)  # compile / load the cached kernels
    t0 = time.perf_counter()
    run._advance(steps)
    elapsed = time.perf_counter() - t0
    P = model.particles.P
    return {"particles": P, "nodes": model.grid.N, "steps": steps, "seconds": elapsed,
            "particle_steps_per_s": P * steps / elapsed, "dt": model.dt}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--out", default=str(Path(__file__).with_name("bench_mpm.json")))
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        print(json.dumps(measure(args.worker, args.steps)))
        return
    root = Path(__file__).resolve().parents[1]
    results = []
    for name in ("single_ugimp", "dls_interface"):
        for threads in (1, 2):
            env = dict(os.environ, NUMBA_NUM_THREADS=str(threads),
                       PYTHONPATH=str(root) + os.pathsep + os.environ.get("PYTHONPATH", ""))
            out = subprocess.run([sys.executable, __file__, "--worker", name, "--steps",
                                  str(args.steps)], env=env, capture_output=True, text=True,
                                 check=True)
            rec = json.loads(out.stdout.strip().splitlines()[-1])
            rec.update({"run": name, "threads": threads, "target": TARGETS[name],
                        "meets_target": rec["particle_steps_per_s"] >= TARGETS[name]})
            results.append(rec)
            print(f"{name:14s} threads={threads} particles={rec['particles']:7d} "
                  f"{rec['particle_steps_per_s']:.3e} particle-steps/s "
                  f"(target {TARGETS[name]:.0e}: {'met' if rec['meets_target'] else 'NOT met'})")
    Path(args.out).write_text(json.dumps({"benchmark": "mpm", "results": results}, indent=2))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
