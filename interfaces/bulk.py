"""Bulk modulus of a unit cell under a uniform dilatation of its boundary (000 Eq 34-36).

Shared by the methods that report ``bulk_modulus`` for a case's
``measurements["bulk_modulus"] = {"strain": eps0, "volume": V}``: the energy form
(Eq 34-35, stored = strain + interfacial energy) and the pressure form (Eq 36, the
volume-averaged mean stress).
"""
from __future__ import annotations

import numpy as np

from .errors import CaseError


def _strain_volume(meas: dict) -> tuple[float, float]:
    try:
        eps0, volume = float(meas["strain"]), float(meas["volume"])
    except (KeyError, TypeError, ValueError):
        raise CaseError(f"measurements.bulk_modulus needs strain and volume (numbers), got {meas!r}") from None
    if not eps0 != 0 or not volume > 0:
        raise CaseError(f"measurements.bulk_modulus: strain must be non-zero and volume > 0, got {meas!r}")
    return eps0, volume


def _dimension(analysis: str) -> int:
    return 2 if analysis in ("plane_strain", "plane_stress") else 3


def bulk_modulus(meas: dict, U_total: float, analysis: str) -> float:
    """Bulk modulus from the stored energy of a uniform dilatation u = eps0 x on the outer
    boundary (000 Eq 34-35): U = (d^2/2) K eps0^2 V, i.e. K = 2 U / (9 V eps0^2) for an
    axisymmetric (or 3D) body, d = 3, and the transverse (in-plane) k = U / (2 V eps0^2) of a
    plane-strain section, d = 2 (composite cylinders). ``U_total`` = bulk + interface energy
    of the volume ``V`` (whole ring when axisymmetric)."""
    eps0, volume = _strain_volume(meas)
    d = _dimension(analysis)
    return 2.0 * U_total / (d * d * volume * eps0 * eps0)


def bulk_modulus_from_pressure(meas: dict, volumes: np.ndarray, stress: np.ndarray,
                               analysis: str) -> float:
    """Bulk modulus K = P / (d eps0) (000 Eq 36) from the average pressure P = <sigma_ii> / d
    over the cell (``volumes`` of the material points or elements, their ``stress`` in
    Voigt order, normal components first); the cell volume is the measurement's."""
    eps0, volume = _strain_volume(meas)
    d = _dimension(analysis)
    mean = float(np.asarray(volumes) @ np.asarray(stress)[:, :d].sum(axis=1)) / (d * volume)
    return mean / (d * eps0)


__all__ = ["bulk_modulus", "bulk_modulus_from_pressure"]
