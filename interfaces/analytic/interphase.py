"""Interphase -> interface parameters, 002 Sec 3.5 Eq 52.

A linear-elastic interphase of thickness t_i replaced by a zero-thickness interface
such that a series (tension or shear) model deforms the same:

    1/Dn = t_i [1/E_i - (1/E1 + 1/E2)/2],     1/Dt = t_i [1/G_i - (1/G1 + 1/G2)/2].

An interphase stiffer than the average substrate gives a negative D, allowed down
to the rigid-interphase limit E_i, G_i -> inf (pass ``math.inf``), where
1/Dn -> -(t_i/2)(1/E1 + 1/E2). Non-positive interphase moduli are beyond that limit
and rejected. 1/D = 0 (t_i = 0, or an interphase matching the substrates) gives inf.
"""
from __future__ import annotations

import math

from interfaces.analytic._checks import nonnegative, positive

__all__ = ["interphase_to_interface"]


def _inverse_parameter(t_i: float, M_i: float, M1: float, M2: float) -> float:
    return t_i * (1.0 / M_i - 0.5 * (1.0 / M1 + 1.0 / M2))


def interphase_to_interface(t_i: float, E_i: float, G_i: float, E1: float, E2: float,
                            G1: float, G2: float) -> tuple[float, float]:
    """(Dn, Dt) in MPa/mm equivalent to an interphase (002 Eq 52).

    ``t_i`` interphase thickness (mm, >= 0); ``E_i, G_i`` its tensile and shear
    moduli (MPa, > 0, ``math.inf`` for the rigid limit); ``E1, E2, G1, G2`` the
    substrates' moduli (MPa, > 0, finite). Results may be negative (stiff interphase).
    """
    t_i = nonnegative("t_i", t_i)
    E_i = positive("E_i", E_i, allow_inf=True)
    G_i = positive("G_i", G_i, allow_inf=True)
    E1, E2 = positive("E1", E1), positive("E2", E2)
    G1, G2 = positive("G1", G1), positive("G2", G2)
    inv_n = _inverse_parameter(t_i, E_i, E1, E2)
    inv_t = _inverse_parameter(t_i, G_i, G1, G2)
    return (math.inf if inv_n == 0.0 else 1.0 / inv_n,
            math.inf if inv_t == 0.0 else 1.0 / inv_t)
