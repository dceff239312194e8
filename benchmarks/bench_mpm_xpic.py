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
import os

from mpm_windows import interleaved_rates, loaded_block, write_json

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

#: run name -> (split block, mpm options)
RUNS = {
    "flip": (False, {}),
    "xpic1": (False, {"xpic": 1}),
    "xpic5": (False, {"xpic": 5}),
    "split_flip": (True, {}),
    "split_xpic5": (True, {"xpic": 5}),
}


def main() -> None:
    from interfaces import IsotropicElastic
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=120)
    ap.add_argument("--windows", type=int, default=6)
    ap.add_argument("--side", type=float, default=160.0)
    args = ap.parse_args()
    mat = IsotropicElastic(E=1000.0, nu=0.3, rho=1e-9)
    out = interleaved_rates({name: (loaded_block(mat, args.side, split),
                                    dict({"shape": "ugimp", "update": "usl"}, **opts))
                             for name, (split, opts) in RUNS.items()}, args.steps, args.windows)
    flip = out["flip"]["particle_steps_per_s"]
    split_flip = out["split_flip"]["particle_steps_per_s"]
    out["cost_xpic1_over_flip"] = flip / out["xpic1"]["particle_steps_per_s"]
    out["cost_xpic5_over_flip"] = flip / out["xpic5"]["particle_steps_per_s"]
    out["cost_split_xpic5_over_split_flip"] = split_flip / out["split_xpic5"]["particle_steps_per_s"]
    write_json(__file__, out)


if __name__ == "__main__":
    main()
