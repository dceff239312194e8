"""MPM throughput of the XPIC(m) particle updates (004 Sec 3.3, mpm/xpic.py) against the
uGIMP FLIP run of the same problem, in particle-steps per second.

The block of ``bench_mpm.py`` (``single_ugimp``: uGIMP, 2x2 particles per cell, plane
strain, bottom fixed, sheared top traction; ``--side`` mm of 1 mm cells) with FLIP,
XPIC(1) and XPIC(5), and the same block split at mid-height into two bodies bonded by a
perfect interface with FLIP and multimaterial XPIC(5). One thread; the runs are timed
alternately in ``--windows`` windows each (the machine's speed drifts: the ratio of the
medians is the figure, by the wall clock and by CPU time; 004 asks XPIC(5) < 2x FLIP
cost). With ``--old PATH`` (a checkout of the previous commit, e.g. ``git worktree add
--detach /tmp/mpm_old main``) that tree's runs are timed in windows interleaved with
these, and the cost ratios of both trees and the new / old speeds are reported. Writes
``bench_mpm_xpic.json`` next to this script.

Usage: ``python benchmarks/bench_mpm_xpic.py [--steps 120] [--windows 6] [--side 160]
[--old PATH]``
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
#: cost ratio -> (run, its FLIP run)
COSTS = {
    "xpic1_over_flip": ("xpic1", "flip"),
    "xpic5_over_flip": ("xpic5", "flip"),
    "split_xpic5_over_split_flip": ("split_xpic5", "split_flip"),
}


def variants(side: float) -> dict:
    """name -> (case, mpm options) of :data:`RUNS` on the ``side`` mm block."""
    from interfaces import IsotropicElastic
    mat = IsotropicElastic(E=1000.0, nu=0.3, rho=1e-9)
    base = {"shape": "ugimp", "update": "usl"}
    return {name: (loaded_block(mat, side, split), dict(base, **opts))
            for name, (split, opts) in RUNS.items()}


def costs(runs: dict) -> dict:
    """The cost ratios of :data:`COSTS` (FLIP speed / variant speed), wall clock and CPU."""
    out = {}
    for key, (name, flip) in COSTS.items():
        out[f"cost_{key}"] = runs[flip]["particle_steps_per_s"] / runs[name]["particle_steps_per_s"]
        if "particle_steps_per_cpu_s" in runs[name]:
            out[f"cpu_cost_{key}"] = (runs[flip]["particle_steps_per_cpu_s"]
                                      / runs[name]["particle_steps_per_cpu_s"])
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=120)
    ap.add_argument("--windows", type=int, default=6)
    ap.add_argument("--side", type=float, default=160.0)
    ap.add_argument("--old", default=None, help="checkout of the previous commit, timed alongside")
    args = ap.parse_args()
    out = interleaved_rates(variants(args.side), args.steps, args.windows, args.old,
                            ("bench_mpm_xpic", "variants", {"side": args.side}))
    if args.old is None:
        out.update(costs(out))
    else:
        out["new"].update(costs(out["new"]))
        out["old"].update(costs(out["old"]))
    write_json(__file__, out)


if __name__ == "__main__":
    main()
