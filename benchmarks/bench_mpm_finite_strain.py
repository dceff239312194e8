"""MPM throughput of the finite-strain (neo-Hookean, 004 Eq 18) stress update against the
small-strain linear update of the same block, in particle-steps per second.

The block of ``bench_mpm.py`` (``single_ugimp``: ~100k particles, uGIMP, 2x2 per cell,
plane strain, bottom fixed, sheared top traction) with ``IsotropicElastic`` of K, G and
with ``NeoHookean(K, G)``, one thread, timed alternately in ``--windows`` windows each
(the machine's speed drifts: the ratio of the medians is the figure). Writes
``bench_mpm_finite_strain.json`` next to this script.

Usage: ``python benchmarks/bench_mpm_finite_strain.py [--steps 200] [--windows 6]``
"""
from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")


def _case(material: str, side: float = 160.0):
    from interfaces import (Body, BoundaryCondition, Case, NeoHookean, Rectangle,
                            isotropic_from_KG)
    K, G = 2450.0, 940.0
    mat = NeoHookean(K=K, G=G, rho=1e-9) if material == "neo_hookean" else \
        isotropic_from_KG(K, G, 1e-9)
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
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--windows", type=int, default=6)
    args = ap.parse_args()
    runs = {}
    for name in ("linear", "neo_hookean"):
        case = _case(name)
        model = Model(case, merge(case, {"cell": 1.0, "shape": "ugimp", "progress": False}))
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
    out["ratio_neo_hookean_to_linear"] = (out["neo_hookean"]["particle_steps_per_s"]
                                          / out["linear"]["particle_steps_per_s"])
    text = json.dumps(out, indent=2)
    print(text)
    (Path(__file__).with_suffix(".json")).write_text(text + "\n")


if __name__ == "__main__":
    main()
