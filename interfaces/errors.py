"""Errors raised for bad input and for failed solves.

Both carry a one-line message that names the offending field (``materials.wood.E_A``)
or says what to change (time step, damping, Dn), so users never see a traceback from
deep inside numpy instead.
"""
from __future__ import annotations

import math
from numbers import Real

import numpy as np


class CaseError(ValueError):
    """Invalid case description or solver option; the message names the field."""


class SolverError(RuntimeError):
    """A solve failed (diverged, did not converge); the message says what to change."""


def check_number(field: str, value, *, low: float | None = None, high: float | None = None,
                 low_open: bool = False, high_open: bool = False,
                 allow_inf: bool = False) -> float:
    """Return ``value`` as a float, or raise :class:`CaseError` naming ``field``.

    ``low``/``high`` are inclusive bounds unless ``low_open``/``high_open``.
    NaN is always rejected; +inf only with ``allow_inf``.
    """
    if isinstance(value, bool) or not isinstance(value, Real):
        try:
            if isinstance(value, str) and value.strip().lower() in ("inf", "+inf", "infinity"):
                value = math.inf
            else:
                raise TypeError
        except TypeError:
            raise CaseError(f"{field} must be a number, got {value!r}") from None
    v = float(value)
    if math.isnan(v):
        raise CaseError(f"{field} must be a number, got NaN")
    if math.isinf(v) and not (allow_inf and v > 0):
        raise CaseError(f"{field} must be finite, got {v}")
    rng = _range_text(low, high, low_open, high_open)
    if low is not None and (v < low or (low_open and v == low)):
        raise CaseError(f"{field} must be {rng}, got {v:g}")
    if high is not None and (v > high or (high_open and v == high)):
        raise CaseError(f"{field} must be {rng}, got {v:g}")
    return v


def check_integer(field: str, value, *, low: int | None = None, high: int | None = None) -> int:
    """Return ``value`` as an int, or raise :class:`CaseError` naming ``field`` and the
    allowed range; a float with a fractional part (``2.5``) or a bool is refused, never
    truncated."""
    what = "an integer" if low is None and high is None else \
        f"an integer {_range_text(low, high, False, False)}"
    if isinstance(value, bool) or not isinstance(value, Real) or not math.isfinite(value) \
            or float(value) != int(value):
        raise CaseError(f"{field} must be {what}, got {value!r}")
    v = int(value)
    if (low is not None and v < low) or (high is not None and v > high):
        raise CaseError(f"{field} must be {what}, got {v}")
    return v


def check_vector(field: str, value, size: int, *, broadcast: bool = False) -> np.ndarray:
    """Return ``value`` as ``size`` finite floats, or raise :class:`CaseError` naming
    ``field``; with ``broadcast`` one number stands for all of them. Text and booleans
    are refused (``np.asarray(True, float)`` would be 1.0)."""
    def refuse():
        return CaseError(f"{field} must be {'one number or ' if broadcast else ''}{size} finite "
                         f"numbers, got {value!r}")

    items = value if isinstance(value, (list, tuple, np.ndarray)) else [value]
    if any(isinstance(v, (str, bytes, bool, np.bool_)) for v in np.ravel(np.asarray(items, object))):
        raise refuse()
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise refuse() from None
    if arr.ndim == 0 and broadcast:
        arr = np.full(size, float(arr))
    if arr.shape != (size,) or not np.all(np.isfinite(arr)):
        raise refuse()
    return arr.copy()


def check_flag(field: str, value) -> bool:
    """Return ``value`` as a bool, or raise :class:`CaseError` naming ``field``: only
    true and false are accepted (a string such as ``"false"`` is refused, not taken as
    truthy)."""
    if not isinstance(value, (bool, np.bool_)):
        raise CaseError(f"{field} must be true or false, got {value!r}")
    return bool(value)


def _range_text(low, high, low_open, high_open) -> str:
    if low is not None and high is not None:
        return f"in {'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}"
    if low is not None:
        return f"{'>' if low_open else '>='} {low:g}"
    if high is not None:
        return f"{'<' if high_open else '<='} {high:g}"
    return "a number"


def build_tagged(registry: dict, d, where: str, convert_lists: bool = False, make=None):
    """Build an object from a TOML table ``{"type": kind, field: value, ...}``.

    ``registry`` maps ``type`` names to dataclasses. Errors are one-line
    :class:`CaseError` messages naming ``where.field``: not a table, unknown type,
    unknown or missing fields, invalid values. ``make(cls, kwargs)`` may replace the
    plain ``cls(**kwargs)`` call.
    """
    from dataclasses import MISSING, fields

    if not isinstance(d, dict):
        raise CaseError(f"{where} must be a table, got {d!r}")
    kind = d.get("type")
    if not isinstance(kind, str) or kind not in registry:
        raise CaseError(f"{where}.type must be one of {', '.join(registry)}, got {kind!r}")
    cls = registry[kind]
    kwargs = {k: (tuple(v) if convert_lists and isinstance(v, list) else v) for k, v in d.items() if k != "type"}
    names = [f.name for f in fields(cls)]
    extra = set(kwargs) - set(names)
    if extra:
        raise CaseError(f"{where}.{sorted(extra)[0]} is not a field of {kind} (fields: {', '.join(names) or 'none'})")
    missing = [f.name for f in fields(cls) if f.name not in kwargs and f.default is MISSING and f.default_factory is MISSING]
    if missing:
        raise CaseError(f"{where}.{missing[0]} is missing ({kind} needs {', '.join(names)})")
    try:
        return make(cls, kwargs) if make is not None else cls(**kwargs)
    except CaseError as e:
        raise CaseError(f"{where}.{e}") from None
    except TypeError as e:
        raise CaseError(f"{where}: {e}") from None
