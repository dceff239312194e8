"""MPM throughput of the CPDI and B2-CPDI shapes (mpm/cpdi.py) against uGIMP FLIP on the
same problem, in particle-steps per second.

The block of ``bench_mpm.py`` (``single_ugimp``: ~100k particles, 2x2 per cell, plane
strain, linear elastic, bottom fixed, sheared top traction) run with shape ``ugimp``,
``cpdi`` and ``b2cpdi`` (FLIP, USL), one thread, timed alternately in ``--windows``
windows each (the machine's speed drifts: the ratios of the medians are the figures).
Writes ``bench_mpm_cpdi.json`` next to this script.

Usage: ``python benchmarks/bench_mpm_cpdi.py [--steps 120] [--windows 6] [--side 160]``
"""
from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

SHAPES = ("ugimp", "cpdi", "b2cpdi")


def _case(side: float):
    from interfaces import Body, BoundaryCondition, Case, IsotropicElastic, Rectangle
    mat = IsotropicElastic(E=1000.0, nu=0.3, rho=1e-9)
    return Case(name="block", analysis="plane_strain", thickness=1.0, materials={"m": mat},
                bodies=[Body("b", Rectangle(0, 0, side, side), "m")],
                boundary_conditions=[
                    BoundaryCondition("fixed", "b", "ymin", ("x", "y"), (0.0, 0.0)),
                    BoundaryCondition("traction", "b", "ymax", ("x", "y"), (1.0, -5.0))])


def main() -> None:
    import numpy as np
    from mpm.options import merge
    from mpm.solver import Model, _Runner
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=120)
    ap.add_argument("--windows", type=int, default=6)
    ap.add_argument("--side", type=float, default=160.0)
    args = ap.parse_args()
    runs = {}
    for shape in SHAPES:
        case = _case(args.side)
        model = Model(case, merge(case, {"cell": 1.0, "shape": shape, "update": "usl",
                                         "progress": False}))
        run = _Runner(model)
        run._advance(3)        # compile / load the cached kernels
        runs[shape] = (model, run, [])
    per = max(1, args.steps // args.windows)
    for _ in range(args.windows):
        for shape, (model, run, rates) in runs.items():
            t0 = time.perf_counter()
            run._advance(per)
            rates.append(model.particles.P * per / (time.perf_counter() - t0))
    out = {shape: {"particles": int(m.particles.P), "steps": per * args.windows,
                   "particle_steps_per_s": float(np.median(r)),
                   "best_window_particle_steps_per_s": float(np.max(r))}
           for shape, (m, _, r) in runs.items()}
    for shape in SHAPES[1:]:
        out[f"ratio_{shape}_to_ugimp"] = (out[shape]["particle_steps_per_s"]
                                          / out["ugimp"]["particle_steps_per_s"])
    text = json.dumps(out, indent=2)
    print(text)
    (Path(__file__).with_suffix(".json")).write_text(text + "\n")


if __name__ == "__main__":
    main()
