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
import os

from mpm_windows import interleaved_rates, loaded_block, write_json

os.environ.setdefault("NUMBA_NUM_THREADS", "1")


def _material(name: str):
    from interfaces import NeoHookean, isotropic_from_KG
    K, G = 2450.0, 940.0
    return NeoHookean(K=K, G=G, rho=1e-9) if name == "neo_hookean" else isotropic_from_KG(K, G, 1e-9)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--windows", type=int, default=6)
    args = ap.parse_args()
    out = interleaved_rates({name: (loaded_block(_material(name)), {"shape": "ugimp"})
                             for name in ("linear", "neo_hookean")}, args.steps, args.windows)
    out["ratio_neo_hookean_to_linear"] = (out["neo_hookean"]["particle_steps_per_s"]
                                          / out["linear"]["particle_steps_per_s"])
    write_json(__file__, out)


if __name__ == "__main__":
    main()
