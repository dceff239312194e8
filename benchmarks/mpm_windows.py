"""Shared pieces of the MPM throughput benchmarks that compare variants of one problem.

The block of ``bench_mpm.py`` (``single_ugimp``: plane strain, bottom fixed, sheared top
traction, 1 mm cells of 2 x 2 particles), optionally split at mid-height into two bodies
bonded by a perfect interface; the variants stepped alternately in windows (the
machine's speed drifts by up to 2x within minutes: the medians over windows, and their
ratios, are the figures); the JSON written next to the calling script.

Each window is timed by the wall clock and by the process's CPU time (on a shared
machine the CPU time is what the run itself spent; one numba thread). With ``old`` (a
checkout of the previous commit, e.g. ``git worktree add --detach /tmp/mpm_old main``)
the same variants are built by that tree's ``mpm`` in a second process and its windows
interleave with this tree's, in alternating order: the old / new comparison of one run.
"""
from __future__ import annotations

import importlib
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

BENCH_DIR = Path(__file__).resolve().parent


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


def summary(particles: dict, steps: dict, rates: dict, cpu_rates: dict | None = None) -> dict:
    """Per variant: particles, steps, median and best particle-steps/s of its windows
    (wall clock) and, with ``cpu_rates``, the median per CPU second."""
    import numpy as np
    out = {name: {"particles": int(particles[name]), "steps": int(steps[name]),
                  "particle_steps_per_s": float(np.median(r)),
                  "best_window_particle_steps_per_s": float(np.max(r))}
           for name, r in rates.items()}
    for name, r in (cpu_rates or {}).items():
        out[name]["particle_steps_per_cpu_s"] = float(np.median(r))
    return out


class _Runs:
    """The built and warmed-up runs of ``variants`` (name -> (case, mpm options)), stepped
    one window at a time."""

    def __init__(self, variants: dict):
        from mpm.options import merge
        from mpm.solver import Model, _Runner
        self.runs = {}
        for name, (case, opts) in variants.items():
            model = Model(case, merge(case, dict({"cell": 1.0, "progress": False}, **opts)))
            run = _Runner(model)
            run._advance(3)           # compiled (or cached) kernels loaded
            self.runs[name] = (model.particles.P, run)

    def window(self, per: int) -> dict:
        """name -> (wall, CPU) particle-steps/s of ``per`` steps of each run in turn."""
        rates = {}
        for name, (P, run) in self.runs.items():
            c0, t0 = time.process_time(), time.perf_counter()
            run._advance(per)
            wall, cpu = time.perf_counter() - t0, time.process_time() - c0
            rates[name] = (P * per / wall, P * per / max(cpu, 1e-9))
        return rates


def _serve(module: str, builder: str, kwargs: str) -> None:
    """The old tree's side of :func:`interleaved_rates`: build the variants of
    ``module.builder(**kwargs)``, print their particle counts, then one window per line
    read (its steps) until stdin closes."""
    runs = _Runs(getattr(importlib.import_module(module), builder)(**json.loads(kwargs)))
    print(json.dumps({n: P for n, (P, _) in runs.runs.items()}), flush=True)
    for line in sys.stdin:
        print(json.dumps(runs.window(int(line))), flush=True)


class _OldTree:
    """A process stepping the same variants with the ``mpm`` of the checkout ``tree``
    (the benchmark modules of this directory)."""

    def __init__(self, tree: str, source: tuple):
        module, builder, kwargs = source
        tree = str(Path(tree).resolve())
        code = (f"import sys; sys.path[:0] = [{tree!r}, {str(BENCH_DIR)!r}]; import mpm_windows; "
                f"mpm_windows._serve({module!r}, {builder!r}, {json.dumps(kwargs)!r})")
        self.proc = subprocess.Popen([sys.executable, "-c", code], cwd=tree, text=True,
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     env=dict(os.environ, PYTHONPATH=tree))
        self.particles = json.loads(self._line())

    def _line(self) -> str:
        line = self.proc.stdout.readline()
        if not line:
            code = self.proc.wait()
            raise RuntimeError(f"the old tree's benchmark process stopped (code {code})")
        return line

    def window(self, per: int) -> dict:
        self.proc.stdin.write(f"{per}\n")
        self.proc.stdin.flush()
        return {n: tuple(r) for n, r in json.loads(self._line()).items()}

    def close(self) -> None:
        self.proc.stdin.close()
        self.proc.wait()


def _collect(windows: list, particles: dict, per: int) -> dict:
    names = list(particles)
    return summary(particles, {n: per * len(windows) for n in names},
                   {n: [w[n][0] for w in windows] for n in names},
                   {n: [w[n][1] for w in windows] for n in names})


def interleaved_rates(variants: dict, steps: int, windows: int, old: str | None = None,
                      source: tuple | None = None) -> dict:
    """``variants``: name -> (case, mpm options). Each model is built and stepped 3 times
    (compiled / cached kernels loaded), then all are stepped ``steps // windows`` steps
    per window in turn; returns :func:`summary` of the window rates. With ``old`` (a
    checkout) and ``source`` = (module, function, kwargs) that builds the same
    ``variants`` in that tree, returns {"new": ..., "old": ..., "new_over_old": speed
    ratios per variant (wall and CPU medians)}."""
    per = max(1, steps // windows)
    runs = _Runs(variants)
    particles = {n: P for n, (P, _) in runs.runs.items()}
    if old is None:
        return _collect([runs.window(per) for _ in range(windows)], particles, per)
    other = _OldTree(old, source)
    new_w, old_w = [], []
    try:
        for k in range(windows):
            if k % 2:
                old_w.append(other.window(per))
                new_w.append(runs.window(per))
            else:
                new_w.append(runs.window(per))
                old_w.append(other.window(per))
    finally:
        other.close()
    new, prev = _collect(new_w, particles, per), _collect(old_w, other.particles, per)
    ratio = {n: {"wall": new[n]["particle_steps_per_s"] / prev[n]["particle_steps_per_s"],
                 "cpu": new[n]["particle_steps_per_cpu_s"] / prev[n]["particle_steps_per_cpu_s"]}
             for n in new if n in prev}
    return {"new": new, "old": prev, "new_over_old": ratio}


def write_json(script: str, out: dict) -> None:
    """Print ``out`` and write it as JSON next to ``script`` (its ``__file__``)."""
    text = json.dumps(out, indent=2)
    print(text)
    Path(script).with_suffix(".json").write_text(text + "\n")
