"""Homogeneous compression of a compressible neo-Hookean block (004 Eq 18), in closed form.

A block stretched (compressed: lam < 1) along y has the homogeneous deformation gradient
F = diag(a, lam, c). The lateral stretches follow from the lateral conditions:

* ``"plane_strain_free"``: plane strain c = 1, the x sides traction-free, a from
  sigma_xx = 0;
* ``"uniaxial_stress"`` (3D, or axisymmetric about y): x and z free, a = c from
  sigma_xx = sigma_zz = 0;
* ``"uniaxial_strain"``: a = c = 1 (lateral sides held), explicit.

With B = F F^T = diag(a^2, lam^2, c^2), I1 = a^2 + lam^2 + c^2 and J = a lam c, the
Cauchy stresses are sigma_ii = G J^(-5/3) (B_ii - I1 / 3) + U'(J)
(``NeoHookean.cauchy_stress``); a free lateral direction gives the scalar equation
G J^(-5/3) (a^2 - I1 / 3) + U'(J) = 0 for a, solved by bracketing (its left side grows
monotonically with a: in compression a > 1). The axial load per reference area is the
nominal (first Piola-Kirchhoff) stress P_yy = J sigma_yy / lam, and the energy per
reference volume W(F) of Eq 18.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from interfaces.errors import CaseError
from interfaces.materials import NeoHookean

LATERAL = ("plane_strain_free", "uniaxial_stress", "uniaxial_strain")


@dataclass(frozen=True)
class HomogeneousState:
    """The compression state at axial stretch ``stretch`` (arrays over the stretches)."""

    stretch: np.ndarray          # lam = current / initial height
    lateral_stretch: np.ndarray  # a (x; also z for uniaxial stress)
    sigma_axial: np.ndarray      # Cauchy sigma_yy (MPa, compression negative)
    sigma_lateral: np.ndarray    # Cauchy sigma_xx (0 where free)
    sigma_out_of_plane: np.ndarray  # Cauchy sigma_zz
    nominal_axial: np.ndarray    # P_yy = J sigma_yy / lam (force per reference area)
    energy_density: np.ndarray   # W (N mm per mm^3 of reference volume)


def _F(a: float, lam: float, c: float) -> np.ndarray:
    return np.diag([a, lam, c])


def _lateral_stretch(mat: NeoHookean, lam: float, lateral: str) -> float:
    if lateral == "uniaxial_strain":
        return 1.0

    def residual(a: float) -> float:
        c = 1.0 if lateral == "plane_strain_free" else a
        return float(mat.cauchy_stress(_F(a, lam, c))[0, 0])

    lo, hi = 1e-3, 1.0
    while residual(hi) < 0.0:
        hi *= 2.0
        if hi > 1e6:
            raise CaseError(f"no traction-free lateral stretch found at stretch {lam:g}")
    while residual(lo) > 0.0:
        lo *= 0.5
    return brentq(residual, lo, hi, xtol=1e-15, rtol=1e-15)


def neo_hookean_compression(mat: NeoHookean, stretch, lateral: str = "plane_strain_free") -> HomogeneousState:
    """Closed-form homogeneous state of ``mat`` at the axial stretches ``stretch`` (> 0)."""
    if lateral not in LATERAL:
        raise CaseError(f"lateral must be one of {', '.join(LATERAL)}, got {lateral!r}")
    lams = np.atleast_1d(np.asarray(stretch, dtype=float))
    if not np.all(lams > 0.0) or not np.all(np.isfinite(lams)):
        raise CaseError(f"stretch must be > 0 and finite, got {stretch!r}")
    out = {k: np.empty(lams.shape) for k in ("a", "sy", "sx", "sz", "P", "W")}
    for k, lam in enumerate(lams):
        a = _lateral_stretch(mat, float(lam), lateral)
        c = a if lateral == "uniaxial_stress" else 1.0
        F = _F(a, float(lam), c)
        s = mat.cauchy_stress(F)
        J = a * lam * c
        out["a"][k], out["sy"][k], out["sx"][k], out["sz"][k] = a, s[1, 1], s[0, 0], s[2, 2]
        out["P"][k] = J * s[1, 1] / lam
        out["W"][k] = float(mat.energy_density(F))
    return HomogeneousState(lams, out["a"], out["sy"], out["sx"], out["sz"], out["P"], out["W"])


def nominal_stress_for_stretch(mat: NeoHookean, stretch: float,
                               lateral: str = "plane_strain_free") -> float:
    """The dead axial load per reference area P_yy that holds the block at ``stretch``."""
    return float(neo_hookean_compression(mat, stretch, lateral).nominal_axial[0])


def stretch_for_nominal_stress(mat: NeoHookean, nominal: float,
                               lateral: str = "plane_strain_free") -> float:
    """The axial stretch at which the dead axial load per reference area ``nominal``
    (MPa, compression negative) holds the block (the inverse of
    :func:`nominal_stress_for_stretch`, monotonic in the stretch)."""
    if nominal == 0.0:
        return 1.0
    lo, hi = (1e-3, 1.0) if nominal < 0.0 else (1.0, 2.0)
    while nominal > 0.0 and nominal_stress_for_stretch(mat, hi, lateral) < nominal:
        hi *= 2.0
        if hi > 1e6:
            raise CaseError(f"no stretch carries the nominal stress {nominal:g} MPa")
    return brentq(lambda lam: nominal_stress_for_stretch(mat, lam, lateral) - nominal, lo, hi,
                  xtol=1e-15, rtol=1e-14)
