"""Specimen stiffness from a FEM solution by the two methods of 002 Sec 3.1."""
from __future__ import annotations

import math

import numpy as np

from interfaces.errors import CaseError

from interfaces.bulk import bulk_modulus  # noqa: F401  (re-exported: the FEM measure)

from .assembly import facet_load


def side_average(disc, sides, u: np.ndarray, direction: np.ndarray) -> float:
    """<u . d> over sides [[body, side], ...]: the traction-consistent (integral) average,
    i.e. the work of a unit uniform traction along d divided by the loaded area, so that
    002 Eq 44 U = 1/2 P (<u_load> - <u_support>) holds exactly for uniform tractions."""
    w = sum(facet_load(disc.mesh, disc.element, disc.side_facets(b, s), direction, disc.thickness,
                       disc.axisymmetric, disc.intorder) for b, s in sides)
    return float(w @ u) / float(w @ direction[np.arange(len(w)) % 2])


def stiffness(disc, meas: dict, f_int: np.ndarray, u: np.ndarray, U_total: float) -> dict:
    """k = P / (<u_load> - <u_support>) (002 Eq 43) and k = P^2 / (2 U) (002 Eq 45).

    P is the force on the load sides along the measurement direction: the internal force
    (bulk + interface) summed over their DOFs, which equals the applied traction resultant
    or the reaction of a prescribed displacement. Whole-ring values when axisymmetric."""
    case = disc.case
    unit = case.stiffness_direction()
    load = meas.get("load", [])
    if not load:
        raise CaseError("measurements.stiffness.load must list at least one [body, side]")
    load_dofs = np.unique(np.concatenate([disc.side_dofs(b, s) for b, s in load]))
    P = disc.ring * float(f_int[load_dofs] @ unit[load_dofs % 2])
    u_load = side_average(disc, load, u, unit)
    u_sup = side_average(disc, meas["support"], u, unit) if meas.get("support") else 0.0
    delta = u_load - u_sup
    return {"load": P, "load_displacement": u_load, "support_displacement": u_sup,
            "stiffness": P / delta if delta != 0 else math.nan,
            "stiffness_energy": P * P / (2.0 * U_total) if U_total > 0 else math.nan}


__all__ = ["side_average", "stiffness", "bulk_modulus"]
