"""CPD 3D benchmark: the 003 Sec 4.5 cuboid at the paper's spacing (Delta = 0.035, delta = 3.01 Delta).

Per size: set-up (neighbours, pattern, block slots; reduced-matrix map) with its peak RSS,
one residual-only and one residual + tangent evaluation (best of ``--repeat``; one and
three-neighbour interactions, C3 < 0 in material A), quadruples evaluated, seconds per
quadruple. With ``--old PATH`` (a checkout of the commit to compare with, e.g.
``git archive main | tar -x -C /tmp/cpd_old``) the same measurement runs on that tree in a
subprocess in the same run; the ratios old / new and the largest differences of energy,
residual and tangent between the trees are reported (same state u = prescribed H X).
With ``--solve`` a whole Newton solve follows on the new tree (residual history, time per
iteration, peak RSS).

    NUMBA_NUM_THREADS=1 MKL_NUM_THREADS=1 python benchmarks/bench_cpd_cuboid.py \\
        --sizes 0.3x0.2x0.2 0.4x0.3x0.3 [--old /tmp/cpd_old] [--solve] [--out file.json]
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _rss_mb() -> dict:
    out = {}
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith(("VmRSS", "VmHWM")):
                out[line.split(":")[0]] = int(line.split()[1]) / 1024
    return out


def _reset_peak():
    try:
        with open("/proc/self/clear_refs", "w") as fh:   # resets VmHWM (Linux)
            fh.write("5")
    except OSError:
        pass


def measure(size: tuple, repeat: int, dump: str | None) -> dict:
    import numpy as np

    from cases import library
    from peridynamics.discretization import discretize
    from peridynamics.interface import split_band
    from peridynamics.newton import ReducedMatrix
    from peridynamics.solver import boundary_vectors, build_system

    h = 0.035
    delta = 3.01 * h
    case = library.cuboid(interface="horizontal", load_case=2, size=size)
    # compile the kernels on the smallest cuboid first: compilation is not measured
    for sz, keep in (((0.3, 0.2, 0.2), False), (size, True)):
        c = library.cuboid(interface="horizontal", load_case=2, size=sz)
        disc = discretize(c, h, delta, delta)
        disc, springs, ties = split_band(c, disc)
        _reset_peak()
        t0 = time.perf_counter()
        system, _ = build_system(c, disc, "continuum", None, springs, ties)
        t_build, rss_build = time.perf_counter() - t0, _rss_mb()
        fixed, u_bar, _ = boundary_vectors(disc)
        free = np.setdiff1d(np.arange(disc.X.size), fixed)
        _reset_peak()
        t0 = time.perf_counter()
        red = ReducedMatrix(system, free)
        t_red, rss_red = time.perf_counter() - t0, _rss_mb()
        u = u_bar.reshape(disc.X.shape)
        system.evaluate(u, keep)
    row = {"size": list(size), "points": int(len(disc.X)), "free_dofs": int(len(free)),
           "pattern_nnz": int(system.pattern.nnz), "reduced_nnz": int(len(red.indices)),
           "time_build_system_s": t_build, "peak_rss_build_system_mb": rss_build["VmHWM"],
           "time_reduced_map_s": t_red, "peak_rss_reduced_map_mb": rss_red["VmHWM"]}
    buf = np.empty(system.pattern.nnz)
    for name, tangent in (("residual", False), ("tangent", True)):
        wall, cpu = [], []
        for _ in range(repeat):
            t0, c0 = time.perf_counter(), time.process_time()
            ev = system.evaluate(u, tangent, out=buf if tangent else None)
            wall.append(time.perf_counter() - t0)
            cpu.append(time.process_time() - c0)
        row[f"time_{name}_s"], row[f"cpu_{name}_s"] = min(wall), min(cpu)
    row["quadruples"] = int(ev.tuples["quadruples"])
    row["cpu_per_quadruple_tangent_s"] = row["cpu_tangent_s"] / max(row["quadruples"], 1)
    if dump:
        np.savez(dump, energy=ev.energy, residual=ev.residual, tangent=ev.tangent.data)
    return row


def solve(size: tuple) -> dict:
    import logging

    import peridynamics
    from cases import library

    logging.basicConfig(level=logging.INFO, format="%(message)s", stream=sys.stderr)
    case = library.cuboid(interface="horizontal", load_case=2, size=size)
    t0, c0 = time.perf_counter(), time.process_time()
    res = peridynamics.solve(case, h=0.035)
    d = res.diagnostics
    return {"size": list(size), "points": d["n_points"], "free_dofs": d["n_free_dofs"],
            "wall_s": time.perf_counter() - t0, "cpu_s": time.process_time() - c0,
            "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
            "newton_history": d["newton_history"], "linear_solver": d["linear_solver"],
            "timings": res.timings}


def _child(tree: str, size: str, repeat: int, dump: str) -> dict:
    env = dict(os.environ, PYTHONPATH=tree)
    out = subprocess.run([sys.executable, __file__, "--child", "--sizes", size, "--repeat", str(repeat),
                          "--dump", dump], cwd=tree, env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def _parse(s: str) -> tuple:
    return tuple(float(v) for v in s.split("x"))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", nargs="+", default=["0.3x0.2x0.2", "0.4x0.3x0.3"])
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--old")
    ap.add_argument("--solve", action="store_true")
    ap.add_argument("--out")
    ap.add_argument("--child", action="store_true")
    ap.add_argument("--dump")
    a = ap.parse_args()
    if a.child:
        sys.path.insert(0, os.getcwd())
        print(json.dumps(measure(_parse(a.sizes[0]), a.repeat, a.dump)))
        return
    import numpy as np

    rows = []
    for s in a.sizes:
        new = _child(str(ROOT), s, a.repeat, "/tmp/bench_cuboid_new.npz")
        row = {"new": new}
        if a.old:
            old = _child(a.old, s, a.repeat, "/tmp/bench_cuboid_old.npz")
            row["old"] = old
            row["ratio_old_over_new"] = {k: old[k] / new[k] for k in new if k.startswith(("cpu_", "time_"))
                                         and new[k] > 0}
            A, B = np.load("/tmp/bench_cuboid_new.npz"), np.load("/tmp/bench_cuboid_old.npz")
            row["max_rel_difference"] = {
                k: float(np.abs(A[k] - B[k]).max() / np.abs(B[k]).max()) for k in ("energy", "residual", "tangent")}
        if a.solve:
            row["solve"] = solve(_parse(s))
        rows.append(row)
        print(json.dumps(row, indent=1, default=str), flush=True)
    if a.out:
        Path(a.out).write_text(json.dumps(rows, indent=1, default=str))


if __name__ == "__main__":
    main()
