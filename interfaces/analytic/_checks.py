"""Input checks shared by the closed-form models (one place, one message style).

Every public function of :mod:`interfaces.analytic` validates its arguments here
and raises :class:`interfaces.errors.CaseError` naming the argument and the
allowed range, so a bad value never reaches numpy as a silent NaN or a deep
traceback.
"""
from __future__ import annotations

import math

import numpy as np

from interfaces.errors import CaseError, check_number

__all__ = ["CaseError", "positive", "nonnegative", "interface_stiffness", "fraction", "points"]


#: largest finite magnitude a length, modulus or load may have (mm, MPa, N): beyond it
#: the closed forms overflow double precision (a cube of 1e103 is already inf)
MAX_MAGNITUDE = 1e30


def positive(name: str, value, *, allow_inf: bool = False) -> float:
    """``value`` as a float in (0, 1e30] (or inf when ``allow_inf``)."""
    v = check_number(name, value, low=0.0, low_open=True, allow_inf=allow_inf)
    return v if math.isinf(v) else check_number(name, v, low=0.0, high=MAX_MAGNITUDE, low_open=True)


def nonnegative(name: str, value, *, allow_inf: bool = False) -> float:
    """``value`` as a float in [0, 1e30] (or inf when ``allow_inf``)."""
    v = check_number(name, value, low=0.0, allow_inf=allow_inf)
    return v if math.isinf(v) else check_number(name, v, low=0.0, high=MAX_MAGNITUDE)


def interface_stiffness(name: str, value, *, allow_negative: bool = False) -> float:
    """An interface parameter Dn or Dt in MPa/mm: ``math.inf`` is perfect, 0 debonded.

    Negative values (a stiff interphase, 002 Eq 52) only when ``allow_negative``;
    the caller then checks the model-specific lower limit.
    """
    if allow_negative:
        v = check_number(name, value, allow_inf=True)
        if v == 0.0:
            return 0.0
        return v
    return check_number(name, value, low=0.0, allow_inf=True)


def fraction(name: str, value, *, low_open: bool = False, high_open: bool = False) -> float:
    """A number in [0, 1] (ends optionally open)."""
    return check_number(name, value, low=0.0, high=1.0, low_open=low_open, high_open=high_open)


def points(name: str, value, low: float, high: float) -> np.ndarray:
    """Coordinates (scalar or array) as a float array, all finite and in [low, high]."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise CaseError(f"{name} must be a number or an array of numbers, got {value!r}") from None
    if not np.all(np.isfinite(arr)):
        raise CaseError(f"{name} must be finite, got non-finite entries")
    tol = 1e-12 * max(abs(low) if math.isfinite(low) else 0.0,
                      abs(high) if math.isfinite(high) else 0.0, 1.0)
    if arr.size and (arr.min() < low - tol or arr.max() > high + tol):
        raise CaseError(f"{name} must lie in [{low:g}, {high:g}], got values in "
                        f"[{arr.min():g}, {arr.max():g}]")
    return np.asarray(np.clip(arr, low, high))
