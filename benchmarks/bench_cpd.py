"""CPD benchmark: 100 x 100 points, delta = 3.01 h, Table 2 set 3 (003 Sec 4.1).

Measures the residual evaluation, the tangent assembly, the sparse factorisation, one full
Newton iteration (assembly + solve) with a fresh factorisation and with the reused
factors, interaction tuples per second and peak memory. Prints the figures and writes
JSON (default benchmarks/bench_cpd.json).

    PYTHONPATH=. NUMBA_NUM_THREADS=1 python benchmarks/bench_cpd.py [--out file.json] [--h 0.01]
"""
from __future__ import annotations

import argparse
import json
import platform
import resource
import time
import tracemalloc
from pathlib import Path

import numpy as np


def _best(fn, repeat=3):
    ts = []
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t0)
    return min(ts), out


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--h", type=float, default=0.01)
    ap.add_argument("--delta-factor", type=float, default=3.01)
    ap.add_argument("--out", default=str(Path(__file__).with_name("bench_cpd.json")))
    args = ap.parse_args(argv)

    from cases import library
    from peridynamics.discretization import discretize
    from peridynamics.newton import ReducedMatrix, TangentSolver
    from peridynamics.solver import boundary_vectors, build_system

    case = library.bimaterial_square(parameter_set=3, load_case=1, interface="vertical")
    h = args.h
    delta = args.delta_factor * h
    tracemalloc.start()
    t0 = time.perf_counter()
    disc = discretize(case, h, delta, delta, grid="cell")       # 100 x 100 body points at h = 0.01
    t_disc = time.perf_counter() - t0
    t0 = time.perf_counter()
    system, _ = build_system(case, disc, "continuum", None)
    t_setup = time.perf_counter() - t0
    fixed, u_bar, f_ext = boundary_vectors(disc)
    n = system.n_nodes * system.dim
    free = np.setdiff1d(np.arange(n), fixed)
    red = ReducedMatrix(system, free)
    u = u_bar.copy()
    system.evaluate(u, True)                                     # JIT warm-up (cached kernels)
    t_res, ev_r = _best(lambda: system.evaluate(u, False))
    t_tan, ev = _best(lambda: system.evaluate(u, True))
    tuples = sum(ev.tuples.values())
    K = red(ev.tangent.data)
    R = ev.residual.ravel()[free]
    solver = TangentSolver(reuse=True)
    t0 = time.perf_counter()
    du = solver.solve(K, -R)
    t_factor_solve = time.perf_counter() - t0
    # next Newton iteration: new tangent at the updated state, solved with the reused factors
    v = u.copy()
    v[free] += du
    t0 = time.perf_counter()
    ev2 = system.evaluate(v, True)
    K2 = red(ev2.tangent.data)
    R2 = ev2.residual.ravel()[free]
    ratio = float(np.linalg.norm(R2) / np.linalg.norm(R))
    # the forcing term used by newton_solve at this iteration
    du2 = solver.solve(K2, -R2, rtol=min(1e-3, 1e-2 * ratio))
    t_iter_reuse = time.perf_counter() - t0
    rel = float(np.linalg.norm(K2 @ du2 + ev2.residual.ravel()[free]) / np.linalg.norm(ev2.residual.ravel()[free]))
    _, peak_traced = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    peak_rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0   # MB (Linux: kB)
    out = {
        "case": "bimaterial_square set 3, vertical interface, load case I",
        "h": h, "delta": delta, "grid_points": int(system.n_nodes),
        "body_points": int((~disc.layer).sum()), "dofs": int(n), "free_dofs": int(len(free)),
        "tangent_nnz": int(system.pattern.nnz), "tuples": ev.tuples,
        "time_discretize_s": t_disc, "time_neighbours_pattern_s": t_setup,
        "time_residual_s": t_res, "time_tangent_assembly_s": t_tan,
        "time_factorize_and_solve_s": t_factor_solve,
        "time_newton_iteration_fresh_factorization_s": t_tan + t_factor_solve,
        "time_newton_iteration_reused_factors_s": t_iter_reuse,
        "reused_factor_solve_relative_residual": rel,
        "normalised_residual_after_first_iteration": ratio,
        "krylov_iterations_second_iteration": solver.stats["krylov_iterations"],
        "tuples_per_second_residual": tuples / t_res,
        "tuples_per_second_tangent": tuples / t_tan,
        "peak_traced_python_memory_MB": peak_traced / 2 ** 20, "peak_rss_MB": peak_rss,
        "python": platform.python_version(), "machine": platform.machine(),
    }
    for k, val in out.items():
        print(f"{k:45s} {val}")
    Path(args.out).write_text(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
