"""CPD benchmark: 100 x 100 points, delta = 3.01 h, Table 2 set 3 (003 Sec 4.1).

One Newton iteration split into its phases: tangent assembly (numba kernels into the
fixed pattern), reduction to the free DOFs, numeric factorisation (symbolic analysis
reused: a second factorisation of the same pattern is timed; its method and precision are
reported), one triangular solve, one product with the tangent, and the linear solve as the
Newton loop runs it right after a factorisation (factorisation + the CG iterations that
bring the step to the asked residual: none with double-precision factors, one with float32
ones); the fresh-factorisation iteration is assembly + reduction + that solve. Then the
iteration as the Newton loop runs it after the first one: the next tangent assembled and
solved to the inexact-Newton forcing term with the factors of the first tangent reused as
the Krylov preconditioner; and a whole Newton
solve (1 and 3 load steps: iterations, residual history, factorisations, Krylov
iterations, time per iteration), with the default preconditioner of each tree. Trees with
``peridynamics.preconditioner`` also report the fresh iteration of the default inexact
Newton step: the pair part of the tangent, its float32 Cholesky, and CG on the exact
tangent to the first forcing term (``iteration(fresh, pairs)``; "fresh iteration old /
pair-preconditioned" compares it with the old tree's fresh iteration). Trees whose kernels
assemble into the free-DOF matrix (``assembly.reduced_target``) time that (``K_ff
direct``) and the pass that adds the tangent and its pair part into their free-DOF
matrices at once (``K_ff+pairs one pass``, the Newton loop's assembly before a
factorisation): their fresh iteration is that pass + factorisation + CG, the others' is
assembly + reduction + pair tangent + factorisation + CG. Three sizes (h = 0.02, 0.0141,
0.01). Times are the
best of a few repetitions, wall clock and process CPU time (the machine is shared: CPU
time is what one core spends). With ``--old PATH`` (a checkout of the previous commit,
e.g. ``git worktree add --detach /tmp/cpd_old main``) the same measurement runs on that
tree in a subprocess in the same run, and the ratios old / new are reported.

    NUMBA_NUM_THREADS=1 MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/bench_cpd.py [--old /tmp/cpd_old] [--out file.json]

(OMP_NUM_THREADS=1 keeps numpy's OpenBLAS on one core too. Trees before the one-thread
vector products of ``peridynamics.newton.vdot`` need it: with OpenBLAS's default two
threads on the loaded 2-core machine their 2 CG iterations took 0.13 s instead of 0.03 s.)
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
    """(best wall time, best CPU time, last result) of ``repeat`` calls."""
    wall, cpu = [], []
    out = None
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        out = fn()
        wall.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    return min(wall), min(cpu), out


def _timed(row: dict, name: str, fn, repeat=3):
    wall, cpu, out = _best(fn, repeat)
    row[f"time_{name}_s"] = wall
    row[f"cpu_{name}_s"] = cpu
    return out


def measure(h: float, delta_factor: float = 3.01) -> dict:
    """Phase times of Newton iterations on the bimaterial square at spacing h (runs on the
    code of whichever tree is first on sys.path: only APIs of both trees are used)."""
    import numpy as np

    from cases import library
    from peridynamics.discretization import discretize
    from peridynamics.newton import NewtonOptions, ReducedMatrix, TangentSolver, newton_solve
    from peridynamics.solver import boundary_vectors, build_system

    case = library.bimaterial_square(parameter_set=3, load_case=1, interface="vertical")
    delta = delta_factor * h
    disc = discretize(case, h, delta, delta, grid="cell")
    row: dict = {}
    system, _ = _timed(row, "neighbours_pattern", lambda: build_system(case, disc, "continuum", None), 1)
    fixed, u_bar, f_ext = boundary_vectors(disc)
    n = system.n_nodes * system.dim
    free = np.setdiff1d(np.arange(n), fixed)
    red = _timed(row, "reduced_map_build", lambda: ReducedMatrix(system, free), 1)
    u = u_bar.copy()
    system.evaluate(u, True)                                     # JIT warm-up (cached kernels)
    _timed(row, "residual", lambda: system.evaluate(u, False))
    try:                                  # into one refilled buffer, as the Newton loop assembles
        system.evaluate(u, False, out=None)
        tangent_buffer = {"out": np.empty(system.pattern.nnz)}
    except TypeError:                     # trees without it
        tangent_buffer = {}
    ev = _timed(row, "tangent_assembly", lambda: system.evaluate(u, True, **tangent_buffer))
    K = _timed(row, "reduce", lambda: red(ev.tangent.data))
    R = ev.residual.ravel()[free]
    solver = TangentSolver(reuse=True)
    t0 = time.perf_counter()
    du = solver.solve(K, -R, rtol=1e-3)                          # first: analysis + factorisation
    row["time_first_factorize_and_solve_s"] = time.perf_counter() - t0
    direct = solver.direct
    _timed(row, "factorization", lambda: direct.factorize(K), 3)
    _timed(row, "triangular_solve", lambda: direct.solve(-R), 5)
    _timed(row, "matvec", lambda: K @ R, 5)

    def fresh_solve():                    # as the Newton loop solves after a factorisation
        solver.factored = False
        return solver.solve(K, -R, rtol=1e-3)

    x = _timed(row, "fresh_linear_solve", fresh_solve, 3)
    row["fresh_linear_solve_relative_residual"] = float(np.linalg.norm(K @ x + R) / np.linalg.norm(R))
    row["factorization_method"] = getattr(direct, "method", "ldlt")
    row["factor_precision"] = getattr(solver, "precision", "double")
    for clock in ("time", "cpu"):         # assembly + reduction + factorisation + solve(s)
        row[f"{clock}_newton_iteration_fresh_factorization_s"] = (
            row[f"{clock}_tangent_assembly_s"] + row[f"{clock}_reduce_s"] + row[f"{clock}_fresh_linear_solve_s"])
    _pair_preconditioner(row, system, free, u, K, R)
    # the second Newton iteration as the loop runs it: assemble at the new iterate, solve
    # to the forcing term with the factors of the first tangent as preconditioner
    v = u.copy()
    v[free] += du
    ev1 = system.evaluate(v, False)
    ratio = float(np.linalg.norm(ev1.residual.ravel()[free]) / np.linalg.norm(R))
    rtol = min(1e-3, 1e-2 * ratio)
    before = dict(solver.stats)

    try:                                  # buffers refilled by every evaluation, as in the Newton loop
        system.evaluate(v, False, out=None)
        buffers = {"out": np.empty(system.pattern.nnz)}, {"out": np.empty(K.nnz)}
    except TypeError:                     # trees without them
        buffers = {}, {}

    def iteration():
        direct.factorize(K)                                      # the first tangent's factors
        solver.factored, solver.stale = True, False
        t0, c0 = time.perf_counter(), time.process_time()
        e = system.evaluate(v, True, **buffers[0])
        K1 = red(e.tangent.data, **buffers[1])
        solver.solve(K1, -e.residual.ravel()[free], rtol=rtol)
        return time.perf_counter() - t0, time.process_time() - c0

    runs = [iteration() for _ in range(3)]
    row["time_newton_iteration_reused_factors_s"] = min(r[0] for r in runs)
    row["cpu_newton_iteration_reused_factors_s"] = min(r[1] for r in runs)
    row["reused_iteration_krylov_iterations"] = (solver.stats["krylov_iterations"] - before["krylov_iterations"]) / 3
    row["reused_iteration_factorizations"] = (solver.stats["factorizations"] - before["factorizations"]) / 3
    row["normalised_residual_after_first_iteration"] = ratio
    for steps in (1, 3):
        t0, c0 = time.perf_counter(), time.process_time()
        out = newton_solve(system, fixed, u_bar, f_ext, NewtonOptions(load_steps=steps))
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        lin = {k: val for k, val in out.linear.items() if not k.startswith("failed")}
        row[f"newton_{steps}_steps"] = {
            "time_s": wall, "cpu_s": cpu, "iterations": out.iterations,
            "iteration_cpu_s": [hh.get("iteration_cpu_s") for hh in out.history],
            "iteration_wall_s": [hh.get("iteration_wall_s") for hh in out.history],
            "time_per_iteration_s": wall / max(out.iterations, 1),
            "cpu_per_iteration_s": cpu / max(out.iterations, 1),
            "residuals": [hh["residuals"] for hh in out.history], "linear": lin,
            "phases_s": {k: float(val) for k, val in out.timings.items()}}
    tuples = sum(ev.tuples.values())
    row.update({
        "h": h, "delta": delta, "grid_points": int(system.n_nodes), "free_dofs": int(len(free)),
        "tangent_nnz": int(system.pattern.nnz), "reduced_nnz": int(K.nnz), "solver": direct.name,
        "tuples_per_cpu_second_tangent": tuples / row["cpu_tangent_assembly_s"],
        "peak_rss_MB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0})
    return row


def _pair_preconditioner(row: dict, system, free, u, K, R) -> None:
    """The fresh iteration of the default inexact Newton step (trees with
    ``peridynamics.preconditioner``): the pair part of the tangent evaluated and reduced,
    its float32 Cholesky, CG on the exact tangent to the first forcing term (1e-3) and to
    1e-10; the iteration = assembly + reduction + pair tangent + factorisation + CG."""
    import numpy as np

    try:
        from peridynamics.preconditioner import PairTangent
        from peridynamics.newton import TangentSolver
    except ImportError:
        return
    pairs = _timed(row, "pair_tangent_build", lambda: PairTangent(system, free), 1)
    P = _timed(row, "pair_tangent", lambda: pairs(u))
    fused = _fused_assembly(row, system, free, u, pairs)
    if fused is not None:                 # the same K_ff and pair tangent, in one pass
        K, P = fused
    solver = TangentSolver(reuse=True)
    solver.solve(K, -R, rtol=1e-3, approx=lambda: P)            # analysis of P's pattern
    _timed(row, "pair_factorization", lambda: solver.approx_direct.factorize(P))
    for tag, rtol in (("", 1e-3), ("_1e-10", 1e-10)):
        before = solver.stats["krylov_iterations"]

        def fresh():
            solver.factored = False
            return solver.solve(K, -R, rtol=rtol, approx=lambda: P)

        x = _timed(row, f"pair_fresh_linear_solve{tag}", fresh)
        row[f"pair_fresh_krylov_iterations{tag}"] = (solver.stats["krylov_iterations"] - before) / 3
        row[f"pair_fresh_relative_residual{tag}"] = float(np.linalg.norm(K @ x + R) / np.linalg.norm(R))
    row["pair_reduced_nnz"] = int(P.nnz)
    for clock in ("time", "cpu"):
        assembly = (row[f"{clock}_tangent_and_pairs_s"] if fused is not None else
                    row[f"{clock}_tangent_assembly_s"] + row[f"{clock}_reduce_s"] + row[f"{clock}_pair_tangent_s"])
        row[f"{clock}_newton_iteration_fresh_pairs_s"] = assembly + row[f"{clock}_pair_fresh_linear_solve_s"]


def _fused_assembly(row: dict, system, free, u, pairs):
    """Trees whose kernels assemble K_ff directly (``assembly.reduced_target``): the tangent into
    K_ff alone (``tangent_reduced``) and with the pair tangent in the same pass
    (``tangent_and_pairs``, the assembly of the default Newton step's fresh iteration; it
    replaces assembly + reduction + pair tangent). Returns (K_ff, P) or None."""
    import numpy as np

    try:
        from peridynamics.assembly import reduced_target
        from peridynamics.reduction import ReducedMatrix
    except ImportError:
        return None
    target = reduced_target(system, ReducedMatrix(system, free))
    if target is None or pairs.fused is None:
        return None
    buf = np.empty(target.nnz)
    _timed(row, "tangent_reduced", lambda: system.evaluate(u, True, out=buf, target=target))
    ev = _timed(row, "tangent_and_pairs", lambda: system.evaluate(u, True, out=buf, target=target, pairs=pairs.fused))
    return ev.tangent, ev.pair_tangent


def _run_in(tree: Path, h: float) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree))
    code = (f"import json, sys; sys.path.insert(0, {str(tree)!r}); sys.path.insert(0, {str(ROOT / 'benchmarks')!r}); "
            f"import bench_cpd; print(json.dumps(bench_cpd.measure({h!r})))")
    out = subprocess.run([sys.executable, "-c", code], env=env, cwd=str(tree), capture_output=True, text=True,
                         check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def _line(tag: str, r: dict) -> str:
    n3 = r["newton_3_steps"]
    pairs = ""
    if "cpu_newton_iteration_fresh_pairs_s" in r:
        fused = (f"K_ff direct={r['cpu_tangent_reduced_s']:.3f} K_ff+pairs one pass={r['cpu_tangent_and_pairs_s']:.3f} "
                 if "cpu_tangent_and_pairs_s" in r else "")
        pairs = (f" | pair preconditioner ({r['pair_reduced_nnz']} nnz): {fused}tangent={r['cpu_pair_tangent_s']:.3f} "
                 f"factor={r['cpu_pair_factorization_s']:.3f} fresh-solve={r['cpu_pair_fresh_linear_solve_s']:.3f} "
                 f"({r['pair_fresh_krylov_iterations']:.0f} CG its to 1e-3, "
                 f"{r['pair_fresh_krylov_iterations_1e-10']:.0f} to 1e-10 in "
                 f"{r['cpu_pair_fresh_linear_solve_1e-10_s']:.3f}) "
                 f"iteration(fresh, pairs)={r['cpu_newton_iteration_fresh_pairs_s']:.3f}")
    base = (f"{tag} h={r['h']:g} points={r['grid_points']} dofs={r['free_dofs']} nnz={r['reduced_nnz']} "
            f"solver={r['solver']} | cpu: assembly={r['cpu_tangent_assembly_s']:.3f} reduce={r['cpu_reduce_s']:.3f} "
            f"factor={r['cpu_factorization_s']:.3f} ({r.get('factorization_method', 'ldlt')}, "
            f"{r.get('factor_precision', 'double')}) tri-solve={r['cpu_triangular_solve_s']:.4f} "
            f"fresh-solve={r['cpu_fresh_linear_solve_s']:.3f} "
            f"matvec={r['cpu_matvec_s']:.4f} residual={r['cpu_residual_s']:.3f} "
            f"iteration(fresh)={r['cpu_newton_iteration_fresh_factorization_s']:.3f} "
            f"iteration(reused)={r['cpu_newton_iteration_reused_factors_s']:.3f} "
            f"[wall {r['time_newton_iteration_reused_factors_s']:.3f}, "
            f"{r['reused_iteration_krylov_iterations']:.1f} Krylov its] | 3 steps: {n3['iterations']} its, "
            f"{n3['cpu_s']:.2f} s cpu, {n3['cpu_per_iteration_s']:.3f} s/it, "
            f"{n3['linear']['factorizations']} factorisations"
            + (f", per-iteration cpu {_fmt(n3['iteration_cpu_s'])}" if n3["iteration_cpu_s"][0] else ""))
    return base + pairs


def _fmt(steps) -> str:
    return " / ".join(",".join(f"{t:.2f}" for t in s) for s in steps)


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--old", default=None, help="checkout of the previous commit to measure side by side")
    ap.add_argument("--sizes", default=",".join(map(str, SIZES)))
    ap.add_argument("--out", default=str(Path(__file__).with_name("bench_cpd.json")))
    args = ap.parse_args(argv)
    rows = []
    for h in (float(v) for v in args.sizes.split(",")):
        row = {"new": _run_in(ROOT, h)}
        if args.old:
            old = _run_in(Path(args.old).resolve(), h)
            row["old"] = old
            row["ratio_old_over_new"] = {k: old[k] / row["new"][k] for k in row["new"]
                                         if k.startswith(("time_", "cpu_")) and k in old and row["new"][k] > 0}
            for steps in (1, 3):
                key = f"newton_{steps}_steps"
                row["ratio_old_over_new"][f"{key}_cpu"] = old[key]["cpu_s"] / row["new"][key]["cpu_s"]
            if "cpu_newton_iteration_fresh_pairs_s" in row["new"]:   # old fresh iteration / new default one
                row["ratio_old_over_new"]["cpu_fresh_iteration_old_over_pairs"] = (
                    old["cpu_newton_iteration_fresh_factorization_s"] / row["new"]["cpu_newton_iteration_fresh_pairs_s"])
        rows.append(row)
        for tag in ("new", "old"):
            if tag in row:
                print(_line(tag, row[tag]), flush=True)
        if "ratio_old_over_new" in row:
            rr = row["ratio_old_over_new"]
            print(f"   old/new (cpu): assembly {rr['cpu_tangent_assembly_s']:.2f}x, "
                  f"fresh iteration {rr['cpu_newton_iteration_fresh_factorization_s']:.2f}x, "
                  f"reused iteration {rr['cpu_newton_iteration_reused_factors_s']:.2f}x, "
                  f"triangular solve {rr['cpu_triangular_solve_s']:.2f}x, "
                  f"Newton solve 1 step {rr['newton_1_steps_cpu']:.2f}x, 3 steps {rr['newton_3_steps_cpu']:.2f}x"
                  + (f", fresh iteration old / pair-preconditioned {rr['cpu_fresh_iteration_old_over_pairs']:.2f}x"
                     if "cpu_fresh_iteration_old_over_pairs" in rr else "")
                  + (f", pair-preconditioned fresh iteration {rr['cpu_newton_iteration_fresh_pairs_s']:.2f}x"
                     f" (wall {rr['time_newton_iteration_fresh_pairs_s']:.2f}x)"
                     if "cpu_newton_iteration_fresh_pairs_s" in rr else ""),
                  flush=True)
    out = {"case": "bimaterial_square set 3, vertical interface, load case I, delta = 3.01 h, cell grid",
           "threads": {k: os.environ.get(k) for k in ("NUMBA_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS")},
           "python": platform.python_version(), "machine": platform.machine(), "sizes": rows}
    Path(args.out).write_text(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
