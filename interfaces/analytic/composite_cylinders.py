"""Composite-cylinders transverse (plane-strain) bulk modulus with a spring interface.

The plane-strain counterpart of ``composite_spheres`` (Hashin and Rosen's composite
cylinder assemblage with the interface of 000 Eq 4, the form used for fibre composites
with imperfect bonding). Derivation (docs/analytic.md repeats it):

A fibre of radius a (plane-strain bulk modulus k_f = lambda_f + G_f = K_f + G_f/3) in a
matrix cylinder of outer radius b (k_m, G_m), phi = (a/b)^2, plane strain, under the
uniform radial displacement u(b) = eps0 b. Lame solutions: u = A r in the fibre
(sigma_rr = 2 k_f A) and u = B r + C/r in the matrix (sigma_rr = 2 k_m B - 2 G_m C/r^2).
Conditions:

    sigma_rr continuous at r = a:   2 k_f A = 2 k_m B - 2 G_m C/a^2
    spring interface:               2 k_f A = Dn (B a + C/a - A a)
    outer boundary:                 B + C/b^2 = eps0

The spring adds [u] = 2 k_f A/Dn to the fibre's surface displacement, so the fibre and the
interface act as one softer fibre, 2 k_f A = 2 k_e u_m(a)/a, with the series combination
1/k_e = 1/k_f + 2/(a Dn). Then c = C/a^2 = B (k_m - k_e)/(k_e + G_m), B = eps0/(1 + phi
(k_m - k_e)/(k_e + G_m)) and the transverse bulk modulus k* = sigma_rr(b)/(2 eps0):

    k* = [k_m (k_e + G_m) - G_m phi (k_m - k_e)] / [k_e + G_m + phi (k_m - k_e)]
       = k_m + phi (k_e - k_m) / (1 + (1 - phi)(k_e - k_m)/(k_m + G_m)),

Hashin-Rosen's formula with k_f replaced by k_e. Dn = inf gives k_e = k_f; Dn = 0 gives
the empty-hole value k_m G_m (1 - phi)/(G_m + phi k_m). The fibre shear modulus enters
only through k_f; Dt does not enter (axial symmetry in the plane). The strain energy per
unit length is U = 2 k* eps0^2 pi b^2 (so k* = U/(2 V eps0^2), V the cross-section area
times the length). A negative Dn (stiff interphase, 002 Eq 52) is accepted down to the
rigid limit 1/k_e = 0.

Units: MPa, mm, MPa/mm; energies per mm of length in N mm / mm.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from interfaces.analytic._checks import points, positive
from interfaces.analytic.composite_spheres import (check_coated_inclusion, modulus_from_inverse,
                                                    series_inverse_modulus)
from interfaces.errors import check_number

__all__ = ["CompositeCylinders", "composite_cylinders_bulk_modulus", "plane_strain_bulk_modulus"]


def plane_strain_bulk_modulus(K: float, G: float) -> float:
    """Plane-strain (transverse) bulk modulus k = lambda + G = K + G/3 (MPa) of an isotropic
    material: sigma_rr + sigma_tt = 2 k (eps_rr + eps_tt) with eps_zz = 0."""
    return positive("K", K) + positive("G", G) / 3.0


@dataclass(frozen=True)
class CompositeCylinders:
    """One composite cylinder: fibre (plane-strain bulk modulus k_f, radius a) in a matrix
    cylinder (k_m, G_m), phi = (a/b)^2, spring interface sigma_rr = Dn [u_r] (MPa/mm,
    inf perfect, 0 debonded). Plane strain, transverse (in-plane) dilatation."""

    k_f: float
    k_m: float
    G_m: float
    phi: float
    a: float
    Dn: float = math.inf

    def __post_init__(self) -> None:
        check_coated_inclusion(self, ("k_f", "k_m", "G_m"), "k_f", 2.0)

    @property
    def b(self) -> float:
        """Outer radius a / sqrt(phi) (mm); inf for phi = 0."""
        return math.inf if self.phi == 0.0 else self.a / math.sqrt(self.phi)

    @property
    def inverse_effective_fibre_modulus(self) -> float:
        """1/k_e = 1/k_f + 2/(a Dn) (1/MPa): fibre and interface in series."""
        return series_inverse_modulus(self.k_f, 2.0, self.a, self.Dn)

    @property
    def effective_fibre_modulus(self) -> float:
        """k_e (MPa); 0 for a debonded fibre, inf at the rigid-interphase limit."""
        return modulus_from_inverse(self.inverse_effective_fibre_modulus)

    @property
    def bulk_modulus(self) -> float:
        """Transverse bulk modulus k* (MPa) of the composite cylinder assemblage (module docstring)."""
        ke, km, Gm, phi = self.effective_fibre_modulus, self.k_m, self.G_m, self.phi
        if math.isinf(ke):  # rigid fibre
            return (km + Gm * phi) / (1.0 - phi)
        return (km * (ke + Gm) - Gm * phi * (km - ke)) / (ke + Gm + phi * (km - ke))

    def coefficients(self, eps0: float = 1.0) -> tuple[float, float, float]:
        """(A, B, C) of u = A r (fibre), u = B r + C/r (matrix) for u(b) = eps0 b."""
        eps0 = check_number("eps0", eps0)
        km, Gm, phi, a = self.k_m, self.G_m, self.phi, self.a
        s = self.inverse_effective_fibre_modulus
        # ratio = c/B = (k_m - k_e)/(k_e + G_m), written in 1/k_e (finite for a debonded fibre)
        ratio = km / Gm if math.isinf(s) else (km * s - 1.0) / (1.0 + Gm * s)
        B = eps0 / (1.0 + phi * ratio)
        c = B * ratio
        if s == 0.0:   # rigid limit: A from traction continuity
            A = (km * B - Gm * c) / self.k_f
        else:          # 2 k_f A = 2 k_e (B + c)
            A = 0.0 if math.isinf(s) else (B + c) / (self.k_f * s)
        return A, B, c * a * a

    def radial_displacement(self, r, eps0: float = 1.0) -> np.ndarray:
        """u_r(r) (mm) for 0 <= r <= b; at r = a the fibre-side value."""
        rr = np.atleast_1d(points("r", r, 0.0, self.b)).astype(float)
        A, B, C = self.coefficients(eps0)
        out = A * rr
        m = rr > self.a
        out[m] = B * rr[m] + C / rr[m]
        return out

    def radial_stress(self, r, eps0: float = 1.0) -> np.ndarray:
        """sigma_rr(r) (MPa) for 0 <= r <= b (continuous across r = a)."""
        rr = np.atleast_1d(points("r", r, 0.0, self.b)).astype(float)
        A, B, C = self.coefficients(eps0)
        out = np.full_like(rr, 2.0 * self.k_f * A)
        m = rr > self.a
        out[m] = 2.0 * self.k_m * B - 2.0 * self.G_m * C / rr[m] ** 2
        return out

    def interface_jump(self, eps0: float = 1.0) -> float:
        """[u_r] = u_matrix(a) - u_fibre(a) (mm)."""
        A, B, C = self.coefficients(eps0)
        return B * self.a + C / self.a - A * self.a


def composite_cylinders_bulk_modulus(k_f: float, k_m: float, G_m: float, phi: float,
                                     a: float = 1.0, Dn: float = math.inf) -> float:
    """Transverse (plane-strain) bulk modulus of composite cylinders with a spring interface (MPa)."""
    return CompositeCylinders(k_f, k_m, G_m, phi, a, Dn).bulk_modulus
