"""Dispatch to the solvers by method name; a missing solver answers with a clear message."""
from __future__ import annotations

import importlib
import time
from typing import Callable

from interfaces import Case, CaseError, Result

SOLVERS = {
    "analytic": ("interfaces.analytic", "solve"),
    "fem": ("fem", "solve"),
    "mpm": ("mpm", "solve"),
    "cpd": ("peridynamics", "solve"),
}


class MethodUnavailable(CaseError):
    """The method is not installed or not implemented for this case."""


def solver(method: str) -> Callable[..., Result]:
    """The ``solve(case, **options)`` function of a method."""
    if method not in SOLVERS:
        raise CaseError(f"unknown method {method!r}; methods: {', '.join(SOLVERS)}")
    module, attr = SOLVERS[method]
    try:
        mod = importlib.import_module(module)
        return getattr(mod, attr)
    except (ImportError, AttributeError) as e:
        raise MethodUnavailable(f"method {method!r} is not available ({e})") from None


def unsupported(case: Case, method: str) -> str | None:
    """Why ``method`` cannot run ``case`` (from the solver package's ``unsupported`` hook)."""
    if method not in SOLVERS or method == "analytic":
        return None
    try:
        hook = getattr(importlib.import_module(SOLVERS[method][0]), "unsupported", None)
    except ImportError:
        return None
    return hook(case) if hook is not None else None


def supported_methods(case: Case) -> list[str]:
    """The case's methods that can run it (a method refusing the case's interface law is left out)."""
    return [m for m in case.methods() if unsupported(case, m) is None]


def resolve_methods(case: Case, methods) -> list[str]:
    """Expand ``"all"`` to the methods supporting the case; check explicit names."""
    if isinstance(methods, str):
        methods = [m.strip() for m in methods.split(",") if m.strip()]
    methods = list(methods)
    if methods == ["all"]:
        return supported_methods(case)
    for m in methods:
        if m not in SOLVERS:
            raise CaseError(f"unknown method {m!r}; methods: {', '.join(SOLVERS)}, all")
        if m not in case.methods():
            raise CaseError(f"method {m!r} does not support case {case.name!r} "
                            f"(supported: {', '.join(case.methods())})")
        reason = unsupported(case, m)
        if reason:
            raise CaseError(f"method {m!r} cannot run case {case.name!r}: {reason}")
    return methods


def run(case: Case, method: str, **options) -> Result:
    """Run one method on a case, recording the wall time in ``timings['total']``."""
    solve = solver(method)
    t0 = time.perf_counter()
    result = solve(case, **options)
    result.timings.setdefault("total", time.perf_counter() - t0)
    return result
