"""CPD benchmark: 100 x 100 points, delta = 3.01 h, Table 2 set 3 (003 Sec 4.1).

One Newton iteration split into its phases: tangent assembly (numba kernels into the
fixed pattern), reduction to the free DOFs, numeric factorisation (symbolic analysis
reused: the second factorisation of the same pattern is timed), solve; plus the residual
evaluation and the next iteration with the factors reused as a GMRES preconditioner.
Three sizes (h = 0.02, 0.0141, 0.01). With ``--old PATH`` (a checkout of the previous
commit, e.g. ``git worktree add --detach /tmp/cpd_old main``) the same measurement runs
on that tree in a subprocess in the same run, and the ratio old / new is reported.

    NUMBA_NUM_THREADS=1 MKL_NUM_THREADS=1 python benchmarks/bench_cpd.py [--old /tmp/cpd_old] [--out file.json]
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import time
from pathlib import Path

SIZES = (0.02, 0.0141, 0.01)
ROOT = Path(__file__).resolve().parents[1]


def _best(fn, repeat=3):
    ts = []
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t0)
    return min(ts), out


def measure(h: float, delta_factor: float = 3.01) -> dict:
    """Phase times of one Newton iteration of the bimaterial square at spacing h."""
    import numpy as np

    from cases import library
    from peridynamics.discretization import discretize
    from peridynamics.newton import ReducedMatrix, TangentSolver
    from peridynamics.solver import boundary_vectors, build_system

    case = library.bimaterial_square(parameter_set=3, load_case=1, interface="vertical")
    delta = delta_factor * h
    disc = discretize(case, h, delta, delta, grid="cell")
    t0 = time.perf_counter()
    system, _ = build_system(case, disc, "continuum", None)
    t_setup = time.perf_counter() - t0
    fixed, u_bar, f_ext = boundary_vectors(disc)
    n = system.n_nodes * system.dim
    free = np.setdiff1d(np.arange(n), fixed)
    t0 = time.perf_counter()
    red = ReducedMatrix(system, free)
    t_red_build = time.perf_counter() - t0
    u = u_bar.copy()
    system.evaluate(u, True)                                     # JIT warm-up (cached kernels)
    t_res, _ = _best(lambda: system.evaluate(u, False))
    t_tan, ev = _best(lambda: system.evaluate(u, True))
    t_red, K = _best(lambda: red(ev.tangent.data))
    R = ev.residual.ravel()[free]
    solver = TangentSolver(reuse=True)
    t0 = time.perf_counter()
    du = solver.solve(K, -R)                                     # first: analysis + factorisation
    t_first = time.perf_counter() - t0
    direct = getattr(solver, "direct", None)
    if direct is not None:                                       # refactorise the same pattern
        t_fact, _ = _best(lambda: direct.factorize(K), repeat=2)
        t_solve, _ = _best(lambda: direct.solve(-R))
        name = direct.name
    else:                                                        # previous code: SuperLU every time
        t_fact, lu = _best(lambda: solver._factor(K) or solver.lu, repeat=2)
        t_solve, _ = _best(lambda: solver.lu.solve(-R))
        name = "superlu"
    v = u.copy()
    v[free] += du
    t0 = time.perf_counter()
    ev2 = system.evaluate(v, True)
    K2 = red(ev2.tangent.data)
    R2 = ev2.residual.ravel()[free]
    ratio = float(np.linalg.norm(R2) / np.linalg.norm(R))
    solver.solve(K2, -R2, rtol=min(1e-3, 1e-2 * ratio))
    t_reuse = time.perf_counter() - t0
    tuples = sum(ev.tuples.values())
    return {
        "h": h, "delta": delta, "grid_points": int(system.n_nodes), "free_dofs": int(len(free)),
        "tangent_nnz": int(system.pattern.nnz), "reduced_nnz": int(K.nnz), "solver": name,
        "time_neighbours_pattern_s": t_setup, "time_reduced_map_build_s": t_red_build,
        "time_residual_s": t_res, "time_tangent_assembly_s": t_tan, "time_reduce_s": t_red,
        "time_first_factorize_and_solve_s": t_first, "time_factorization_s": t_fact,
        "time_solve_s": t_solve,
        "time_newton_iteration_fresh_factorization_s": t_tan + t_red + t_fact + t_solve,
        "time_newton_iteration_reused_factors_s": t_reuse,
        "normalised_residual_after_first_iteration": ratio,
        "tuples_per_second_tangent": tuples / t_tan,
        "peak_rss_MB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
    }


def _run_in(tree: Path, h: float) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree))
    code = (f"import json, sys; sys.path.insert(0, {str(tree)!r}); sys.path.insert(0, {str(ROOT / 'benchmarks')!r}); "
            f"import bench_cpd; print(json.dumps(bench_cpd.measure({h!r})))")
    out = subprocess.run([sys.executable, "-c", code], env=env, cwd=str(tree), capture_output=True, text=True,
                         check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--old", default=None, help="checkout of the previous commit to measure side by side")
    ap.add_argument("--sizes", default=",".join(map(str, SIZES)))
    ap.add_argument("--out", default=str(Path(__file__).with_name("bench_cpd.json")))
    args = ap.parse_args(argv)
    rows = []
    for h in (float(v) for v in args.sizes.split(",")):
        new = _run_in(ROOT, h)
        row = {"new": new}
        if args.old:
            old = _run_in(Path(args.old).resolve(), h)
            row["old"] = old
            row["ratio_old_over_new"] = {k: old[k] / new[k] for k in new
                                         if k.startswith("time_") and k in old and new[k] > 0}
        rows.append(row)
        for tag in ("new", "old"):
            if tag in row:
                r = row[tag]
                print(f"{tag} h={h:g} points={r['grid_points']} dofs={r['free_dofs']} nnz={r['reduced_nnz']} "
                      f"solver={r['solver']} assembly={r['time_tangent_assembly_s']:.3f} reduce={r['time_reduce_s']:.3f} "
                      f"factor={r['time_factorization_s']:.3f} solve={r['time_solve_s']:.3f} "
                      f"iteration(fresh)={r['time_newton_iteration_fresh_factorization_s']:.3f} "
                      f"iteration(reused)={r['time_newton_iteration_reused_factors_s']:.3f} "
                      f"residual={r['time_residual_s']:.3f}", flush=True)
        if "ratio_old_over_new" in row:
            rr = row["ratio_old_over_new"]
            print(f"   old/new: fresh iteration {rr['time_newton_iteration_fresh_factorization_s']:.2f}x, "
                  f"reused {rr['time_newton_iteration_reused_factors_s']:.2f}x, "
                  f"factorisation {rr['time_factorization_s']:.2f}x", flush=True)
    out = {"case": "bimaterial_square set 3, vertical interface, load case I, delta = 3.01 h, cell grid",
           "threads": {k: os.environ.get(k) for k in ("NUMBA_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS")},
           "python": platform.python_version(), "machine": platform.machine(), "sizes": rows}
    Path(args.out).write_text(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
