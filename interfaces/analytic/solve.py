"""``solve(case) -> Result`` for the closed-form models (method ``"analytic"``)."""
from __future__ import annotations

import math
import time

from interfaces.analytic._checks import CaseError
from interfaces.analytic.registry import MODELS, PROFILES
from interfaces.result import Result

__all__ = ["solve"]

#: analytic parameter -> the law attributes that hold it (a bilinear law's Dn is its
#: tension branch, the one the models describe)
_LAW_FIELDS = {"Dn": ("Dn", "Dn_tension"), "Dt": ("Dt",)}


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
    if not isinstance(name, str) or name not in MODELS:
        raise CaseError(f"analytic.model must be one of {', '.join(sorted(MODELS))}, got {name!r}")
    _check_interface_parameters(case, params)
    params.update(overrides)
    t0 = time.perf_counter()
    quantities = MODELS[name](**params)
    t1 = time.perf_counter()
    curves = PROFILES[name](**params) if profiles else {}
    t2 = time.perf_counter()
    return Result(method="analytic", case_name=case.name, quantities=quantities, profiles=curves,
                  timings={"quantities": t1 - t0, "profiles": t2 - t1, "total": t2 - t0},
                  diagnostics={"model": name, "parameters": params})


def _check_interface_parameters(case, params: dict) -> None:
    """The ``[analytic]`` table repeats the interface parameters of the case's laws; an
    edited case whose table still holds old ones would be compared with a model of
    another specimen. Refuse the mismatch, naming both fields."""
    for key, attrs in _LAW_FIELDS.items():
        if key not in params:
            continue
        for i, pair in enumerate(getattr(case, "interfaces", [])):
            law_value = next((getattr(pair.law, a) for a in attrs if hasattr(pair.law, a)), None)
            if law_value is None or pair.zones:
                continue
            try:
                given = float(params[key])
            except (TypeError, ValueError):
                return              # the model's own check names the bad value
            same = given == law_value or (math.isfinite(given) and math.isfinite(law_value)
                                          and abs(given - law_value) <= 1e-12 * max(abs(law_value), 1e-300))
            if not same:
                raise CaseError(f"analytic.{key} = {given:g} but interfaces[{i}].law has {key} = "
                                f"{law_value:g}: update the [analytic] table to the case's interface "
                                "(or remove it)")
