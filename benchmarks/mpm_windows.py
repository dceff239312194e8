"""Shared pieces of the MPM throughput benchmarks that compare variants of one problem.

The block of ``bench_mpm.py`` (``single_ugimp``: plane strain, bottom fixed, sheared top
traction, 1 mm cells of 2 x 2 particles), optionally split at mid-height into two bodies
bonded by a perfect interface; the variants stepped alternately in windows (the
machine's speed drifts by up to 2x within minutes: the medians over windows, and their
ratios, are the figures); the JSON written next to the calling script.
"""
from __future__ import annotations

import json
import math
import time
from pathlib import Path


def loaded_block(material, side: float = 160.0, split: bool = False):
    """The benchmark block of ``material``, ``side`` mm square (split: two bodies
    bonded by a perfect interface at mid-height)."""
    from interfaces import Body, BoundaryCondition, Case, InterfacePair, LinearInterface, Rectangle
    if split:
        bodies = [Body("low", Rectangle(0, 0, side, side / 2), "m"),
                  Body("up", Rectangle(0, side / 2, side, side / 2), "m")]
        pairs = [InterfacePair("low", "up", LinearInterface(Dn=math.inf, Dt=math.inf))]
    else:
        bodies, pairs = [Body("b", Rectangle(0, 0, side, side), "m")], []
    return Case(name="block", analysis="plane_strain", thickness=1.0, materials={"m": material},
                bodies=bodies, interfaces=pairs, boundary_conditions=[
                    BoundaryCondition("fixed", bodies[0].name, "ymin", ("x", "y"), (0.0, 0.0)),
                    BoundaryCondition("traction", bodies[-1].name, "ymax", ("x", "y"),
                                      (1.0, -5.0))])


def summary(particles: dict, steps: dict, rates: dict) -> dict:
    """Per variant: particles, steps, median and best particle-steps/s of its windows."""
    import numpy as np
    return {name: {"particles": int(particles[name]), "steps": int(steps[name]),
                   "particle_steps_per_s": float(np.median(r)),
                   "best_window_particle_steps_per_s": float(np.max(r))}
            for name, r in rates.items()}


def interleaved_rates(variants: dict, steps: int, windows: int) -> dict:
    """``variants``: name -> (case, mpm options). Each model is built and stepped 3 times
    (compiled / cached kernels loaded), then all are stepped ``steps // windows`` steps
    per window in turn; returns :func:`summary` of the window rates."""
    from mpm.options import merge
    from mpm.solver import Model, _Runner
    runs = {}
    for name, (case, opts) in variants.items():
        model = Model(case, merge(case, dict({"cell": 1.0, "progress": False}, **opts)))
        run = _Runner(model)
        run._advance(3)
        runs[name] = (model, run, [])
    per = max(1, steps // windows)
    for _ in range(windows):
        for model, run, rates in runs.values():
            t0 = time.perf_counter()
            run._advance(per)
            rates.append(model.particles.P * per / (time.perf_counter() - t0))
    return summary({n: m.particles.P for n, (m, _, _) in runs.items()},
                   {n: per * windows for n in runs}, {n: r for n, (_, _, r) in runs.items()})


def write_json(script: str, out: dict) -> None:
    """Print ``out`` and write it as JSON next to ``script`` (its ``__file__``)."""
    text = json.dumps(out, indent=2)
    print(text)
    Path(script).with_suffix(".json").write_text(text + "\n")
