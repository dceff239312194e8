"""Checkpoints of an MPM run: its whole state in one file, saved every few minutes of
wall time and on Ctrl-C, from which ``mpm.solve(..., resume=True)`` continues.

The state is what the compiled step does not rebuild every step (mpm/LAYOUT.md: the
nodal fields are zeroed and re-extrapolated each step): the particle arrays that
change (positions, velocities, stresses, strains, volumes, deformation gradients and
the loaded-edge offsets they carry), the run's clock and
history, the adaptive damping, time step and time limit, the last interval's snapshot (Rayleigh
period), the gauges and the VTK frames. A resumed run repeats the uninterrupted one
bit for bit: the output intervals, hence the damping updates, fall on the same steps.

The file is an ``.npz`` (arrays, no pickled objects) written through a temporary
file and a rename, with a fingerprint of the case and the options: a checkpoint of
another run is refused, never continued.
"""
from __future__ import annotations

import hashlib
import json
import os
import tempfile
import time
from pathlib import Path

import numpy as np

from interfaces.errors import CaseError

#: options that do not change the computed run (left out of the fingerprint)
_NEUTRAL_OPTIONS = ("progress", "checkpoint", "checkpoint_every", "resume", "vtk_dir")

#: particle arrays that evolve during a run
_PARTICLE_ARRAYS = ("x", "v", "stress", "strain", "volume", "F", "foff", "eos")


def fingerprint(case, opts: dict) -> str:
    """Hash of the case (its TOML) and of every option that changes the run."""
    kept = {k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in sorted(opts.items())
            if k not in _NEUTRAL_OPTIONS}
    text = case.to_toml() + json.dumps(kept, sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()


def save(path: str | os.PathLike, model, runner) -> None:
    """Write the run's state to ``path`` (atomically)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    pt = model.particles
    arrays = {f"particle_{k}": getattr(pt, k) for k in _PARTICLE_ARRAYS}
    arrays["history"] = runner.history()
    arrays["ke_prev"] = runner.ke_prev
    if runner.snapshot is not None:
        arrays["snapshot_u"], arrays["snapshot_strain"] = runner.snapshot
    if runner.gauges is not None:
        arrays["gauge_times"] = np.asarray(runner.gauges.times, float)
        arrays["gauge_samples"] = np.asarray(runner.gauges.samples, float).reshape(
            len(runner.gauges.samples), -1)
    for k, (t, x, fields) in enumerate(runner.frames):
        arrays[f"frame{k}_position"] = x
        for name, value in fields.items():
            arrays[f"frame{k}_field_{name}"] = value
    scalars = {"fingerprint": fingerprint(model.case, model.opts), "t": runner.t,
               "steps": runner.steps, "wall": runner.wall(), "over_limit": list(runner.over_limit),
               "period": model.period, "alpha": model.alpha, "max_time": model.max_time,
               "dt": model.dt,
               "frame_times": [t for t, _, _ in runner.frames],
               "frame_fields": [list(f) for _, _, f in runner.frames]}
    arrays["scalars"] = np.frombuffer(json.dumps(scalars).encode(), dtype=np.uint8)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".npz", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            np.savez(f, **arrays)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def load(path: str | os.PathLike, model, runner) -> None:
    """Put the state saved in ``path`` back into ``model`` and ``runner``; a CaseError if
    the file belongs to another case or other options."""
    path = Path(path)
    try:
        data = np.load(path, allow_pickle=False)
        scalars = json.loads(bytes(data["scalars"]).decode())
    except (OSError, ValueError, KeyError) as e:
        raise CaseError(f"mpm option resume: {path} is not a readable MPM checkpoint ({e})") from None
    if scalars["fingerprint"] != fingerprint(model.case, model.opts):
        raise CaseError(f"mpm option resume: the checkpoint {path} was written by another case "
                        "or other options; run without resume (or with the same case and options)")
    pt = model.particles
    for k in _PARTICLE_ARRAYS:
        if f"particle_{k}" in data:     # checkpoints written before F was kept: identity
            getattr(pt, k)[...] = data[f"particle_{k}"]
    runner.t, runner.steps = float(scalars["t"]), int(scalars["steps"])
    runner.wall_before = float(scalars.get("wall", 0.0))   # absent in older checkpoints
    runner.started = time.perf_counter()
    hist = data["history"]
    runner.hist_chunks = [hist] if hist.shape[0] else []
    runner.ke_prev[:] = data["ke_prev"]
    runner.over_limit = [int(scalars["over_limit"][0]), int(scalars["over_limit"][1]),
                         float(scalars["over_limit"][2])]
    if "snapshot_u" in data:
        runner.snapshot = (data["snapshot_u"].copy(), data["snapshot_strain"].copy())
    if runner.gauges is not None and "gauge_times" in data:
        runner.gauges.times = data["gauge_times"].tolist()
        runner.gauges.samples = [tuple(row) for row in data["gauge_samples"].tolist()]
    runner.frames = [(t, data[f"frame{k}_position"].copy(),
                      {name: data[f"frame{k}_field_{name}"].copy() for name in names})
                     for k, (t, names) in enumerate(zip(scalars["frame_times"],
                                                        scalars["frame_fields"]))]
    model.period, model.alpha = float(scalars["period"]), float(scalars["alpha"])
    model.max_time = float(scalars["max_time"])
    # runs with finite-strain fields set dt from the state between chunks
    model.dt = float(scalars.get("dt", model.dt))         # absent in older checkpoints
