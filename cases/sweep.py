"""Parameter sweeps: the same case over a list of parameter values, every method,
run in parallel in a local process pool or on a Dask cluster.

Nothing finished is lost: with ``record_dir`` each point is written to
``record_dir/points/point_NNN.json`` the moment it finishes (atomically), a point whose
method fails records the error and the sweep carries on, and ``resume=True`` runs only
the points that have no record yet (after an interrupt), giving the same numbers as an
uninterrupted sweep. A point that runs MPM saves the solver's state next to its record
(``point_NNN.mpm.npz``, every few minutes and on Ctrl-C: mpm/checkpoint.py) and, resumed,
continues from it: an interrupted hours-long point is not started again.
"""
from __future__ import annotations

import csv
import io
import json
import math
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path

from interfaces import CaseError
from interfaces.case import encode_values

from .methods import failure_text, resolve_methods, run
from .output import atomic_write_text
from .registry import build
from .resume import with_mpm_checkpoint

SPEC_FILE = "sweep_spec.json"
#: seconds a sweep waits after Ctrl-C for its workers to save their MPM state
WORKER_GRACE = 60.0


def run_point(case_name: str, overrides: dict, methods: list, options: dict) -> dict:
    """One sweep point: build the case with ``overrides``, run each method, return
    quantities, or the error of a method that failed (the other methods still run)."""
    try:
        case = build(case_name, **overrides)
    except CaseError as e:
        return {m: {"error": str(e)} for m in methods}
    out = {}
    for m in methods:
        try:
            r = run(case, m, **options.get(m, {}))
            out[m] = {"quantities": {k: v for k, v in r.quantities.items()
                                     if isinstance(v, (int, float)) and not isinstance(v, bool)},
                      "time": r.timings.get("total", math.nan)}
        except Exception as e:                  # say why, keep the point and the other methods
            out[m] = {"error": failure_text(e)}
    return out


@dataclass
class Sweep:
    """Quantities per curve, parameter value and method.

    ``curves`` maps a label to the case overrides of that curve (one unnamed curve
    without overrides by default); ``points[c * len(values) + i]`` holds curve ``c`` at
    ``values[i]`` (None if not run).
    """

    case_name: str
    param: str
    values: list
    methods: list
    points: list = field(default_factory=list)
    curves: dict = field(default_factory=lambda: {"": {}})

    @property
    def labels(self) -> list[str]:
        return list(self.curves)

    @property
    def named(self) -> bool:
        """True when the sweep has labelled curves (not the one default curve)."""
        return _named(self.curves)

    def point(self, i: int, curve: int = 0):
        return self.points[curve * len(self.values) + i]

    def value(self, i: int, method: str, quantity: str, curve: int = 0) -> float:
        v = (self.point(i, curve) or {}).get(method, {}).get("quantities", {}).get(quantity, math.nan)
        return float(v)

    def series(self, method: str, quantity: str, curve: int | None = None) -> list[float]:
        """``quantity`` of ``method`` at every value of one curve (all curves, one after
        the other, when ``curve`` is None); NaN where missing."""
        cs = range(len(self.curves)) if curve is None else [curve]
        return [self.value(i, method, quantity, c) for c in cs for i in range(len(self.values))]

    def _where(self, k: int) -> str:
        """``param=value`` of flat point ``k``, prefixed by its curve's label if any."""
        c, i = divmod(k, len(self.values))
        label = self.labels[c]
        return f"{label + ' ' if label else ''}{self.param}={self.values[i]}"

    def quantity_names(self) -> list[str]:
        names: list[str] = []
        for p in self.points:
            for m in self.methods:
                for k in (p or {}).get(m, {}).get("quantities", {}):
                    if k not in names:
                        names.append(k)
        return names

    def errors(self) -> list[str]:
        return [f"{self._where(k)} {m}: {p[m]['error']}" for k, p in enumerate(self.points)
                for m in self.methods if p is not None and "error" in p.get(m, {})]

    def missing(self) -> list[int]:
        """Indices of the points that were not run (interrupted sweep)."""
        return [i for i, p in enumerate(self.points) if p is None]

    def table(self, quantities: list[str] | None = None) -> str:
        """A table per curve: a row per parameter value, a column per (quantity, method)."""
        qs = quantities or self.quantity_names()
        n = len(self.values)
        cols = [(q, m) for q in qs for m in self.methods
                if any(math.isfinite(self.value(i, m, q, c)) for i in range(n) for c in range(len(self.curves)))]
        width = max([26] + [len(q) + len(m) + 3 for q, m in cols])
        head = f"{self.param:>10} " + "".join(f"{q + ' ' + m:>{width}}" for q, m in cols)
        blocks = []
        for c, label in enumerate(self.labels):
            lines = ([f"{label}: {_assignments(self.curves[label])}"] if label else []) + [head, "-" * len(head)]
            for i, v in enumerate(self.values):
                p = self.point(i, c)
                if p is None:
                    lines.append(f"{v!s:>10}  (not run)")
                    continue
                cells = []
                for q, m in cols:
                    x = self.value(i, m, q, c)
                    failed = "error" in p.get(m, {})
                    cells.append(f"{'failed' if failed else '-' if math.isnan(x) else f'{x:.6g}':>{width}}")
                lines.append(f"{v!s:>10} " + "".join(cells))
            blocks.append("\n".join(lines))
        return "\n\n".join(blocks)

    def to_json(self, path=None) -> str:
        data = {"case": self.case_name, "param": self.param, "values": encode_values(self.values),
                "methods": self.methods, "points": self.points}
        if self.named:
            data["curves"] = encode_values(self.curves)
        text = json.dumps(data, indent=1, default=str)
        if path is not None:
            atomic_write_text(path, text)
        return text

    def to_csv(self, path=None) -> str:
        buf = io.StringIO()
        w = csv.writer(buf)
        lead = ["curve"] if self.named else []
        w.writerow(lead + [self.param, "method", "quantity", "value"])
        for c, label in enumerate(self.labels):
            row = [label] if self.named else []
            for i, v in enumerate(self.values):
                for m in self.methods:
                    for q, x in (self.point(i, c) or {}).get(m, {}).get("quantities", {}).items():
                        w.writerow(row + [v, m, q, x])
        if path is not None:
            atomic_write_text(path, buf.getvalue())
        return buf.getvalue()


