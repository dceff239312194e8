"""MPM throughput of the Mie-Grueneisen shock run (004 Eq 51-52, case ``shock_bar``)
against the same impact with the neo-Hookean material of 004 Eq 18 (same K, G), in
particle-steps per second.

The Mie-Grueneisen run adds the pressure and energy update per particle; both recompute
dt between chunks of ``mpm.solver.STATE_DT_CHUNK`` steps (a compiled pass over the
particles each time, ``mpm.signal_speed``). The bar of 004 Fig 7 made ``--height`` mm high (default 10: 32k
particles at 0.25 mm cells), one thread, whole runs timed alternately ``--windows``
times (the machine's speed drifts: the ratio of the medians is the figure). Writes
``bench_mpm_shock.json`` next to this script.

Usage: ``python benchmarks/bench_mpm_shock.py [--height 10] [--windows 3]``
"""
from __future__ import annotations

import argparse
import os

from mpm_windows import summary, write_json

os.environ.setdefault("NUMBA_NUM_THREADS", "1")


def _case(material: str, height: float):
    import cases
    from interfaces import NeoHookean
    case = cases.build("shock_bar", height=height)
    if material == "neo_hookean":
        mg = case.materials["nickel"]
        case.materials["nickel"] = NeoHookean(K=mg.K, G=mg.G, rho=mg.rho)
    return case


def main() -> None:
    import mpm
    ap = argparse.ArgumentParser()
    ap.add_argument("--height", type=float, default=10.0)
    ap.add_argument("--windows", type=int, default=3)
    args = ap.parse_args()
    names = ("neo_hookean", "mie_gruneisen")
    rates: dict[str, list[float]] = {n: [] for n in names}
    info = {}
    for name in names:                      # compile / load the cached kernels
        mpm.solve(_case(name, 1.0), progress=False, max_time=1e-8)
    for _ in range(args.windows):
        for name in names:
            res = mpm.solve(_case(name, args.height), progress=False)
            rates[name].append(res.timings["particle_steps_per_s"])
            info[name] = (res.diagnostics["particles"], res.diagnostics["time_steps"])
    out = summary({n: info[n][0] for n in names}, {n: info[n][1] for n in names}, rates)
    out["ratio_mie_gruneisen_to_neo_hookean"] = (out["mie_gruneisen"]["particle_steps_per_s"]
                                                 / out["neo_hookean"]["particle_steps_per_s"])
    write_json(__file__, out)


if __name__ == "__main__":
    main()
