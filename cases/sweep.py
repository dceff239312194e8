"""Parameter sweeps: the same case over a list of parameter values, every method,
run in parallel in a local process pool or on a Dask cluster."""
from __future__ import annotations

import csv
import io
import json
import math
import os
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

from interfaces import CaseError

from .methods import resolve_methods, run
from .registry import build


def run_point(case_name: str, overrides: dict, methods: list, options: dict) -> dict:
    """One sweep point: build the case with ``overrides``, run each method, return quantities."""
    case = build(case_name, **overrides)
    out = {}
    for m in methods:
        try:
            r = run(case, m, **options.get(m, {}))
            out[m] = {"quantities": {k: v for k, v in r.quantities.items() if isinstance(v, (int, float))},
                      "time": r.timings.get("total", math.nan)}
        except CaseError as e:  # includes unavailable methods: report, do not abort the sweep
            out[m] = {"error": str(e)}
    return out


@dataclass
class Sweep:
    """Quantities per parameter value and method."""

    case_name: str
    param: str
    values: list
    methods: list
    points: list = field(default_factory=list)

    def value(self, i: int, method: str, quantity: str) -> float:
        v = self.points[i].get(method, {}).get("quantities", {}).get(quantity, math.nan)
        return float(v)

    def quantity_names(self) -> list[str]:
        names: list[str] = []
        for p in self.points:
            for m in self.methods:
                for k in p.get(m, {}).get("quantities", {}):
                    if k not in names:
                        names.append(k)
        return names

    def errors(self) -> list[str]:
        return [f"{self.param}={v} {m}: {p[m]['error']}" for v, p in zip(self.values, self.points)
                for m in self.methods if "error" in p.get(m, {})]

    def to_json(self, path=None) -> str:
        text = json.dumps({"case": self.case_name, "param": self.param,
                           "values": [str(v) if isinstance(v, float) and math.isinf(v) else v for v in self.values],
                           "methods": self.methods, "points": self.points}, indent=1, default=str)
        if path is not None:
            Path(path).write_text(text)
        return text

    def to_csv(self, path=None) -> str:
        buf = io.StringIO()
        w = csv.writer(buf)
        w.writerow([self.param, "method", "quantity", "value"])
        for i, v in enumerate(self.values):
            for m in self.methods:
                for q, x in self.points[i].get(m, {}).get("quantities", {}).items():
                    w.writerow([v, m, q, x])
        if path is not None:
            Path(path).write_text(buf.getvalue())
        return buf.getvalue()


def sweep(case_name: str, param: str, values, methods="all", fixed: dict | None = None,
          options: dict | None = None, workers: int | None = None, dask_address=None) -> Sweep:
    """Run ``case_name`` for each value of ``param`` (plus ``fixed`` overrides).

    Points run in a local process pool (``workers``, default: CPU count), or, with
    ``dask_address`` (a scheduler address or a ``dask.distributed.Client``/cluster),
    on a Dask cluster; both give the same numbers.
    """
    fixed = dict(fixed or {})
    options = options or {}
    values = list(values)
    if not values:
        raise CaseError("values must list at least one parameter value")
    base = build(case_name, **fixed, **{param: values[0]})
    mlist = resolve_methods(base, methods)
    tasks = [(case_name, {**fixed, param: v}, mlist, options) for v in values]
    if dask_address is not None:
        points = _run_dask(tasks, dask_address)
    elif workers == 1 or len(tasks) == 1:
        points = [run_point(*t) for t in tasks]
    else:
        n = workers or min(len(tasks), os.cpu_count() or 1)
        with ProcessPoolExecutor(max_workers=n) as pool:
            points = list(pool.map(run_point, *zip(*tasks)))
    return Sweep(case_name=case_name, param=param, values=values, methods=mlist, points=points)


def _run_dask(tasks, address):
    try:
        from dask.distributed import Client
    except ImportError:
        raise CaseError("--dask needs the optional dependency: pip install 'imperfect-interfaces[dask]'") from None
    if isinstance(address, Client):
        client, own = address, False
    elif hasattr(address, "scheduler_address"):
        client, own = Client(address), True
    else:
        client, own = Client(str(address)), True
    try:
        futures = [client.submit(run_point, *t, pure=False) for t in tasks]
        return client.gather(futures)
    finally:
        if own:
            client.close()
