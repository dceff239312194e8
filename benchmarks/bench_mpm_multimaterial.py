"""Throughput of the multimaterial node kernels (mpm.multimaterial, 000/004).

Builds a 2D grid whose every node carries two fields (worst case: all nodes are
multimaterial nodes), then times ``correct_momentum`` (phase 0 and 1, frictional
contact and perfect bond) and ``add_interface_forces`` (imperfect interface with
area correction, h-perp, force limiting) per normal method, and the logistic
regression normals (004 Eq 19-25) on a two-block particle set. Prints multimaterial
nodes per second and writes the figures to JSON.

    PYTHONPATH=. python benchmarks/bench_mpm_multimaterial.py [--nodes 200000] [--out bench_mpm_multimaterial.json]
"""
from __future__ import annotations

import argparse
import json
import platform
import time
from types import SimpleNamespace

import numpy as np

from interfaces.case import InterfacePair
from interfaces.laws import CoulombFriction, LinearInterface
from mpm import multimaterial as mm


def _case(law):
    return SimpleNamespace(bodies=[SimpleNamespace(name="a"), SimpleNamespace(name="b")],
                           interfaces=[InterfacePair("a", "b", law)], dimension=2)


def _state(n: int, rng) -> dict:
    mass = rng.uniform(0.5, 1.5, (n, 2))
    return dict(mass=mass, momentum=rng.normal(size=(n, 2, 2)) * mass[:, :, None],
                force=rng.normal(size=(n, 2, 2)), volume=np.full((n, 2), 0.125),
                volume_gradient=rng.normal(size=(n, 2, 2)),
                displacement=rng.normal(size=(n, 2, 2)) * 1e-3,
                position=rng.normal(size=(n, 2, 2)) * 1e-3, cell=np.array([0.5, 0.5]))


def _best(fn, repeat: int) -> float:
    fn()                                   # compile / warm up
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nodes", type=int, default=200_000, help="multimaterial nodes")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--out", default="bench_mpm_multimaterial.json")
    args = ap.parse_args(argv)
    rng = np.random.default_rng(0)
    n = args.nodes
    res: dict = {"nodes": n, "python": platform.python_version(), "machine": platform.machine(),
                 "timings_s": {}, "nodes_per_s": {}}

    def record(name, seconds):
        res["timings_s"][name] = seconds
        res["nodes_per_s"][name] = n / seconds
        print(f"{name:45s} {seconds * 1e3:9.2f} ms  {n / seconds / 1e6:7.2f} M nodes/s")

    for normal in ("SN", "MVG", "AVG"):
        opts = {"normal": normal, "normal_vector": [1.0, 0.0]}
        fr = mm.build_pair_tables(_case(CoulombFriction(0.3)), opts)
        s = _state(n, rng)
        record(f"correct_momentum friction {normal} phase 0",
               _best(lambda: mm.correct_momentum(0, s["mass"], s["momentum"], s["force"], s["volume"],
                                                 s["volume_gradient"], s["displacement"], s["position"],
                                                 s["cell"], fr, 1e-6, 1.0), args.repeat))
        record(f"correct_momentum friction {normal} phase 1",
               _best(lambda: mm.correct_momentum(1, s["mass"], s["momentum"], s["force"], s["volume"],
                                                 s["volume_gradient"], s["displacement"], s["position"],
                                                 s["cell"], fr, 1e-6, 1.0), args.repeat))
        it = mm.build_pair_tables(_case(LinearInterface(100.0, 10.0)), opts)
        out = np.zeros((n, mm.NODE_OUT_COLUMNS))
        record(f"add_interface_forces {normal}",
               _best(lambda: mm.add_interface_forces(s["mass"], s["momentum"], s["volume"],
                                                     s["volume_gradient"], s["displacement"],
                                                     s["position"], s["cell"], 1.0, it, 1e-6,
                                                     s["force"], out), args.repeat))
    perfect = mm.build_pair_tables(_case(LinearInterface(np.inf, np.inf)), {})
    s = _state(n, rng)
    record("correct_momentum perfect phase 0",
           _best(lambda: mm.correct_momentum(0, s["mass"], s["momentum"], s["force"], s["volume"],
                                             s["volume_gradient"], s["displacement"], s["position"],
                                             s["cell"], perfect, 1e-6, 1.0), args.repeat))

    # logistic regression on two blocks meeting along a horizontal line
    h, cell = 0.25, np.array([0.5, 0.5])
    side = int(np.sqrt(n))
    xs = (np.arange(2 * side) + 0.5) * h
    X, Y = np.meshgrid(xs, np.arange(8) * h + h / 2 - 4 * h, indexing="ij")
    x = np.column_stack([X.ravel(), Y.ravel()]) + np.array([1.0, 2.0 + 4 * h])
    field = (x[:, 1] > 2.0 + 4 * h).astype(np.int64)
    nn = np.array([int(x[:, 0].max() / cell[0]) + 4, int(x[:, 1].max() / cell[1]) + 4], np.int64)
    mass = np.zeros((int(nn.prod()), 2))
    iy = int(round((2.0 + 4 * h) / cell[1]))
    rows = np.arange(1, nn[0] - 2) + nn[0] * iy
    mass[rows] = 1.0
    res["lr_nodes"] = int(rows.size)
    t = _best(lambda: mm.lr_normals_separations(x, field, np.array([h / 2, h / 2]), np.zeros(2), cell,
                                                nn, mass, nodes=rows), args.repeat)
    res["timings_s"]["lr_normals_separations"] = t
    res["nodes_per_s"]["lr_normals_separations"] = rows.size / t
    print(f"{'lr_normals_separations':45s} {t * 1e3:9.2f} ms  {rows.size / t / 1e6:7.2f} M nodes/s "
          f"({rows.size} nodes, {x.shape[0]} particles)")
    with open(args.out, "w") as fh:
        json.dump(res, fh, indent=2)
    print(f"wrote {args.out}")
    return res


if __name__ == "__main__":
    main()
