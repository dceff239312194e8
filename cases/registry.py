"""Registry of the named cases: ``build(name, **overrides)`` and ``names()``."""
from __future__ import annotations

import inspect
from typing import Callable

from interfaces import Case, CaseError

from . import curved, library

CASES: dict[str, Callable[..., Case]] = {
    "dls": library.dls,
    "two_layer": library.two_layer,
    "dcb": library.dcb,
    "wave": library.wave,
    "particulate": library.particulate,
    "bimaterial_square": library.bimaterial_square,
    "cuboid": library.cuboid,
    "composite_spheres": curved.composite_spheres,
    "composite_cylinders": curved.composite_cylinders,
    "inclusion": curved.inclusion,
}


def names() -> list[str]:
    return list(CASES)


def parameters(name: str) -> dict:
    """The keyword overrides a case accepts, with their defaults."""
    fn = _builder(name)
    return {k: p.default for k, p in inspect.signature(fn).parameters.items()}


def _builder(name: str) -> Callable[..., Case]:
    if name not in CASES:
        raise CaseError(f"unknown case {name!r}; known cases: {', '.join(CASES)}")
    return CASES[name]


def build(name: str, **overrides) -> Case:
    """Build the named case with the papers' defaults and keyword overrides."""
    fn = _builder(name)
    allowed = parameters(name)
    for k in overrides:
        if k not in allowed:
            raise CaseError(f"{name} has no parameter {k!r} (parameters: {', '.join(allowed)})")
    try:
        return fn(**overrides)
    except CaseError as e:
        raise CaseError(f"{name}: {e}") from None
    except TypeError as e:  # wrong type of an override value
        raise CaseError(f"{name}: {e}") from None


def summary(name: str) -> str:
    """First line of the builder's docstring."""
    return (inspect.getdoc(_builder(name)) or "").splitlines()[0]
