"""``solve(case) -> Result`` for the closed-form models (method ``"analytic"``)."""
from __future__ import annotations

import time

from interfaces.analytic._checks import CaseError
from interfaces.analytic.registry import MODELS, PROFILES
from interfaces.result import Result

__all__ = ["solve"]


def solve(case, *, profiles: bool = True, **overrides) -> Result:
    """Evaluate the model named in ``case.analytic`` = {"model": name, **params}.

    ``overrides`` replace entries of ``case.analytic`` (e.g. ``Dt=10.0`` in a sweep);
    ``profiles=False`` skips the profile curves. Quantities and profiles are those of
    :mod:`interfaces.analytic.registry`; the Result has no fields (no discretization).
    """
    spec = getattr(case, "analytic", None)
    if not spec:
        raise CaseError(f"case {getattr(case, 'name', '?')!r} has no analytic model "
                        f"(case.analytic is empty); available models: {', '.join(sorted(MODELS))}")
    params = {k: v for k, v in dict(spec).items() if k != "model"}
    name = spec.get("model")
    if name not in MODELS:
        raise CaseError(f"analytic.model must be one of {', '.join(sorted(MODELS))}, got {name!r}")
    params.update(overrides)
    t0 = time.perf_counter()
    quantities = MODELS[name](**params)
    t1 = time.perf_counter()
    curves = PROFILES[name](**params) if profiles else {}
    t2 = time.perf_counter()
    return Result(method="analytic", case_name=case.name, quantities=quantities, profiles=curves,
                  timings={"quantities": t1 - t0, "profiles": t2 - t1, "total": t2 - t0},
                  diagnostics={"model": name, "parameters": params})
