"""MPM throughput of the XPIC(m) particle updates (004 Sec 3.3, mpm/xpic.py) against the
uGIMP FLIP run of the same problem, in particle-steps per second.

The block of ``bench_mpm.py`` (``single_ugimp``: uGIMP, 2x2 particles per cell, plane
strain, bottom fixed, sheared top traction; ``--side`` mm of 1 mm cells) with FLIP,
XPIC(1) and XPIC(5), and the same block split at mid-height into two bodies bonded by a
perfect interface with FLIP and multimaterial XPIC(5). One thread; the runs are timed
alternately in ``--windows`` windows each (the machine's speed drifts: the ratio of the
medians is the figure; 004 asks XPIC(5) < 2x FLIP cost). Writes ``bench_mpm_xpic.json``
next to this script.

Usage: ``python benchmarks/bench_mpm_xpic.py [--steps 120] [--windows 6] [--side 160]``
"""
from __future__ import annotations

import argparse
import json
import math
import os
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

#: run name -> (split block, mpm options)
RUNS = {
    "flip": (False, {}),
    "xpic1": (False, {"xpic": 1}),
    "xpic5": (False, {"xpic": 5}),
    "split_flip": (True, {}),
    "split_xpic5": (True, {"xpic": 5}),
}


def _case(split: bool, side: float):
    from interfaces import (Body, BoundaryCondition, Case, InterfacePair, IsotropicElastic,
                            LinearInterface, Rectangle)
    mat = IsotropicElastic(E=1000.0, nu=0.3, rho=1e-9)
    if split:
        bodies = [Body("low", Rectangle(0, 0, side, side / 2), "m"),
                  Body("up", Rectangle(0, side / 2, side, side / 2), "m")]
        pairs = [InterfacePair("low", "up", LinearInterface(Dn=math.inf, Dt=math.inf))]
    else:
        bodies, pairs = [Body("b", Rectangle(0, 0, side, side), "m")], []
    return Case(name="block", analysis="plane_strain", thickness=1.0, materials={"m": mat},
                bodies=bodies, interfaces=pairs, boundary_conditions=[
                    BoundaryCondition("fixed", bodies[0].name, "ymin", ("x", "y"), (0.0, 0.0)),
                    BoundaryCondition("traction", bodies[-1].name, "ymax", ("x", "y"),
                                      (1.0, -5.0))])


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
    for name, (split, opts) in RUNS.items():
        case = _case(split, args.side)
        model = Model(case, merge(case, dict({"cell": 1.0, "shape": "ugimp", "update": "usl",
                                              "progress": False}, **opts)))
        run = _Runner(model)
        run._advance(3)        # compile / load the cached kernels
        runs[name] = (model, run, [])
    per = max(1, args.steps // args.windows)
    for _ in range(args.windows):
        for name, (model, run, rates) in runs.items():
            t0 = time.perf_counter()
            run._advance(per)
            rates.append(model.particles.P * per / (time.perf_counter() - t0))
    out = {name: {"particles": int(m.particles.P), "steps": per * args.windows,
                  "particle_steps_per_s": float(np.median(r)),
                  "best_window_particle_steps_per_s": float(np.max(r))}
           for name, (m, _, r) in runs.items()}
    flip = out["flip"]["particle_steps_per_s"]
    split_flip = out["split_flip"]["particle_steps_per_s"]
    out["cost_xpic1_over_flip"] = flip / out["xpic1"]["particle_steps_per_s"]
    out["cost_xpic5_over_flip"] = flip / out["xpic5"]["particle_steps_per_s"]
    out["cost_split_xpic5_over_split_flip"] = split_flip / out["split_xpic5"]["particle_steps_per_s"]
    text = json.dumps(out, indent=2)
    print(text)
    (Path(__file__).with_suffix(".json")).write_text(text + "\n")


if __name__ == "__main__":
    main()
