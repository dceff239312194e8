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
import os

from mpm_windows import interleaved_rates, loaded_block, write_json

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

SHAPES = ("ugimp", "cpdi", "b2cpdi")


def main() -> None:
    from interfaces import IsotropicElastic
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=120)
    ap.add_argument("--windows", type=int, default=6)
    ap.add_argument("--side", type=float, default=160.0)
    args = ap.parse_args()
    case = loaded_block(IsotropicElastic(E=1000.0, nu=0.3, rho=1e-9), args.side)
    out = interleaved_rates({shape: (case, {"shape": shape, "update": "usl"}) for shape in SHAPES},
                            args.steps, args.windows)
    for shape in SHAPES[1:]:
        out[f"ratio_{shape}_to_ugimp"] = (out[shape]["particle_steps_per_s"]
                                          / out["ugimp"]["particle_steps_per_s"])
    write_json(__file__, out)


if __name__ == "__main__":
    main()
