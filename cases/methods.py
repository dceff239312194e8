"""Dispatch to the solvers by method name; a missing solver answers with a clear message."""
from __future__ import annotations

import importlib
import time
import traceback
from pathlib import Path
from typing import Callable

from interfaces import Case, CaseError, Result, SolverError

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


def unsupported_reason(case: Case, method: str) -> str | None:
    """None when ``method`` can run ``case``; otherwise a one-line reason. A method
    supports a case that has its discretization entry (an analytic model for
    ``analytic``) and that its package's optional ``supports(case)`` accepts."""
    if method not in case.methods():
        return (f"method {method!r} does not support case {case.name!r} "
                f"(supported: {', '.join(supported_methods(case))})")
    return _package_refusal(case, method)


def _package_refusal(case: Case, method: str) -> str | None:
    """The method package's own word on the case: None, or why not (also when the
    package cannot be imported)."""
    try:
        mod = importlib.import_module(SOLVERS[method][0])
    except ImportError as e:
        return f"method {method!r} is not available ({e})"
    check = getattr(mod, "supports", None)
    reason = check(case) if callable(check) else None
    return None if reason is None else f"{method}: {reason}"


def supported_methods(case: Case) -> list[str]:
    """The methods that can run ``case`` (what ``imperfect list`` and ``all`` mean)."""
    return [m for m in case.methods() if _package_refusal(case, m) is None]


def resolve_methods(case: Case, methods) -> list[str]:
    """Expand ``"all"`` to the methods that can run the case; check explicit names (a
    method that cannot run the case is a CaseError saying why)."""
    if isinstance(methods, str):
        methods = [m.strip() for m in methods.split(",") if m.strip()]
    methods = list(methods)
    if methods == ["all"]:
        return supported_methods(case)
    for m in methods:
        if m not in SOLVERS:
            raise CaseError(f"unknown method {m!r}; methods: {', '.join(SOLVERS)}, all")
        reason = unsupported_reason(case, m)
        if reason is not None:
            raise CaseError(reason)
    return methods


def run(case: Case, method: str, **options) -> Result:
    """Run one method on a case, recording the wall time in ``timings['total']``."""
    solve = solver(method)
    t0 = time.perf_counter()
    result = solve(case, **options)
    result.timings.setdefault("total", time.perf_counter() - t0)
    return result


#: what a run that exhausts the memory is told (one method of a comparison, or the command)
OUT_OF_MEMORY = "out of memory: use a coarser discretization (element_size, cell, h)"


def failure_text(error: Exception) -> str:
    """What a method's failure tells the user: the message of a CaseError / SolverError
    (bad input, unsupported, diverged), else the exception's type, message and the line
    that raised it (a defect, or a library giving up; the other methods' results and
    sweep points are kept either way)."""
    if isinstance(error, (CaseError, SolverError)):
        return str(error)
    if isinstance(error, MemoryError):
        return OUT_OF_MEMORY
    where = traceback.extract_tb(error.__traceback__)[-1] if error.__traceback__ else None
    at = f" (at {Path(where.filename).name}:{where.lineno})" if where else ""
    return f"{type(error).__name__}: {error}{at}"