def sweep(case_name: str, param: str, values, methods="all", fixed: dict | None = None,
          options: dict | None = None, workers: int | None = None, dask_address=None,
          record_dir=None, resume: bool = False, progress: bool = False,
          curves: dict | None = None) -> Sweep:
    """Run ``case_name`` for each value of ``param`` (plus ``fixed`` overrides).

    ``curves`` (label -> overrides, applied over ``fixed``) runs the whole sweep once
    per curve, all points in one pool: e.g. the micro- and nanoparticle composites of
    000 Fig 13 against D. Points run in a local process pool (``workers``, default: CPU
    count), or, with ``dask_address`` (a scheduler address or a
    ``dask.distributed.Client``/cluster), on a Dask cluster; both give the same numbers.
    ``record_dir`` keeps each finished point on disk; ``resume`` reuses the points
    already there (the sweep's case, parameter, values, curves, methods, fixed overrides
    and options must be the same). An interrupt (Ctrl-C) ends the sweep with the
    finished points recorded.
    """
    fixed = dict(fixed or {})
    options = options or {}
    values = list(values)
    curves = _check_curves(curves, param)
    if not values:
        raise CaseError("values must list at least one parameter value")
    overrides = [{**fixed, **over} for over in curves.values()]
    first = [build(case_name, **over, **{param: values[0]}) for over in overrides]  # checks every curve's input
    mlist = resolve_methods(first[0], methods)
    own = sorted({"checkpoint", "resume"} & set(options.get("mpm", {})))
    if own:                              # one file for every point would mix their states
        raise CaseError(f"mpm option {', '.join(own)} is not for sweeps: each point keeps its own "
                        "MPM state in the sweep's --out folder and --resume continues it")
    spec = {"case": case_name, "param": param, "values": encode_values(values), "methods": mlist,
            "fixed": encode_values(fixed), "options": encode_values(options)}
    if _named(curves):
        spec["curves"] = encode_values(curves)
    n = len(values)
    record = Path(record_dir) if record_dir is not None else None
    count = n * len(curves)
    points = _prepare_record(record, spec, resume, count) if record is not None else [None] * count
    todo = [k for k, p in enumerate(points) if p is None]
    keep_state = record is not None and dask_address is None and "mpm" in mlist
    tasks = {k: (case_name, {**overrides[k // n], param: values[k % n]}, mlist,
                 with_mpm_checkpoint(options, _mpm_state(record, k), resume) if keep_state else options)
             for k in todo}

    def finished(k: int, point: dict) -> None:
        points[k] = point
        if record is not None:
            _mpm_state(record, k).unlink(missing_ok=True)
            data = {"index": k, "value": encode_values(values[k % n]), "point": point}
            if _named(curves):
                data["curve"] = list(curves)[k // n]
            atomic_write_text(record / "points" / f"point_{k:03d}.json", json.dumps(data, default=str))

    bar = _progress(len(points), len(points) - len(todo), f"{case_name} {param}", progress)
    try:
        if dask_address is not None:
            _run_dask(tasks, dask_address, finished, bar)
        elif workers == 1 or len(tasks) <= 1:
            for k, t in tasks.items():
                finished(k, run_point(*t))
                bar.update(1)
        else:
            _run_pool(tasks, workers, finished, bar)
    finally:
        bar.close()
    return Sweep(case_name=case_name, param=param, values=values, methods=mlist, points=points, curves=curves)


def _check_curves(curves: dict | None, param: str) -> dict:
    """The curves of a sweep: one unnamed curve by default; labels must be distinct
    non-empty words and no curve may override the swept parameter."""
    if not curves:
        return {"": {}}
    out = {}
    for label, over in curves.items():
        if not isinstance(label, str) or not label.strip() or any(ch in label for ch in ":,="):
            raise CaseError(f"curve label must be a non-empty name without ':', ',' or '=', got {label!r}")
        if param in over:
            raise CaseError(f"curve {label!r} sets the swept parameter {param}; give it in --values instead")
        out[label.strip()] = dict(over)
    return out


def _named(curves: dict) -> bool:
    return list(curves) != [""]


def _assignments(over: dict) -> str:
    return ", ".join(f"{k}={v}" for k, v in over.items()) or "(case defaults)"


def load_spec(record_dir) -> dict:
    """The stored description of a recorded sweep (for ``imperfect sweep --resume``)."""
    path = Path(record_dir) / SPEC_FILE
    try:
        return json.loads(path.read_text())
    except OSError:
        raise CaseError(f"--resume {record_dir}: no recorded sweep there ({SPEC_FILE} missing)") from None
    except json.JSONDecodeError as e:
        raise CaseError(f"--resume {record_dir}: {SPEC_FILE} is not valid JSON ({e})") from None


def _mpm_state(record: Path, k: int) -> Path:
    """The MPM checkpoint of point ``k`` while it runs."""
    return record / "points" / f"point_{k:03d}.mpm.npz"


def _prepare_record(record: Path, spec: dict, resume: bool, count: int) -> list:
    points: list = [None] * count
    (record / "points").mkdir(parents=True, exist_ok=True)
    spec_path = record / SPEC_FILE
    if resume and spec_path.exists():
        old = load_spec(record)
        diff = [k for k in {**old, **spec} if old.get(k) != spec.get(k)]
        if diff:
            raise CaseError(f"--resume {record}: the recorded sweep differs in {', '.join(diff)} "
                            f"(recorded: {', '.join(f'{k}={old.get(k)!r}' for k in diff)})")
        for f in sorted((record / "points").glob("point_*.json")):
            try:
                data = json.loads(f.read_text())
                points[int(data["index"])] = data["point"]
            except (OSError, ValueError, KeyError, IndexError, TypeError):
                continue            # a damaged record is simply run again
    else:
        for f in (record / "points").glob("point_*"):
            f.unlink()
        atomic_write_text(spec_path, json.dumps(spec, indent=1, default=str))
    return points


def _run_pool(tasks: dict, workers, finished, bar) -> None:
    n = workers or min(len(tasks), os.cpu_count() or 1)
    pool = ProcessPoolExecutor(max_workers=n)
    try:
        futures = {pool.submit(run_point, *t): i for i, t in tasks.items()}
        for fut in as_completed(futures):
            finished(futures[fut], fut.result())
            bar.update(1)
    except BaseException:
        workers_left = list((getattr(pool, "_processes", None) or {}).values())
        pool.shutdown(wait=False, cancel_futures=True)
        _stop_workers(workers_left)
        raise
    pool.shutdown()


def _stop_workers(procs: list, grace: float = WORKER_GRACE) -> None:
    """After Ctrl-C: a terminal's Ctrl-C reaches the workers too, and an MPM run there
    stops at the end of its interval and saves its state (mpm.solver._InterruptFlag), so
    wait up to ``grace`` seconds for them before terminating the rest (those keep their
    last periodic checkpoint)."""
    deadline = time.monotonic() + grace
    for proc in procs:
        proc.join(max(0.0, deadline - time.monotonic()))
    for proc in procs:
        if proc.is_alive():
            proc.terminate()


def _run_dask(tasks: dict, address, finished, bar) -> None:
    try:
        from dask.distributed import Client, as_completed as dask_completed
    except ImportError:
        raise CaseError("--dask needs the optional dependency: pip install 'imperfect-interfaces[dask]'") from None
    if isinstance(address, Client):
        client, own = address, False
    elif hasattr(address, "scheduler_address"):
        client, own = Client(address), True
    else:
        client, own = Client(str(address)), True
    try:
        futures = {client.submit(run_point, *t, pure=False): i for i, t in tasks.items()}
        for fut in dask_completed(list(futures)):
            finished(futures[fut], fut.result())
            bar.update(1)
    finally:
        if own:
            client.close()


class _NoBar:
    def update(self, n: int = 1) -> None:
        pass

    def close(self) -> None:
        pass


def _progress(total: int, done: int, label: str, enabled: bool):
    """A tqdm bar over the sweep's points on stderr (none when disabled or unavailable)."""
    if not enabled:
        return _NoBar()
    try:
        from tqdm import tqdm
    except ImportError:
        return _NoBar()
    return tqdm(total=total, initial=done, desc=label, unit="point", file=sys.stderr, dynamic_ncols=True)
