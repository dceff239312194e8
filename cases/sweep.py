"""Parameter sweeps: the same case over a list of parameter values, every method,
run in parallel in a local process pool or on a Dask cluster.

Nothing finished is lost: with ``record_dir`` each point is written to
``record_dir/points/point_NNN.json`` the moment it finishes (atomically), a point whose
method fails records the error and the sweep carries on, and ``resume=True`` runs only
the points that have no record yet (after an interrupt), giving the same numbers as an
uninterrupted sweep.
"""
from __future__ import annotations

import csv
import io
import json
import math
import os
import sys
import traceback
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path

from interfaces import CaseError, SolverError
from interfaces.case import encode_values

from .methods import resolve_methods, run
from .output import atomic_write_text
from .registry import build

SPEC_FILE = "sweep_spec.json"


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
        except (CaseError, SolverError) as e:   # bad input, unsupported, diverged: say why
            out[m] = {"error": str(e)}
        except Exception as e:                  # a bug: keep the point, show where
            where = traceback.extract_tb(e.__traceback__)[-1]
            out[m] = {"error": f"{type(e).__name__}: {e} (at {Path(where.filename).name}:{where.lineno})"}
    return out


@dataclass
class Sweep:
    """Quantities per parameter value and method (``points[i]`` is None if not run)."""

    case_name: str
    param: str
    values: list
    methods: list
    points: list = field(default_factory=list)

    def value(self, i: int, method: str, quantity: str) -> float:
        v = (self.points[i] or {}).get(method, {}).get("quantities", {}).get(quantity, math.nan)
        return float(v)

    def quantity_names(self) -> list[str]:
        names: list[str] = []
        for p in self.points:
            for m in self.methods:
                for k in (p or {}).get(m, {}).get("quantities", {}):
                    if k not in names:
                        names.append(k)
        return names

    def errors(self) -> list[str]:
        return [f"{self.param}={v} {m}: {p[m]['error']}" for v, p in zip(self.values, self.points)
                for m in self.methods if p is not None and "error" in p.get(m, {})]

    def missing(self) -> list[int]:
        """Indices of the points that were not run (interrupted sweep)."""
        return [i for i, p in enumerate(self.points) if p is None]

    def table(self, quantities: list[str] | None = None) -> str:
        """One table: a row per parameter value, a column per (quantity, method)."""
        qs = quantities or self.quantity_names()
        cols = [(q, m) for q in qs for m in self.methods
                if any(math.isfinite(self.value(i, m, q)) for i in range(len(self.values)))]
        head = f"{self.param:>10} " + "".join(f"{q + ' ' + m:>26}" for q, m in cols)
        lines = [head, "-" * len(head)]
        for i, v in enumerate(self.values):
            if self.points[i] is None:
                lines.append(f"{v!s:>10}  (not run)")
                continue
            cells = []
            for q, m in cols:
                x = self.value(i, m, q)
                failed = "error" in self.points[i].get(m, {})
                cells.append(f"{'failed' if failed else '-' if math.isnan(x) else f'{x:.6g}':>26}")
            lines.append(f"{v!s:>10} " + "".join(cells))
        return "\n".join(lines)

    def to_json(self, path=None) -> str:
        text = json.dumps({"case": self.case_name, "param": self.param, "values": encode_values(self.values),
                           "methods": self.methods, "points": self.points}, indent=1, default=str)
        if path is not None:
            atomic_write_text(path, text)
        return text

    def to_csv(self, path=None) -> str:
        buf = io.StringIO()
        w = csv.writer(buf)
        w.writerow([self.param, "method", "quantity", "value"])
        for i, v in enumerate(self.values):
            for m in self.methods:
                for q, x in (self.points[i] or {}).get(m, {}).get("quantities", {}).items():
                    w.writerow([v, m, q, x])
        if path is not None:
            atomic_write_text(path, buf.getvalue())
        return buf.getvalue()


def sweep(case_name: str, param: str, values, methods="all", fixed: dict | None = None,
          options: dict | None = None, workers: int | None = None, dask_address=None,
          record_dir=None, resume: bool = False, progress: bool = False) -> Sweep:
    """Run ``case_name`` for each value of ``param`` (plus ``fixed`` overrides).

    Points run in a local process pool (``workers``, default: CPU count), or, with
    ``dask_address`` (a scheduler address or a ``dask.distributed.Client``/cluster),
    on a Dask cluster; both give the same numbers. ``record_dir`` keeps each finished
    point on disk; ``resume`` reuses the points already there (the sweep's case,
    parameter, values, methods, fixed overrides and options must be the same).
    An interrupt (Ctrl-C) ends the sweep with the finished points recorded.
    """
    fixed = dict(fixed or {})
    options = options or {}
    values = list(values)
    if not values:
        raise CaseError("values must list at least one parameter value")
    base = build(case_name, **fixed, **{param: values[0]})
    mlist = resolve_methods(base, methods)
    spec = {"case": case_name, "param": param, "values": encode_values(values), "methods": mlist,
            "fixed": encode_values(fixed), "options": encode_values(options)}
    points: list = [None] * len(values)
    record = Path(record_dir) if record_dir is not None else None
    if record is not None:
        points = _prepare_record(record, spec, resume)
    todo = [i for i, p in enumerate(points) if p is None]
    tasks = {i: (case_name, {**fixed, param: values[i]}, mlist, options) for i in todo}

    def finished(i: int, point: dict) -> None:
        points[i] = point
        if record is not None:
            atomic_write_text(record / "points" / f"point_{i:03d}.json",
                              json.dumps({"index": i, "value": encode_values(values[i]), "point": point},
                                         default=str))

    bar = _progress(len(values), len(values) - len(todo), f"{case_name} {param}", progress)
    try:
        if dask_address is not None:
            _run_dask(tasks, dask_address, finished, bar)
        elif workers == 1 or len(tasks) <= 1:
            for i, t in tasks.items():
                finished(i, run_point(*t))
                bar.update(1)
        else:
            _run_pool(tasks, workers, finished, bar)
    finally:
        bar.close()
    return Sweep(case_name=case_name, param=param, values=values, methods=mlist, points=points)


def load_spec(record_dir) -> dict:
    """The stored description of a recorded sweep (for ``imperfect sweep --resume``)."""
    path = Path(record_dir) / SPEC_FILE
    try:
        return json.loads(path.read_text())
    except OSError:
        raise CaseError(f"--resume {record_dir}: no recorded sweep there ({SPEC_FILE} missing)") from None
    except json.JSONDecodeError as e:
        raise CaseError(f"--resume {record_dir}: {SPEC_FILE} is not valid JSON ({e})") from None


def _prepare_record(record: Path, spec: dict, resume: bool) -> list:
    points: list = [None] * len(spec["values"])
    (record / "points").mkdir(parents=True, exist_ok=True)
    spec_path = record / SPEC_FILE
    if resume and spec_path.exists():
        old = load_spec(record)
        diff = [k for k in spec if old.get(k) != spec[k]]
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
        for f in (record / "points").glob("point_*.json"):
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
        pool.shutdown(wait=False, cancel_futures=True)
        for proc in list(getattr(pool, "_processes", {}).values()):
            proc.terminate()
        raise
    pool.shutdown()


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
